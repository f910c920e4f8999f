// The HSM, the kernel and the classification of guennebaud2007 section 3, shared by ssm-gbp06 and
// ssm-contour, and their CPU mirror for the per-pixel records.
#include "hsm/hsm.h"

#include <cfloat>
#include <cmath>
#include <tuple>

#include "error.h"
#include "visibility/discontinuities.h"
#include "visibility/pull_push.h"

namespace shadowlab {

using namespace shared;

namespace {

constexpr float kNoCaster = FLT_MAX;  // shadow_map.cpp's "no caster" marker (kernel.frag: 3.4e38)

// guennebaud2007 sec. 3: "a hierarchical version of the shadow map (HSM) is built from high to low
// resolution in a similar fashion to mipmapped textures. Each pixel stores both the minimum and
// maximum covered depth values." HSM level 0 is the map itself; the pyramid texture holds levels 1,
// 2, ... as its mip levels 0, 1, ...; level 1 is a full-screen draw (hsm_first.frag), the others
// one dispatch each (hsm.comp).
class HsmPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& hsm = ctx.texture("hsm");
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        // light_multires: also "depth_levels", every level's min depth in an atlas of two layers,
        // the map itself and the HSM levels side by side (hsmLevelAtlasX).
        const bool minLevels = ctx.param("light_multires") != 0.0;
        Texture* depthLevels = minLevels ? &ctx.texture("depth_levels") : nullptr;
        std::vector<std::string> rest;
        if (minLevels) {
            rest.push_back("MIN_LEVELS");
            glCopyImageSubData(map.id(), GL_TEXTURE_2D, 0, 0, 0, 0, depthLevels->id(), GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0,
                               map.width(), map.height(), 1);
        }
        const int mapSize = map.width();
        // HSM level 1, a quarter of the map's texels, as a full-screen draw (hsm_first.frag: why);
        // its atlas copy starts at x = 0 (hsmLevelAtlasX(1)), so both targets share coordinates.
        std::vector<std::string> firstDefines;
        if (depthLevels) firstDefines.push_back("MIN_LEVELS");
        std::vector<Framebuffer::Attachment> colors{{&hsm, 0, -1}};
        if (depthLevels) colors.push_back({depthLevels, 0, 1});
        const Framebuffer& firstFbo = firstFbo_.get(colors, std::nullopt);
        const ShaderProgram& firstProgram = ctx.programs().get("common/fullscreen.vert", "backprojection/hsm_first.frag", firstDefines);
        firstProgram.use();
        glBindTextureUnit(0, map.id());
        firstProgram.set("shadowMap", 0);
        firstFbo.bind(hsm.width(), hsm.height());
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        memoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        const ShaderProgram& reduce = ctx.programs().compute("backprojection/hsm.comp", rest);
        if (depthLevels) bindImage(2, *depthLevels, 0, GL_WRITE_ONLY, 1);  // the atlas's levels 2, 3, ...
        for (int k = 1; k < hsm.levels(); ++k) {
            bindImage(0, hsm, k - 1, GL_READ_ONLY);
            bindImage(1, hsm, k, GL_WRITE_ONLY);
            if (depthLevels) reduce.set("atlasX", hsmLevelAtlasX(k + 1, mapSize));
            reduce.dispatch(GLuint((hsm.width(k) + 7) / 8), GLuint((hsm.height(k) + 7) / 8));
            memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // level k is the next dispatch's source
        }
        memoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    }

private:
    FramebufferCache firstFbo_;
};

// Kernel size (eq. 1 and refinement) and classification per pixel: shaders/backprojection/kernel.frag.
class KernelPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& size = ctx.texture("kernel_size");
        Texture& iterations = ctx.texture("kernel_iterations");
        Texture& classes = ctx.texture("classification");
        Texture& occluder = ctx.texture("occluder_depth");
        const Framebuffer& fbo = fbo_.get({&size, &iterations, &classes, &occluder}, nullptr);
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "backprojection/kernel.frag");
        program.use();
        const Texture& hsm = ctx.texture("hsm");
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setReceiverUniforms(ctx, program, map.width());
        glBindTextureUnit(3, hsm.id());
        program.set("hsm", 3);
        glBindTextureUnit(4, map.id());
        program.set("shadowMap", 4);
        program.set("hsmTopLevel", hsm.levels());
        program.set("lightWidthWorld", bpLightWidth(bpLightShape(ctx.light()), ctx.light().size));
        fbo.bind(ctx.width(), ctx.height());
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
};

}  // namespace

std::vector<ParamDesc> backprojectionParams() {
    std::vector<ParamDesc> params = shadowMapParams();
    ParamDesc cap{"max_kernel", "", ParamDesc::Type::Int, "texels", 256, 4, 8192, 1,
                  "cap on the kernel width w_k the visibility loop walks (not the paper's: its sec. 5 bounds the cost "
                  "with coarser HSM levels); wider kernels are clamped and lose their outer occluders. The test scenes "
                  "reach w_k = 108 at most at sm_size 1024",
                  ""};
    params.push_back(cap);
    ParamDesc multires{"light_multires", "", ParamDesc::Type::Bool, "", 1.0, 0, 1, 1,
                       "light-space multi-resolution (guennebaud2007 sec. 5.1): walk the finest HSM level whose kernel "
                       "is at most t_k of its texels instead of the shadow map itself, so the cost no longer grows "
                       "with the penumbra", ""};
    params.push_back(multires);
    ParamDesc tk{"t_k", "t_k", ParamDesc::Type::Float, "texels", 24.0, 2.0, 256.0, 1.0,
                 "kernel threshold t_k of eq. 2: the largest kernel, in texels of the level walked (2 t_k at most "
                 "outside the blending band); 24 keeps ssm-contour within 0.002 RMSE of the full-resolution walk on "
                 "every scene in assets/, where 16 loses 0.01 on plant under a light of size 2 "
                 "(techniques/ssm-contour/README.md)",
                 "light_multires == true"};
    params.push_back(tk);
    ParamDesc screen{"screen_adaptive", "", ParamDesc::Type::Bool, "", 1.0, 0, 1, 1,
                     "screen-space multi-resolution (guennebaud2007 sec. 5.2 and 6): compute the visibility of a "
                     "dithered subset of the penumbra pixels, denser where the penumbra is narrow on screen (eq. 4-6), "
                     "pack them by blocks and reconstruct the rest by pull-push", ""};
    params.push_back(screen);
    ParamDesc smin{"s_min", "s_min", ParamDesc::Type::Float, "pixels", 16.0, 1.0, 1024.0, 1.0,
                   "s_min of eq. 6: the screen-space penumbra size at which pixels start to be skipped (sec. 5.2: \"for "
                   "a fully automatic process, we suggest s_min = 16\")",
                   "screen_adaptive == true"};
    params.push_back(smin);
    ParamDesc pattern{"pattern", "h", ParamDesc::Type::Int, "pixels", 4.0, 2.0, 16.0, 1.0,
                      "width h of the ordered-dither pattern of eq. 6 (Fig. 9's 4 x 4): one pixel in h x h is always "
                      "computed, the lowest density the widest penumbrae get",
                      "screen_adaptive == true", ParamDesc::Constraint::PowerOfTwo, {}};
    params.push_back(pattern);
    ParamDesc disc{"discontinuities", "", ParamDesc::Type::Bool, "", 1.0, 0, 1, 1,
                   "compute every pixel near a depth or normal discontinuity of the receivers (sec. 5.2, Fig. 8 "
                   "right): pull-push would otherwise blend penumbrae across two surfaces (off: Fig. 8 left)",
                   "screen_adaptive == true"};
    params.push_back(disc);
    return params;
}

