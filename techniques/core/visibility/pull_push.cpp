// Pull-push reconstruction (guennebaud2007 sec. 5.2 after Gortler et al. 1996): the GPU passes
// (shaders/common/pull_push_pull.comp, pull_push_push.comp) and their CPU mirror, both on
// shaders/shared/pull_push.glsl. Level convention: pull_push.h.
#include "visibility/pull_push.h"

#include "error.h"
#include "shared/shared.h"

namespace shadowlab {

using namespace shared;

namespace {

GLuint groups(int n) { return GLuint((n + 7) / 8); }

std::string sizeText(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

// The pyramid must follow pull_push.h's convention: mip m is pull-push level m + 1, down to 1x1.
void checkPyramid(const char* what, const Texture& pyramid, int width, int height) {
    const int w1 = pullPushLevelSize(1, width), h1 = pullPushLevelSize(1, height);
    if (pyramid.format() != GL_RG32F || pyramid.width() != w1 || pyramid.height() != h1 ||
        pyramid.levels() != fullMipLevels(w1, h1))
        throw InternalError(std::string("PullPush::run: the ") + what + " pyramid is " + pyramid.formatName() + " " +
                            sizeText(pyramid.width(), pyramid.height()) + " with " + std::to_string(pyramid.levels()) +
                            " levels; a " + sizeText(width, height) + " frame needs RG32F " + sizeText(w1, h1) +
                            " with " + std::to_string(fullMipLevels(w1, h1)) + " levels (SizeRule::frame(2), levels = 0)");
}

// ---- CPU mirror: images in GL's row order (row 0 at the bottom), as the shaders index them ------

Image flipRows(const Image& in) {
    Image out(in.width, in.height, in.channels);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x)
            for (int c = 0; c < in.channels; ++c) out.at(x, in.height - 1 - y, c) = in.at(x, y, c);
    return out;
}

vec2 texelAt(const Image& image, int x, int y) { return vec2(image.at(x, y, 0), image.at(x, y, 1)); }

// pull_push_pull.comp
Image pullLevel(const Image& fine, int width, int height) {
    Image coarse(width, height, 2);
    const ivec2 coarseSize(width, height), fineSize(fine.width, fine.height);
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            ivec4 block = pullBlock(ivec2(px, py), coarseSize, fineSize);
            vec2 sums(0.0f);
            for (int y = block.y; y <= block.w; ++y)
                for (int x = block.x; x <= block.z; ++x) sums = pullAccumulate(sums, texelAt(fine, x, y));
            vec2 r = pullResult(sums);
            coarse.at(px, py, 0) = r.x;
            coarse.at(px, py, 1) = r.y;
        }
    return coarse;
}

// pull_push_push.comp: the completed visibility of one level (channel 0) beside its weight.
Image pushLevel(const Image& pulled, const Image* coarser) {
    Image out(pulled.width, pulled.height, 2);
    for (int py = 0; py < pulled.height; ++py)
        for (int px = 0; px < pulled.width; ++px) {
            vec2 texel = texelAt(pulled, px, py);
            float c = texel.x;  // COARSEST
            if (coarser) {
                const ivec2 coarseSize(coarser->width, coarser->height);
                ivec4 taps = pushTaps(ivec2(px, py), coarseSize);
                vec2 f = pushFractions(ivec2(px, py), coarseSize);
                c = pushBilinear(coarser->at(taps.x, taps.y), coarser->at(taps.z, taps.y), coarser->at(taps.x, taps.w),
                                 coarser->at(taps.z, taps.w), f);
            }
            out.at(px, py, 0) = pushBlend(texel, c);
            out.at(px, py, 1) = texel.y;
        }
    return out;
}

}  // namespace