PassDesc hsmPass() {
    PassDesc p;
    p.name = "hsm";
    p.doc = "hierarchical shadow map: min and max depth pyramid, every level (guennebaud2007 sec. 3)";
    p.reads = shadowTestReads();
    p.reads.push_back("param:light_multires");
    ResourceDesc hsm = ResourceDesc::texture("hsm", Format::RG32F, SizeRule::like("shadow_map", 2),
                                             "HSM levels 1, 2, ... (level 0 is the shadow map): (min, max) light-view "
                                             "depth over the map texels each texel covers");
    hsm.kind = ResourceKind::Pyramid;
    hsm.levels = 0;
    ResourceDesc levels = ResourceDesc::texture("depth_levels", Format::R32F, SizeRule::like("shadow_map"),
                                                "light_multires: the min depth of every HSM level in one atlas, layer 0 "
                                                "the shadow map itself, layer 1 the levels 1, 2, ... side by side "
                                                "(hsmLevelAtlasX), so the visibility walk reads a level with one fetch at "
                                                "level of detail 0 (sec. 5.1)");
    levels.kind = ResourceKind::TextureArray;
    levels.layers = 2;
    levels.appliesWhen = "light_multires == true";
    p.creates = {hsm, levels};
    p.state = PipelineState::fullscreen();
    p.soft = true;
    p.create = [] { return std::make_unique<HsmPass>(); };
    return p;
}

PassDesc kernelPass() {
    PassDesc p;
    p.name = "kernel";
    p.doc = "kernel width from the top-level min (eq. 1), refined level by level until it converges; lit / umbra / "
            "penumbra from the kernel's depth bounds (guennebaud2007 sec. 3)";
    p.reads = {"gbuffer", "light", "hsm", "param:bias_const", "param:bias_slope"};
    for (const std::string& r : shadowTestReads()) p.reads.push_back(r);
    p.creates = {
        ResourceDesc::texture("kernel_size", Format::R32F, SizeRule::frame(),
                              "converged kernel width w_k per pixel, texels (0 when the top level already says lit)"),
        ResourceDesc::texture("kernel_iterations", Format::R32F, SizeRule::frame(),
                              "refinement steps per pixel (HSM levels read after the first estimate)"),
        ResourceDesc::texture("classification", Format::R32F, SizeRule::frame(),
                              "0 umbra, 0.5 penumbra, 1 lit (from the kernel's HSM depth bounds)"),
        ResourceDesc::texture("occluder_depth", Format::R32F, SizeRule::frame(),
                              "z_occ (guennebaud2007 sec. 5.1): the occluding min depths of the refinement level's "
                              "four texels around p', bilinearly weighted; a smooth hint for the level (eq. 3) and "
                              "the penumbra size (eq. 4); 0 when lit"),
    };
    p.soft = true;
    p.create = [] { return std::make_unique<KernelPass>(); };
    return p;
}

std::vector<InternalDesc> backprojectionInternals() {
    std::vector<InternalDesc> out = shadowMapInternals();
    InternalDesc hsm;
    hsm.name = "hsm";
    hsm.kind = InternalDesc::Kind::Pyramid;
    hsm.resource = "hsm";
    hsm.channels = {"min", "max"};
    hsm.doc = "hierarchical shadow map levels 1, 2, ... (file level k is HSM level k + 1; HSM level 0 is "
              "shadow_map): min and max light-view depth per texel (inf = no caster)";
    hsm.convert = farMarkerToInfinity;
    out.push_back(hsm);
    out.push_back({"kernel_size", InternalDesc::Kind::Image, "kernel_size", {"texels"},
                   "converged kernel width w_k per pixel (guennebaud2007 eq. 1 and refinement), texels", "", {}, {}, {}, {}});
    out.push_back({"kernel_iterations", InternalDesc::Kind::Image, "kernel_iterations", {"steps"},
                   "kernel refinement steps per pixel", "", {}, {}, {}, {}});
    out.push_back({"classification", InternalDesc::Kind::Image, "classification", {"class"},
                   "0 umbra, 0.5 penumbra, 1 lit", "", {}, {}, {}, {}});
    out.push_back({"occluder_depth", InternalDesc::Kind::Image, "occluder_depth", {"z_occ"},
                   "smooth occluder depth z_occ per pixel (guennebaud2007 sec. 5.1), light-view depth; 0 when lit", "",
                   {}, {}, {}, {}});
    return out;
}

ResourceDesc lightLevelsResource() {
    ResourceDesc r = ResourceDesc::texture("light_levels", Format::RGBA32F, SizeRule::frame(),
                                           "light-space multi-resolution per pixel (guennebaud2007 sec. 5.1): lambda "
                                           "(eq. 3; ssm-gbp06: eq. 2's level), the HSM level walked, the level blended "
                                           "in and its weight; -1 on lit and umbra pixels");
    r.appliesWhen = "light_multires == true";
    return r;
}

InternalDesc lightLevelsInternal() {
    InternalDesc i{"light_levels", InternalDesc::Kind::Image, "light_levels", {"lambda", "level", "blend_level", "blend_weight"},
                   "lambda (eq. 3), the HSM level walked, the level blended in and its weight (sec. 5.1); -1 where "
                   "nothing was back-projected (lit, umbra)", "", {}, {}, {}, {}};
    i.appliesWhen = "light_multires == true";
    return i;
}

std::vector<std::string> backprojectionVisibilityReads() {
    std::vector<std::string> reads = {"gbuffer", "light", "hsm", "kernel_size", "classification", "occluder_depth",
                                      "param:bias_const", "param:bias_slope", "param:max_kernel",
                                      "param:light_multires", "param:t_k", "param:screen_adaptive", "selection", "depth_levels", "block_occupancy",
                                      "pack.counts", "pack.pixels", "pack.offsets"};
    for (const std::string& r : shadowTestReads()) reads.push_back(r);
    return reads;
}

std::vector<std::string> backprojectionVisibilityModifies() { return {"visibility_sparse"}; }

// ---- the screen-space multi-resolution (sec. 5.2 and 6) -----------------------------------------------

namespace {

const char* kScreenAdaptive = "screen_adaptive == true";
const char* kDiscontinuities = "screen_adaptive == true && discontinuities == true";
constexpr int kCountSlots = 12;  // pack.comp's counts

class DiscontinuitiesPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        if (!ctx.applies(kDiscontinuities)) return;
        // Widened past the largest pixel spacing the pattern leaves: h (one pixel in h x h).
        buffer_.run(ctx, ctx.texture("discontinuities"), DiscontinuityBuffer::kDefaultDepthThreshold,
                    DiscontinuityBuffer::kDefaultNormalThreshold, dilationRadiusForSpacing(ctx.paramInt("pattern")));
    }

private:
    DiscontinuityBuffer buffer_;
};

class SelectionPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        if (!ctx.applies(kScreenAdaptive)) return;
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "backprojection/select.frag", {});
        program.use();
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setReceiverUniforms(ctx, program, map.width());
        setLightFrontUniforms(program, ctx.light());
        glBindTextureUnit(3, ctx.texture("classification").id());
        program.set("classification", 3);
        glBindTextureUnit(4, ctx.texture("occluder_depth").id());
        program.set("occluderDepth", 4);
        const bool discontinuities = ctx.applies(kDiscontinuities);
        glBindTextureUnit(5, discontinuities ? ctx.texture("discontinuities").id() : ctx.texture("classification").id());
        program.set("discontinuities", 5);
        program.set("useDiscontinuities", discontinuities);
        program.set("lightWidthWorld", bpLightWidth(bpLightShape(ctx.light()), ctx.light().size));
        program.set("sMin", float(ctx.param("s_min")));
        program.set("patternSize", ctx.paramInt("pattern"));
        const Camera& camera = ctx.camera();
        program.set("eta", float(ctx.height()) / (2.0f * std::tan(glm::radians(camera.fovYDegrees) * 0.5f)));
        program.set("cameraPosition", camera.position);
        program.set("cameraViewFromWorld", camera.viewFromWorld());
        // A full-screen draw into the two images (select.frag: why not a compute pass).
        Texture& selection = ctx.texture("selection");
        Texture& sparse = ctx.texture("visibility_sparse");
        const Framebuffer& fbo = fbo_.get({&selection, &sparse}, nullptr);
        fbo.bind(selection.width(), selection.height());
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                      GL_FRAMEBUFFER_BARRIER_BIT);
    }

private:
    FramebufferCache fbo_;
};

class PackPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        if (!ctx.applies(kScreenAdaptive)) return;
        const GLuint counts = ctx.buffer("pack.counts");
        glClearNamedBufferData(counts, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
        Texture& selection = ctx.texture("selection");
        const Texture& occupancy = ctx.texture("block_occupancy");
        const glm::ivec2 blocks(occupancy.width(), occupancy.height());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counts);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, ctx.buffer("pack.pixels"));
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, ctx.buffer("pack.offsets"));
        for (int step = 1; step <= 3; ++step) {  // count, scan, write (pack.comp)
            const ShaderProgram& pack =
                ctx.programs().compute("backprojection/pack.comp", {"PACK_STEP " + std::to_string(step)});
            pack.use();
            pack.set("blocks", blocks);
            if (step != 2) {
                bindImage(0, selection, 0, GL_READ_WRITE);
                bindImage(1, occupancy, 0, GL_WRITE_ONLY);
                pack.dispatch(GLuint((blocks.x + 7) / 8), GLuint((blocks.y + 7) / 8));
            } else {
                pack.dispatch(1);
            }
            memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
        memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                      GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        for (GLuint unit = 0; unit < 3; ++unit) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unit, 0);
    }
};

class ScreenPullPushPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        if (!ctx.applies(kScreenAdaptive)) return;
        pullPush_.run(ctx.programs(), ctx.texture("visibility_sparse"), ctx.texture("pull_push.pull"),
                      ctx.texture("pull_push.push"), ctx.texture("visibility"));
    }

private:
    PullPush pullPush_;
};

}  // namespace