void PullPush::run(ProgramCache& programs, const Texture& input, Texture& pull, Texture& push, Texture& output) {
    const int width = input.width(), height = input.height();
    if (input.format() != GL_RG32F) throw InternalError("PullPush::run: the input is " + input.formatName() + ", not RG32F (v, w)");
    if (output.format() != GL_R32F || output.width() != width || output.height() != height)
        throw InternalError("PullPush::run: the output is " + output.formatName() + " " +
                            sizeText(output.width(), output.height()) + ", not R32F " + sizeText(width, height));
    checkPyramid("pull", pull, width, height);
    checkPyramid("push", push, width, height);
    const int top = pull.levels() - 1;  // mip of the 1x1 level

    // Pull: level 1 from the input, then level m + 2 from m + 1 (mips m + 1 from m).
    const ShaderProgram& first = programs.compute("common/pull_push_pull.comp", {"FIRST_LEVEL"});
    glBindTextureUnit(0, input.id());
    first.set("inputVisibilityWeight", 0);
    bindImage(1, pull, 0, GL_WRITE_ONLY);
    first.dispatch(groups(pull.width(0)), groups(pull.height(0)));
    memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    const ShaderProgram& reduce = programs.compute("common/pull_push_pull.comp");
    for (int m = 1; m <= top; ++m) {
        bindImage(0, pull, m - 1, GL_READ_ONLY);
        bindImage(1, pull, m, GL_WRITE_ONLY);
        reduce.dispatch(groups(pull.width(m)), groups(pull.height(m)));
        memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // level m is the next dispatch's source
    }

    // Push: the 1x1 top is complete by itself; every finer level blends with the one above it.
    const ShaderProgram& coarsest = programs.compute("common/pull_push_push.comp", {"COARSEST"});
    bindImage(0, pull, top, GL_READ_ONLY);
    bindImage(2, push, top, GL_WRITE_ONLY);
    coarsest.dispatch(1, 1);
    memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    const ShaderProgram& blend = programs.compute("common/pull_push_push.comp");
    for (int m = top - 1; m >= 0; --m) {
        bindImage(0, pull, m, GL_READ_ONLY);
        bindImage(1, push, m + 1, GL_READ_ONLY);
        bindImage(2, push, m, GL_WRITE_ONLY);
        blend.dispatch(groups(push.width(m)), groups(push.height(m)));
        memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    const ShaderProgram& final = programs.compute("common/pull_push_push.comp", {"FINAL"});
    glBindTextureUnit(0, input.id());
    final.set("inputVisibilityWeight", 0);
    bindImage(1, push, 0, GL_READ_ONLY);
    bindImage(2, output, 0, GL_WRITE_ONLY);
    final.dispatch(groups(width), groups(height));
    memoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

namespace {

class PullPushPass : public Pass {
public:
    PullPushPass(std::string input, std::string output) : input_(std::move(input)), output_(std::move(output)) {}
    void execute(PassContext& ctx) override {
        pullPush_.run(ctx.programs(), ctx.texture(input_), ctx.texture("pull_push.pull"), ctx.texture("pull_push.push"),
                      ctx.texture(output_));
    }

private:
    std::string input_, output_;
    PullPush pullPush_;
};

}  // namespace

std::vector<ResourceDesc> pullPushPyramids(const std::string& input, const std::string& appliesWhen) {
    ResourceDesc pull = ResourceDesc::texture(
        "pull_push.pull", Format::RG32F, SizeRule::frame(2),
        "pull-push levels 1, 2, ... down to 1x1 (level 0 is '" + input +
            "'): (v, w) = weighted mean visibility and min(1, sum of the weights) over the pixels each texel covers");
    pull.kind = ResourceKind::Pyramid;
    pull.levels = 0;
    pull.appliesWhen = appliesWhen;
    ResourceDesc push = pull;
    push.name = "pull_push.push";
    push.doc = "pull-push levels 1, 2, ... after the push: (completed visibility, the pull weight of that level)";
    return {pull, push};
}

PassDesc pullPushPass(const std::string& input, const std::string& output, const std::string& appliesWhen) {
    PassDesc p;
    p.name = "pull_push";
    p.doc = "pull-push reconstruction of the sparse visibility buffer '" + input +
            "' (guennebaud2007 sec. 5.2, Gortler et al. 1996): pull to 1x1 by weighted means, push back by bilinear blending";
    p.reads = {input};
    ResourceDesc out = ResourceDesc::texture(output, Format::R32F, SizeRule::frame(),
                                             "visibility reconstructed by pull-push from '" + input +
                                                 "': computed pixels (w = 1) unchanged, gaps filled");
    out.appliesWhen = appliesWhen;
    p.creates = pullPushPyramids(input, appliesWhen);
    p.creates.push_back(out);
    p.state = PipelineState::fullscreen();
    p.soft = true;
    // Every pixel depends on the whole frame (the 1x1 level), and compute dispatches ignore the
    // scissor refineFrame bands with: one run per frame.
    p.wholeFrame = true;
    p.create = [input, output] { return std::make_unique<PullPushPass>(input, output); };
    return p;
}

std::vector<InternalDesc> pullPushInternals(const std::string& appliesWhen) {
    InternalDesc pull;
    pull.name = "pull_push.pull";
    pull.kind = InternalDesc::Kind::Pyramid;
    pull.resource = "pull_push.pull";
    pull.channels = {"visibility", "weight"};
    pull.doc = "pull phase of the pull-push reconstruction (guennebaud2007 sec. 5.2): file level m is pull-push "
               "level m + 1 (level 0 is the sparse input), weighted mean visibility and saturated weight";
    pull.appliesWhen = appliesWhen;
    InternalDesc push = pull;
    push.name = "pull_push.push";
    push.resource = "pull_push.push";
    push.doc = "push phase of the pull-push reconstruction: file level m is pull-push level m + 1, completed "
               "visibility (gaps filled from the coarser level, bilinearly) and the pull weight of that level";
    return {pull, push};
}

Image pullPushCpu(const Image& vw, std::vector<Image>* pullOut, std::vector<Image>* pushOut) {
    if (vw.channels != 2 || vw.width < 1 || vw.height < 1)
        throw InternalError("pullPushCpu: expected a 2-channel (v, w) image, got " + std::to_string(vw.channels) +
                            " channels " + sizeText(vw.width, vw.height));
    const Image level0 = flipRows(vw);
    std::vector<Image> pull;
    for (int k = 1;; ++k) {
        const Image& fine = k == 1 ? level0 : pull.back();
        pull.push_back(pullLevel(fine, pullPushLevelSize(k, vw.width), pullPushLevelSize(k, vw.height)));
        if (pull.back().width == 1 && pull.back().height == 1) break;
    }
    std::vector<Image> push(pull.size());
    for (size_t m = pull.size(); m-- > 0;) push[m] = pushLevel(pull[m], m + 1 < pull.size() ? &push[m + 1] : nullptr);
    Image completed = pushLevel(level0, &push[0]);
    Image out(vw.width, vw.height, 1);
    for (int y = 0; y < vw.height; ++y)
        for (int x = 0; x < vw.width; ++x) out.at(x, vw.height - 1 - y) = completed.at(x, y, 0);
    if (pullOut) {
        pullOut->clear();
        for (const Image& l : pull) pullOut->push_back(flipRows(l));
    }
    if (pushOut) {
        pushOut->clear();
        for (const Image& l : push) pushOut->push_back(flipRows(l));
    }
    return out;
}

}  // namespace shadowlab