std::vector<PassDesc> screenSelectionPasses() {
    PassDesc disc;
    disc.name = "discontinuities";
    disc.doc = "discontinuity buffer (guennebaud2007 sec. 5.2): thresholded Sobel on the camera depth and normals, "
               "widened past the pattern's largest pixel spacing; every pixel on it is computed";
    disc.reads = {"gbuffer", "camera", "param:screen_adaptive", "param:discontinuities", "param:pattern"};
    ResourceDesc d = ResourceDesc::texture("discontinuities", Format::R32F, SizeRule::frame(),
                                           "1 on a depth or normal discontinuity of the receivers seen from the camera "
                                           "(widened by the pattern width h), 0 elsewhere");
    d.appliesWhen = kDiscontinuities;
    disc.creates = {d};
    disc.soft = true;
    disc.wholeFrame = true;
    disc.create = [] { return std::make_unique<DiscontinuitiesPass>(); };

    PassDesc sel;
    sel.name = "selection";
    sel.doc = "classification and view-dependent selection (guennebaud2007 sec. 5.2 eq. 4-6, sec. 6 pass one): per "
              "pixel lit, umbra, or penumbra selected by the dither pattern, forced by a discontinuity, or skipped; "
              "the sparse v-buffer (v, w)";
    sel.reads = {"gbuffer", "camera", "light", "classification", "occluder_depth", "discontinuities",
                 "param:screen_adaptive", "param:discontinuities", "param:s_min", "param:pattern",
                 "param:bias_const", "param:bias_slope"};
    for (const std::string& r : shadowTestReads()) sel.reads.push_back(r);
    ResourceDesc codes = ResourceDesc::texture(
        "selection", Format::R32F, SizeRule::frame(),
        "per pixel: 0 background, 1 lit, 2 umbra, 3 penumbra selected by eq. 6, 4 forced by a discontinuity, 5 "
        "evaluated with its whole block (sec. 6), 6 skipped (filled by pull-push)");
    codes.appliesWhen = kScreenAdaptive;
    ResourceDesc sparse = ResourceDesc::texture(
        "visibility_sparse", Format::RG32F, SizeRule::frame(),
        "the sparse v-buffer before pull-push: (v, w), w = 1 where known (lit, umbra, background, evaluated), 0 on "
        "skipped pixels");
    sparse.appliesWhen = kScreenAdaptive;
    sel.creates = {codes, sparse};
    sel.soft = true;
    sel.wholeFrame = true;
    sel.create = [] { return std::make_unique<SelectionPass>(); };

    PassDesc pack;
    pack.name = "pack";
    pack.doc = "block classification and packing (guennebaud2007 sec. 6): blocks of 16 x 16 pixels over 80% selected "
               "are processed whole (all their penumbra pixels), empty ones skipped, the selected pixels of the others "
               "compacted; a prefix sum over the blocks orders the list by block rows";
    pack.reads = {"param:screen_adaptive"};
    pack.modifies = {"selection"};
    ResourceDesc occupancy = ResourceDesc::texture("block_occupancy", Format::R32F, SizeRule::frame(BP_BLOCK),
                                                   "per block of 16 x 16 pixels: its selected pixels (eq. 6 or forced) "
                                                   "over its pixels; > 0.8 processed whole, 0 skipped, else compacted");
    occupancy.appliesWhen = kScreenAdaptive;
    ResourceDesc counts;
    counts.name = "pack.counts";
    counts.kind = ResourceKind::StorageBuffer;
    counts.size = SizeRule::fixed(kCountSlots, 1);
    counts.elementBytes = 4;
    counts.doc = "[0] pixels listed, [1-3] the visibility pass's dispatch, [4] blocks processed whole, [8] compacted "
                 "blocks, [9] skipped blocks, [10] selected pixels";
    counts.appliesWhen = kScreenAdaptive;
    ResourceDesc pixels = counts;
    pixels.name = "pack.pixels";
    pixels.size = SizeRule::frame();
    pixels.doc = "the pixels to evaluate, x | y << 16, by blocks in row-major order (a whole block's penumbra pixels, "
                 "a compacted block's selected ones, in scan order)";
    ResourceDesc blocks = counts;
    blocks.name = "pack.offsets";
    blocks.size = SizeRule::frame(BP_BLOCK);
    blocks.doc = "per block of 16 x 16 pixels (row-major): the first entry of its pixels in pack.pixels";
    pack.creates = {occupancy, counts, pixels, blocks};
    pack.soft = true;
    pack.wholeFrame = true;
    pack.create = [] { return std::make_unique<PackPass>(); };
    return {disc, sel, pack};
}

PassDesc screenPullPushPass() {
    PassDesc p;
    p.name = "pull_push";
    p.doc = "pull-push reconstruction of the sparse v-buffer (guennebaud2007 sec. 5.2, Gortler et al. 1996): "
            "computed pixels kept, skipped ones filled from coarser weighted means";
    p.reads = {"visibility_sparse", "param:screen_adaptive"};
    p.modifies = {"visibility"};
    p.creates = pullPushPyramids("visibility_sparse", kScreenAdaptive);
    p.soft = true;
    p.wholeFrame = true;
    p.create = [] { return std::make_unique<ScreenPullPushPass>(); };
    return p;
}

std::vector<InternalDesc> screenAdaptiveInternals() {
    std::vector<InternalDesc> out;
    InternalDesc sel{"selection", InternalDesc::Kind::Image, "selection", {"code"},
                     "per pixel (sec. 5.2, 6): 0 background, 1 lit, 2 umbra, 3 selected by eq. 6, 4 forced by a "
                     "discontinuity, 5 evaluated with its whole block, 6 skipped (pull-push)", "", {}, {}, {}, {}};
    sel.appliesWhen = kScreenAdaptive;
    out.push_back(sel);
    InternalDesc disc{"discontinuities", InternalDesc::Kind::Image, "discontinuities", {"discontinuity"},
                      "the discontinuity buffer (sec. 5.2): 1 on a widened depth or normal discontinuity", "", {}, {}, {}, {}};
    disc.appliesWhen = kDiscontinuities;
    out.push_back(disc);
    InternalDesc occ{"block_occupancy", InternalDesc::Kind::Image, "block_occupancy", {"selected_fraction"},
                     "per 16 x 16 block (sec. 6): selected pixels over its pixels; > 0.8 whole, 0 skipped, else "
                     "compacted", "", {}, {}, {}, {}};
    occ.appliesWhen = kScreenAdaptive;
    out.push_back(occ);
    InternalDesc sparse{"visibility_sparse", InternalDesc::Kind::Image, "visibility_sparse", {"visibility", "weight"},
                        "the v-buffer before pull-push (sec. 5.2): w = 1 where computed or known, 0 on skipped pixels",
                        "", {}, {}, {}, {}};
    sparse.appliesWhen = kScreenAdaptive;
    out.push_back(sparse);
    for (InternalDesc& i : pullPushInternals(kScreenAdaptive)) out.push_back(i);
    return out;
}

CounterDesc screenSelectionCounter() {
    CounterDesc c;
    c.name = "screen_selection";
    c.doc = "the screen-space selection (guennebaud2007 sec. 5.2, 6): penumbra pixels evaluated (selected by eq. 6, "
            "forced by a discontinuity, with their whole block) and skipped (filled by pull-push), their evaluated "
            "fraction, and the 16 x 16 blocks processed whole, compacted and skipped";
    c.appliesWhen = kScreenAdaptive;
    c.reads = {"selection", "pack.counts", "param:screen_adaptive"};
    c.count = [](PassContext& ctx) {
        const Image codes = readTexture(ctx.texture("selection"), 1);
        size_t n[SEL_SKIPPED + 1] = {};
        for (float v : codes.data) {
            const int code = int(v);
            if (code >= 0 && code <= SEL_SKIPPED) ++n[code];
        }
        std::vector<uint32_t> counts(kCountSlots);
        glGetNamedBufferSubData(ctx.buffer("pack.counts"), 0, GLsizeiptr(counts.size() * 4), counts.data());
        const size_t evaluated = n[SEL_SELECTED] + n[SEL_FORCED] + n[SEL_BLOCK];
        const size_t penumbra = evaluated + n[SEL_SKIPPED];
        return nlohmann::json{{"penumbra_pixels", penumbra},
                              {"evaluated_pixels", evaluated},
                              {"selected_pixels", n[SEL_SELECTED]},
                              {"forced_pixels", n[SEL_FORCED]},
                              {"block_pixels", n[SEL_BLOCK]},
                              {"skipped_pixels", n[SEL_SKIPPED]},
                              {"evaluated_fraction", penumbra ? double(evaluated) / double(penumbra) : 1.0},
                              {"listed_pixels", counts[0]},
                              {"blocks_whole", counts[4]},
                              {"blocks_compacted", counts[8]},
                              {"blocks_skipped", counts[9]}};
    };
    return c;
}

int bpLightShape(const Light& light) {
    return light.shape == LightShape::Square ? BP_LIGHT_SQUARE : BP_LIGHT_DISK;
}

float bpLightHalfSize(const Light& light) {
    return light.shape == LightShape::Square ? 0.5f * light.size : light.size;
}

void setReceiverUniforms(PassContext& ctx, const ShaderProgram& program, int smSize) {
    const LightView& view = ctx.lightView();
    program.set("lightViewFromWorld", view.viewFromWorld);
    program.set("lightClipFromView", view.clipFromView);
    program.set("lightTanHalfFov", view.tanHalfFov);
    program.set("shadowMapSize", float(smSize));
    program.set("lightPosition", ctx.light().position);
    program.set("biasConstTexels", float(ctx.param("bias_const")));
    program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
    ctx.bindGBuffer(program);  // units 0-2
}

// ---- CPU mirror -----------------------------------------------------------------------------------------

BackprojectionCpu BackprojectionCpu::read(PassContext& ctx) {
    BackprojectionCpu c;
    const Texture& hsm = ctx.texture("hsm");
    c.size = ctx.texture(shadowTestMap(ctx)).width();
    c.topLevel = hsm.levels();
    c.view = ctx.lightView();
    c.lightPosition = ctx.light().position;
    c.shape = bpLightShape(ctx.light());
    c.lightWidth = bpLightWidth(c.shape, ctx.light().size);
    c.lightHalfSize = bpLightHalfSize(ctx.light());
    c.biasConst = float(ctx.param("bias_const"));
    c.biasSlope = float(ctx.param("bias_slope"));
    c.maxKernel = float(ctx.param("max_kernel"));
    for (int k = 0; k < hsm.levels(); ++k) {
        c.hsm.push_back(readTextureLevel(hsm, k));
        if (c.hsm.back().width != hsmLevelSize(k + 1, c.size))
            throw InternalError("hsm level " + std::to_string(k + 1) + " is " + std::to_string(c.hsm.back().width) +
                                " texels across, hsmLevelSize says " + std::to_string(hsmLevelSize(k + 1, c.size)));
    }
    c.depth = readTextureLevel(ctx.texture(shadowTestMap(ctx)), 0);
    return c;
}

float BackprojectionCpu::depthAt(glm::ivec2 t) const {
    if (t.x < 0 || t.y < 0 || t.x >= size || t.y >= size) return kNoCaster;
    return depth.at(t.x, size - 1 - t.y);
}

int BackprojectionCpu::levelSize(int level) const {
    return hsmLevelSize(level, size);
}

glm::vec2 BackprojectionCpu::hsmAt(int level, glm::ivec2 t) const {
    if (level == 0) return glm::vec2(depthAt(t));
    const Image& l = hsm[size_t(level - 1)];
    return {l.at(t.x, l.height - 1 - t.y, 0), l.at(t.x, l.height - 1 - t.y, 1)};
}

BpReceiver BackprojectionCpu::receiver(const glm::vec3& worldPosition, const glm::vec3& worldNormal) const {
    return bpReceiver(view.viewFromWorld, view.clipFromView, worldPosition, worldNormal, lightPosition, view.tanHalfFov,
                      float(size), biasConst, biasSlope);
}

bool BackprojectionCpu::occludes(const BpReceiver& r, glm::ivec2 t, float z) const {
    return bpSampleOccludes(r, glm::vec2(t) + 0.5f, z, float(size), view.tanHalfFov);
}

float BackprojectionCpu::levelDepth(int level, glm::ivec2 t) const {
    int n = levelSize(level);
    if (t.x < 0 || t.y < 0 || t.x >= n || t.y >= n) return kNoCaster;
    return hsmAt(level, t).x;
}

bool BackprojectionCpu::levelOccludes(const BpReceiver& r, int level, glm::ivec2 t, float z) const {
    return bpLevelSampleOccludes(r, level, t, z, float(size), view.tanHalfFov);
}

glm::vec2 BackprojectionCpu::backprojectLevel(const BpReceiver& r, glm::vec2 u, int level, float z) const {
    return backprojectToLight(r.position, u * float(1 << level), z, float(size), view.tanHalfFov, lightHalfSize);
}

KernelResult computeKernel(const BackprojectionCpu& c, const BpReceiver& r) {
    KernelResult k;
    const float smSize = float(c.size);
    const float zp = r.position.z;
    k.globalMin = c.hsmAt(c.topLevel, {0, 0}).x;
    if (k.globalMin >= zp - r.bias) return k;
    float w = std::min(hsmKernelTexels(c.lightWidth, smSize, c.view.tanHalfFov, k.globalMin, zp), 2.0f * smSize);
    glm::vec2 bounds(k.globalMin, 3.4e38f);
    float planeMin = 0.0f;
    int lastLevel = 0;
    for (int step = 0; step < 32; ++step) {  // kernel.frag's kMaxRefinements
        int level = hsmRefinementLevel(w, c.topLevel);
        lastLevel = level;
        int levelSize = c.levelSize(level);
        glm::ivec4 rangeL = levelTexelRange(kernelTexelRange(r.centre, w, c.size), level, levelSize);
        bounds = glm::vec2(3.4e38f, -3.4e38f);
        for (int y = rangeL.y; y <= rangeL.w; ++y)
            for (int x = rangeL.x; x <= rangeL.z; ++x) {
                glm::vec2 t = c.hsmAt(level, {x, y});
                bounds = glm::vec2(std::min(bounds.x, t.x), std::max(bounds.y, t.y));
            }
        planeMin = regionPlaneDepthMin(r, levelRegionTexels(rangeL, level, levelSize, c.size), smSize, c.view.tanHalfFov);
        k.iterations += 1;
        KernelStep s;
        s.level = level;
        s.texels = rangeL;
        s.bounds = bounds;
        if (bounds.x >= zp - r.bias) {
            s.refinedTexels = 0.0f;
            k.steps.push_back(s);
            break;
        }
        float refined = hsmKernelTexels(c.lightWidth, smSize, c.view.tanHalfFov, bounds.x, zp);
        s.refinedTexels = refined;
        k.steps.push_back(s);
        if (refined >= w) break;
        w = refined;
    }
    k.texels = w;
    k.classification = bpClassify(r, bounds, planeMin);
    if (k.classification == BP_CLASS_LIT) return k;
    // z_occ, as kernel.frag.
    glm::vec2 u = r.centre / float(1 << lastLevel) - 0.5f;
    glm::ivec2 i0 = glm::ivec2(glm::floor(u));
    glm::vec4 d(c.levelDepth(lastLevel, i0), c.levelDepth(lastLevel, i0 + glm::ivec2(1, 0)),
                c.levelDepth(lastLevel, i0 + glm::ivec2(1, 1)), c.levelDepth(lastLevel, i0 + glm::ivec2(0, 1)));
    k.occluderDepth = occluderDepthHint(d, u - glm::floor(u), zp - r.bias, bounds.x);
    k.hintLevel = lastLevel;
    return k;
}

namespace {
const char* className(float c) {
    return c == BP_CLASS_LIT ? "lit" : c == BP_CLASS_UMBRA ? "umbra" : "penumbra";
}
nlohmann::json finite(float v) { return std::isfinite(v) && std::abs(v) < 1e30f ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

glm::vec3 chooseLightLevels(const BackprojectionCpu& c, const BpReceiver& r, float w, float zOcc, float tk, float beta,
                            float* lambda) {
    if (beta < 0.0f) {
        int lod = lightLevelForKernel(w, tk, c.topLevel);
        if (lambda) *lambda = float(lod);
        return glm::vec3(float(lod), 0.0f, 0.0f);
    }
    float smoothKernel = hsmKernelTexels(c.lightWidth, float(c.size), c.view.tanHalfFov, zOcc, r.position.z);
    float l = lightLevelContinuous(smoothKernel, w, tk, c.topLevel);
    if (lambda) *lambda = l;
    return lightLevelBlend(l, beta, c.topLevel);
}

PixelRecordStart startPixelRecord(PassContext& ctx, glm::ivec2 pixel, float beta) {
    PixelRecordStart s;
    nlohmann::json& j = s.record;
    int row = ctx.height() - 1 - pixel.y;
    glm::vec4 position(0.0f), normal(0.0f);
    resetPackState();  // into client memory (gl/texture.h)
    glGetTextureSubImage(ctx.gbuffer().position->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof position,
                         &position);
    glGetTextureSubImage(ctx.gbuffer().normal->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof normal, &normal);
    if (position.w == 0.0f) {
        j["background"] = true;
        s.done = true;
        return s;
    }
    // The screen-space selection's code at this pixel (sec. 5.2, 6): a skipped pixel's image value is
    // pull-push's, not the back-projection the record recomputes.
    j["selection"] = nullptr;
    if (ctx.param("screen_adaptive") != 0.0) {
        static const char* names[] = {"background", "lit", "umbra", "selected", "forced", "block", "skipped"};
        const int code = int(ctx.pixelValue("selection", pixel));
        j["selection"] = code >= 0 && code <= SEL_SKIPPED ? names[code] : "unknown";
    }
    s.cpu = BackprojectionCpu::read(ctx);
    const BackprojectionCpu& c = s.cpu;
    const Light& light = ctx.light();
    s.front = lightFractionInFront(light.isPoint() ? LIGHT_SHAPE_POINT : int(light.shape), light.position,
                                   light.isPoint() ? glm::vec3(0.0f) : light.right(), light.up,
                                   light.isPoint() ? 0.0f : light.size, glm::vec3(position), glm::vec3(normal));
    s.receiver = c.receiver(glm::vec3(position), glm::vec3(normal));
    const BpReceiver& r = s.receiver;
    j["light_geometry"] = {{"shape", c.shape == BP_LIGHT_SQUARE ? "square" : "disk"},
                           {"area", bpLightArea(c.shape)},
                           {"unit_world", c.lightHalfSize},
                           {"coordinates", c.shape == BP_LIGHT_SQUARE ? "the light square is [-1,1]^2 (unit w_l / 2) on its right, up axes"
                                                                      : "the light disk is the unit disk (unit: its radius) on its right, up axes"}};
    j["receiver"] = {{"light_frame", {r.position.x, r.position.y, r.position.z}},
                     {"shadow_map_texel", {r.centre.x, r.centre.y}},
                     {"bias", r.bias},
                     {"in_light_frustum", r.inside != 0.0f}};
    float lightArea = bpLightArea(c.shape);
    if (r.inside == 0.0f) {
        j["classification"] = "lit";
        j["kernel"] = nullptr;  // outside the light's frustum: lit, as for `hard`
        s.done = true;
        return s;
    }
    s.kernel = computeKernel(c, r);
    nlohmann::json steps = nlohmann::json::array();
    for (const KernelStep& k : s.kernel.steps)
        steps.push_back({{"level", k.level},
                         {"texels", {k.texels.x, k.texels.y, k.texels.z, k.texels.w}},
                         {"min", finite(k.bounds.x)},
                         {"max", finite(k.bounds.y)},
                         {"refined_texels", k.refinedTexels}});
    float used = std::min(s.kernel.texels, c.maxKernel);
    s.range = kernelTexelRange(r.centre, used, c.size);
    j["kernel"] = {{"global_min", finite(s.kernel.globalMin)},
                   {"occluder_depth", finite(s.kernel.occluderDepth)},
                   {"texels", s.kernel.texels},
                   {"used_texels", used},
                   {"iterations", s.kernel.iterations},
                   {"steps", steps},
                   {"texel_range", {s.range.x, s.range.y, s.range.z, s.range.w}}};
    j["classification"] = className(s.kernel.classification);
    j["light_levels"] = nullptr;  // filled below for penumbra pixels when light_multires is on
    if (s.kernel.classification == BP_CLASS_UMBRA) s.initialArea = lightArea;
    s.done = s.kernel.classification != BP_CLASS_PENUMBRA;
    if (!s.done && ctx.param("light_multires") != 0.0) {
        float tk = float(ctx.param("t_k")), lambda = 0.0f;
        glm::vec3 levels = chooseLightLevels(c, r, used, s.kernel.occluderDepth, tk, beta, &lambda);
        s.level = int(levels.x);
        s.blendLevel = int(levels.y);
        s.blendWeight = levels.z;
        j["light_levels"] = {{"t_k", tk},
                             {"lod_eq2", lightLevelForKernel(used, tk, c.topLevel)},
                             {"lambda", lambda},
                             {"level", s.level},
                             {"blend_level", s.blendLevel},
                             {"blend_weight", s.blendWeight},
                             {"level_texel_range", [&] {
                                  int n = c.levelSize(s.level);
                                  glm::ivec4 l = levelTexelRange(s.range, s.level, n);
                                  return nlohmann::json::array({l.x, l.y, l.z, l.w});
                              }()}};
    } else if (!s.done) {
        j["light_levels"] = nullptr;  // light_multires off: the map itself
    }
    return s;
}

void finishPixelRecord(PassContext& ctx, glm::ivec2 pixel, PixelRecordStart& s, float itemsArea,
                       const BlendedLevelArea* blended) {
    nlohmann::json& j = s.record;
    if (j.contains("background")) return;
    float occluded = s.initialArea + itemsArea;
    j["initial_area"] = s.initialArea;
    j["occluded_area"] = occluded;
    j["front_fraction"] = s.front;
    float v = bpVisibility(occluded, s.cpu.shape);
    j["blend_initial_area"] = nullptr;  // no level blended in
    j["blend_occluded_area"] = nullptr;
    if (blended && s.blendWeight > 0.0f) {
        float other = blended->initialArea + blended->itemsArea;
        j["blend_initial_area"] = blended->initialArea;
        j["blend_occluded_area"] = other;
        v = v + (bpVisibility(other, s.cpu.shape) - v) * s.blendWeight;  // GLSL mix
    }
    j["visibility_recomputed"] = v * s.front;
    j["visibility"] = ctx.pixelValue("visibility", pixel);
}

KernelCapDesc backprojectionKernelCap() {
    KernelCapDesc k;
    k.name = "max_kernel";
    k.doc = "penumbra pixels (the kernel pass's classification); clamped when the converged kernel w_k (eq. 1) "
            "was wider than max_kernel texels, so the visibility pass walked only max_kernel of it";
    k.reads = {"classification", "kernel_size", "param:max_kernel"};
    k.count = [](PassContext& ctx) {
        KernelCapCount c;
        c.cap = ctx.param("max_kernel");
        const Image cls = readTexture(ctx.texture("classification"), 1);
        const Image w = readTexture(ctx.texture("kernel_size"), 1);
        for (size_t i = 0; i < cls.pixelCount(); ++i) {
            if (cls.data[i] != BP_CLASS_PENUMBRA) continue;
            c.add(w.data[i], w.data[i] > c.cap);
        }
        return c;
    };
    return k;
}

std::vector<std::pair<std::string, std::string>> backprojectionRecordSchema() {
    return {{"background", "true when no geometry covers the pixel (then no other field)"},
            {"light_geometry", "shape, area (4 for the square, pi for the disk, in light coordinates), unit and axes"},
            {"receiver", "p in the light frame (x, y, depth z_p), p' in shadow-map texels, depth bias (world)"},
            {"kernel", "global_min (top HSM level), texels (converged w_k, eq. 1), used_texels (after max_kernel), "
                       "iterations, steps [{level, texels [x0,y0,x1,y1] of that level, min, max, refined_texels}], "
                       "texel_range (level-0 texels walked)"},
            {"classification", "lit, umbra or penumbra (from the kernel's depth bounds)"},
            {"selection", "screen-space selection (sec. 5.2, 6; null when screen_adaptive is off): lit, umbra, "
                          "selected (eq. 6), forced (a discontinuity), block (its 16 x 16 block processed whole), or "
                          "skipped: then the image holds pull-push's value, not visibility_recomputed"},
            {"light_levels", "light-space multi-resolution (sec. 5.1; null when light_multires is off): t_k, "
                             "lod_eq2 (eq. 2), lambda (eq. 3 from kernel.occluder_depth; GBP06: eq. 2's level), "
                             "level walked, blend_level and blend_weight (sec. 5.1's pseudo-code), "
                             "level_texel_range [x0,y0,x1,y1] of the level walked"},
            {"initial_area", "occluded area before the list: the full light for umbra (and, for ssm-contour, when "
                             "the contour inside test occludes the light centre), else 0"},
            {"occluded_area", "initial_area + the list's areas (the level walked)"},
            {"blend_initial_area", "when blend_weight > 0: the blended level's initial area"},
            {"blend_occluded_area", "when blend_weight > 0: the blended level's occluded area (its list is not "
                                    "recorded)"},
            {"front_fraction", "the fraction of the light in front of the receiver's tangent plane (the visibility "
                               "convention, shaders/shared/tangent_plane.glsl)"},
            {"visibility_recomputed", "clamp(1 - occluded_area / light area, 0, 1), mixed with the blended level's by "
                                      "blend_weight, x front_fraction, on the CPU"},
            {"visibility", "this light's visibility in the image (GPU)"}};
}

std::vector<std::string> backprojectionRecordReads() {
    std::vector<std::string> reads = {"gbuffer", "light", "hsm", "visibility", "param:bias_const", "param:bias_slope",
                                      "param:max_kernel", "param:light_multires", "param:t_k",
                                      "param:screen_adaptive", "selection"};
    for (const std::string& r : shadowTestReads()) reads.push_back(r);
    return reads;
}

void BackprojectionVisibilityPass::setUniforms(PassContext& ctx, const ShaderProgram& program) {
    const Texture& map = ctx.texture(shadowTestMap(ctx));
    setReceiverUniforms(ctx, program, map.width());
    glBindTextureUnit(3, map.id());
    program.set("shadowMap", 3);
    glBindTextureUnit(4, ctx.texture("kernel_size").id());
    program.set("kernelSize", 4);
    glBindTextureUnit(5, ctx.texture("classification").id());
    program.set("classification", 5);
    const Texture& hsm = ctx.texture("hsm");
    glBindTextureUnit(6, hsm.id());
    program.set("hsm", 6);
    program.set("hsmTopLevel", hsm.levels());
    glBindTextureUnit(7, ctx.texture("occluder_depth").id());
    program.set("occluderDepth", 7);
    if (ctx.param("light_multires") != 0.0) {
        const Texture& levels = ctx.texture("depth_levels");
        glBindTextureUnit(9, levels.id());
        program.set("depthLevels", 9);
    }
    program.set("lightWidthWorld", bpLightWidth(bpLightShape(ctx.light()), ctx.light().size));
    program.set("kernelThreshold", float(ctx.param("t_k")));
    program.set("lightHalfSize", bpLightHalfSize(ctx.light()));
    program.set("maxKernelTexels", float(ctx.param("max_kernel")));
    setLightFrontUniforms(program, ctx.light());
    if (extra_) extra_(ctx, program);
}

// The visibility shaders' variant (visibility_common.glsl): the level arithmetic only where
// light_multires is on, and the light's shape as a constant, so that neither the full-resolution
// walk nor a square light pays for what it never uses (llvmpipe runs both sides of every branch).
namespace {
std::vector<std::string> backprojectionVisibilityDefines(PassContext& ctx) {
    std::vector<std::string> defines = {"BP_LIGHT_SHAPE " + std::to_string(bpLightShape(ctx.light()))};
    if (ctx.param("light_multires") != 0.0) defines.push_back("LIGHT_MULTIRES");
    return defines;
}
}  // namespace

void BackprojectionVisibilityPass::execute(PassContext& ctx) {
    if (ctx.applies(kScreenAdaptive)) {
        executeSparse(ctx);
        return;
    }
    Texture& visibility = ctx.texture("visibility");
    // The variant: backprojectionVisibilityDefines.
    const bool multires = ctx.param("light_multires") != 0.0;
    Texture* levels = multires ? &ctx.texture("light_levels") : nullptr;
    std::vector<const Texture*> targets{&visibility};
    if (levels) targets.push_back(levels);
    const Framebuffer& fbo = fbo_.get(targets, nullptr);
    const ShaderProgram& program =
        ctx.programs().get("common/fullscreen.vert", shader_, backprojectionVisibilityDefines(ctx));
    program.use();
    setUniforms(ctx, program);
    fbo.bind(ctx.width(), ctx.height());
    drawFullscreenTriangle();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// Sec. 6's third pass: the visibility of the whole blocks and of the compacted pixels, stored at
// their places in the sparse v-buffer. Under refineFrame's bands (a scissor, which compute ignores)
// only the band's pixels are evaluated, so the bands share the work as the fragment path's do.
void BackprojectionVisibilityPass::executeSparse(PassContext& ctx) {
    const bool multires = ctx.param("light_multires") != 0.0;
    GLint box[4] = {0, 0, ctx.width(), ctx.height()};
    if (glIsEnabled(GL_SCISSOR_TEST)) glGetIntegerv(GL_SCISSOR_BOX, box);
    const glm::ivec4 band(box[0], box[1], box[0] + box[2], box[1] + box[3]);
    const bool wholeFrame = band == glm::ivec4(0, 0, ctx.width(), ctx.height());
    Texture& sparse = ctx.texture("visibility_sparse");
    if (multires && wholeFrame) {
        const float none[4] = {-1.0f, -1.0f, -1.0f, 0.0f};
        glClearTexImage(ctx.texture("light_levels").id(), 0, GL_RGBA, GL_FLOAT, none);
    } else if (multires) {
        const float none[4] = {-1.0f, -1.0f, -1.0f, 0.0f};
        glClearTexSubImage(ctx.texture("light_levels").id(), 0, band.x, band.y, 0, band.z - band.x, band.w - band.y, 1,
                           GL_RGBA, GL_FLOAT, none);
    }
    // The blocks the band covers, as one range of the row-major list: from the band's first block
    // to its last (a superset when the band is narrower than the frame; `band` filters the pixels).
    const Texture& occupancy = ctx.texture("block_occupancy");
    const int blocksX = occupancy.width(), blockCount = occupancy.width() * occupancy.height();
    const int bx0 = band.x / BP_BLOCK, by0 = band.y / BP_BLOCK;
    const int bx1 = (band.z - 1) / BP_BLOCK, by1 = (band.w - 1) / BP_BLOCK;
    const int firstBlock = by0 * blocksX + bx0, endBlock = by1 * blocksX + bx1 + 1;
    const GLuint counts = ctx.buffer("pack.counts");
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counts);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, ctx.buffer("pack.pixels"));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, ctx.buffer("pack.offsets"));
    const ShaderProgram& args = ctx.programs().compute("backprojection/pack_args.comp");
    args.use();
    args.set("firstBlock", firstBlock);
    args.set("endBlock", endBlock);
    args.set("blockCount", blockCount);
    args.dispatch(1);
    memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    const ShaderProgram& program = ctx.programs().compute(sparseShader_, backprojectionVisibilityDefines(ctx));
    program.use();
    setUniforms(ctx, program);
    program.set("band", band);
    program.set("firstBlock", firstBlock);
    program.set("endBlock", endBlock);
    program.set("blockCount", blockCount);
    bindImage(0, sparse, 0, GL_WRITE_ONLY);
    if (multires) bindImage(1, ctx.texture("light_levels"), 0, GL_WRITE_ONLY);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, counts);
    glDispatchComputeIndirect(GLintptr(1 * sizeof(GLuint)));
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    for (GLuint unit = 0; unit < 3; ++unit) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unit, 0);
    memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

}  // namespace shadowlab
