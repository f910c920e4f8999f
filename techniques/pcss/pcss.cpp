// `pcss`: percentage-closer soft shadows (Fernando 2005, recapped in buades2015 sec. 2, eq. 1). The
// light-centre shadow map of `hard`; a blocker search over the region the light and the receiver
// define; the penumbra width of eq. 1; PCF with a kernel of that width.
#include "pcss/pcss.h"

#include <cmath>

#include "error.h"
#include "hard/hard.h"
#include "shared/shared.h"
#include "visibility/shadow_map.h"

namespace shadowlab {

float lightWidthWorld(const Light& light) {
    if (light.isPoint()) return 0.0f;
    return light.shape == LightShape::Square ? light.size : 2.0f * light.size;
}

const std::array<glm::vec2, 32>& poissonDisk32() {
    static const std::array<glm::vec2, 32> disk = [] {
        std::array<glm::vec2, 32> points{};
        size_t count = 0;
        const float minDistance = 0.25f;
        for (uint32_t i = 0; count < points.size(); ++i) {
            uint32_t h = shared::pcgHash(i * 2654435761u + 17u);
            glm::vec2 p(shared::hashToUnit(h) * 2.0f - 1.0f, shared::hashToUnit(shared::pcgHash(h)) * 2.0f - 1.0f);
            if (glm::dot(p, p) > 1.0f) continue;
            bool far = true;
            for (size_t k = 0; k < count && far; ++k) far = glm::distance(points[k], p) >= minDistance;
            if (far) points[count++] = p;
            if (i > 1000000u) throw InternalError("poissonDisk32: dart throwing did not converge");
        }
        return points;
    }();
    return disk;
}

ResourceDesc markResource(const std::string& name, const std::string& doc) {
    return ResourceDesc::texture(name, Format::DEPTH32F_STENCIL8, SizeRule::frame(), doc);
}

void drawStencilMarks(PassContext& ctx, int where, int channel, float above) {
    std::vector<std::string> defines;
    if (channel < 0)
        defines.push_back("MARK_GEOMETRY");
    else
        defines.push_back("MARK_CHANNEL " + std::to_string(channel));
    const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "pcss/mark.frag", defines);
    program.use();
    if (channel < 0) {
        ctx.bindGBuffer(program);
    } else {
        program.set("marks", 4);
        program.set("markAbove", above);
    }
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glEnable(GL_STENCIL_TEST);
    glStencilMask(0xFF);
    if (where < 0) {
        glStencilFunc(GL_ALWAYS, 1, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    } else {
        glStencilFunc(GL_EQUAL, where, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
    }
    drawFullscreenTriangle();
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void beginStencilTest(int value) {
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_EQUAL, value, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glStencilMask(0x00);
}

void endStencilTest() {
    glDisable(GL_STENCIL_TEST);
    glStencilMask(0xFF);
}

namespace {

void setPcssUniforms(PassContext& ctx, const ShaderProgram& program, const Texture& map) {
    setShadowLookupUniforms(program, ctx.lightView(), map.width(), ctx.light());
    program.set("biasConstTexels", float(ctx.param("bias_const")));
    program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
    program.set("lightWidthWorld", lightWidthWorld(ctx.light()));
    program.set("lightNearZ", ctx.lightView().nearZ);
    program.set("pattern", ctx.paramChoice("pattern") == "poisson" ? 1 : 0);
    const auto& disk = poissonDisk32();
    glProgramUniform2fv(program.id(), program.location("poissonDisk"), GLsizei(disk.size()), &disk[0].x);
}

// Step 1: blocker search, average blocker depth, penumbra width (eq. 1) and the PCF kernel.
class BlockerSearchPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& out = ctx.texture("pcss_blockers");
        Texture& mask = ctx.texture("pcss_mask");
        const Framebuffer& fbo = fbo_.get({&out}, &mask);
        fbo.bind(ctx.width(), ctx.height());
        glClearNamedFramebufferfi(fbo.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
        drawStencilMarks(ctx, -1);  // 1: geometry
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "pcss/blocker_search.frag");
        program.use();
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setPcssUniforms(ctx, program, map);
        program.set("blockerKernel", float(ctx.paramInt("blocker_kernel")));
        program.set("filterKernel", float(ctx.paramInt("filter_kernel")));
        ctx.bindGBuffer(program);
        glBindTextureUnit(3, map.id());
        program.set("shadowMap", 3);
        const float none[4] = {-1.0f, 0.0f, 0.0f, 0.0f};  // what skipped pixels keep: no blocker
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, none);
        beginStencilTest(1);
        drawFullscreenTriangle();
        endStencilTest();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
};

// Step 2: PCF over the kernel of step 1.
class FilterPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& visibility = ctx.texture("visibility");
        Texture& mask = ctx.texture("pcss_mask");
        const Framebuffer& fbo = fbo_.get({&visibility}, &mask);
        fbo.bind(ctx.width(), ctx.height());
        glBindTextureUnit(4, ctx.texture("pcss_blockers").id());
        drawStencilMarks(ctx, 1, 0, -0.5f);  // 2: geometry with a blocker (z_avg >= 0)
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "pcss/filter.frag");
        program.use();
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setPcssUniforms(ctx, program, map);
        ctx.bindGBuffer(program);
        glBindTextureUnit(3, map.id());
        program.set("shadowMap", 3);
        glBindTextureUnit(4, ctx.texture("pcss_blockers").id());
        program.set("blockers", 4);
        setLightFrontUniforms(program, ctx.light());
        const float lit[4] = {1.0f, 0.0f, 0.0f, 0.0f};  // what the background keeps
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, lit);
        beginStencilTest(2);
        drawFullscreenTriangle();
        endStencilTest();
        // Geometry without a blocker (stencil 1): "totally illuminated", but only by the part of
        // the light in front of its tangent plane (the visibility convention).
        const ShaderProgram& front = ctx.programs().get("common/fullscreen.vert", "common/light_front.frag");
        front.use();
        ctx.bindGBuffer(front);
        setLightFrontUniforms(front, ctx.light());
        beginStencilTest(1);
        drawFullscreenTriangle();
        endStencilTest();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
};

}  // namespace

std::vector<ParamDesc> filteringShadowMapParams() {
    std::vector<ParamDesc> params = shadowMapParams();
    for (ParamDesc& p : params) {
        if (p.key != "sm_size") continue;
        // The kernels are in texels and capped (m = 41, buades2015's setting): the finer the map, the
        // more texels a penumbra spans. At 512 the test scenes' penumbrae fit under m at their own
        // light sizes (square-occluder's 1-unit penumbra is 31 texels); at 1024 it is 63 and every
        // filtered pixel is clamped (closed-form RMSE 0.045 against 0.006; kernel_caps in --stats).
        p.defaultValue = 512;
        p.doc = "shadow-map resolution (width = height); 512 keeps the test scenes' penumbrae under m = 41 texels "
                "(at 1024 square-occluder's needs 63: clamped, see kernel_caps in --stats)";
    }
    return params;
}

KernelCapDesc pcssFilterKernelCap() {
    KernelCapDesc k;
    k.name = "filter_kernel";
    k.doc = "pixels where the blocker search found a blocker (the filter ran); clamped when eq. 1's kernel reached "
            "m = filter_kernel (or the map's 2 sm_size - 1)";
    k.reads = {"pcss_blockers", "param:filter_kernel", "param:sm_size"};
    k.count = [](PassContext& ctx) {
        KernelCapCount c;
        c.cap = std::min(std::max(double(ctx.paramInt("filter_kernel")), 1.0),
                         double(shared::maxKernelForMap(float(ctx.paramInt("sm_size")))));
        const Image b = readTexture(ctx.texture("pcss_blockers"), 4);
        for (size_t i = 0; i < b.pixelCount(); ++i) {
            if (!(b.data[i * 4] >= 0.0f)) continue;  // no blocker: not filtered
            const double kernel = b.data[i * 4 + 3];
            c.add(kernel, kernel >= c.cap * (1.0 - 1e-6));
        }
        return c;
    };
    return k;
}

// The kernel parameters of the shadow-map filtering family, with buades2015's settings.
ParamDesc blockerKernelParam() {
    ParamDesc n{"blocker_kernel", "n", ParamDesc::Type::Int, "texels", 29, 1, 127, 2,
                "largest blocker-search width n; each pixel searches the region its light and depth define, up to n "
                "(buades2015 uses 7, 11, 29; 29 with m = 41 is its Tables 2-6 setting). Clamped to 2 sm_size - 1",
                ""};
    n.constraint = ParamDesc::Constraint::Odd;
    return n;
}

ParamDesc filterKernelParam(const std::string& unit) {
    ParamDesc m{"filter_kernel", "m", ParamDesc::Type::Int, unit, 41, 1, 127, 2,
                "largest filter width m; each pixel filters over its eq. 1 penumbra, up to m (buades2015 uses 15, 21, 41)",
                ""};
    m.constraint = ParamDesc::Constraint::Odd;
    return m;
}

namespace {

// The picked pixel's record (--pixel, the shadow-map view): hard's (the receiver's texel and depths),
// with what pcss fetched instead of that one texel: the blocker search's square and, when it found
// a blocker, the filter's kernel, as blocker_search.frag and filter.frag fetch them (texel
// floor(uv size) + offset, clamped to the map; offsets in [-r, r]^2 with r = kernelRadius(width),
// or Poisson taps inside the disk of diameter width, whose bounding square is recorded).
InternalDesc pcssPixelRecord() {
    InternalDesc r = shadowMapPixelRecord();
    r.doc = "the picked pixel's shadow-map look-ups: the blocker search's region and the filter's (--pixel x,y)";
    for (auto& [key, doc] : r.schema)
        if (key == "texels_read")
            doc = "rectangles [x0, y0, x1, y1] (inclusive, from the bottom) of the texels fetched: the blocker search's "
                  "square, then the filter kernel's when a blocker was found (Poisson: the taps' bounding squares); "
                  "empty outside the light's frustum (lit without a test)";
    r.schema.push_back({"blocker_search", "width (texels, eq. of blockerSearchWidthTexels capped at n), blockers found, "
                                          "their average depth z_avg (null: none) and the texel rectangle searched"});
    r.schema.push_back({"filter", "the PCF kernel width (texels, from eq. 1, capped at m) and its texel rectangle; null "
                                  "when no blocker was found (the pixel is lit without filtering)"});
    r.reads.push_back("pcss_blockers");
    r.reads.push_back("param:pattern");
    auto hardRecord = r.record;
    r.record = [hardRecord](PassContext& ctx, glm::ivec2 pixel) {
        nlohmann::json j = hardRecord(ctx, pixel);
        if (j.contains("background") || j["texels_read"].empty()) return j;
        glm::vec4 b(0.0f);  // (z_avg, count, search width, kernel) of blocker_search.frag
        resetPackState();  // into client memory (gl/texture.h)
        glGetTextureSubImage(ctx.texture("pcss_blockers").id(), 0, pixel.x, ctx.height() - 1 - pixel.y, 0, 1, 1, 1, GL_RGBA,
                             GL_FLOAT, sizeof b, &b);
        const int size = ctx.texture(shadowTestMap(ctx)).width();
        const glm::vec2 centre = glm::vec2(j["shadow_map_uv"][0].get<float>(), j["shadow_map_uv"][1].get<float>()) * float(size);
        const bool poisson = ctx.paramChoice("pattern") == "poisson";
        auto rect = [&](float width) {
            glm::ivec2 lo, hi;
            if (poisson) {
                lo = glm::ivec2(glm::floor(centre - 0.5f * width));
                hi = glm::ivec2(glm::floor(centre + 0.5f * width));
            } else {
                const int radius = shared::kernelRadius(width);
                lo = glm::ivec2(glm::floor(centre)) - radius;
                hi = glm::ivec2(glm::floor(centre)) + radius;
            }
            lo = glm::clamp(lo, glm::ivec2(0), glm::ivec2(size - 1));
            hi = glm::clamp(hi, glm::ivec2(0), glm::ivec2(size - 1));
            return nlohmann::json{lo.x, lo.y, hi.x, hi.y};
        };
        const bool found = b.x >= 0.0f;
        j["blocker_search"] = {{"width_texels", b.z},
                               {"blockers_found", b.y},
                               {"average_blocker_depth", found ? nlohmann::json(b.x) : nlohmann::json(nullptr)},
                               {"texels", rect(b.z)}};
        j["texels_read"] = nlohmann::json::array({rect(b.z)});
        if (found) {
            j["filter"] = {{"kernel_texels", b.w}, {"texels", rect(b.w)}};
            j["texels_read"].push_back(rect(b.w));
        } else {
            j["filter"] = nullptr;
        }
        return j;
    };
    return r;
}

}  // namespace

const TechniqueDesc& pcssTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "pcss";
        d.name = "Percentage-closer soft shadows";
        d.citation = "Fernando 2005, Percentage-closer soft shadows; recap in buades2015 sec. 2, eq. 1 and sec. 4.1 (Fig. 2)";
        d.summary = "blocker search in the shadow map, penumbra width from the average blocker depth (eq. 1, parallel "
                    "light, occluder and receiver), then PCF with a kernel that wide";
        d.soft = true;
        d.params = filteringShadowMapParams();
        d.params.push_back(blockerKernelParam());
        ParamDesc m = filterKernelParam("texels");
        m.doc += ". Clamped to 2 sm_size - 1";
        d.params.push_back(m);
        ParamDesc pattern{"pattern", "", ParamDesc::Type::Enum, "", 0, 0, 1, 1,
                          "sampling pattern of both searches: regular = every texel of the kernel (the paper's n x n and "
                          "m x m, a square light), poisson = 32 taps of a Poisson disk scaled to the kernel (a disk light, "
                          "fixed cost, noisy)",
                          ""};
        pattern.choices = {"regular", "poisson"};
        d.params.push_back(pattern);

        std::vector<std::string> common = {"gbuffer", "light", "param:bias_const", "param:bias_slope", "param:pattern"};
        for (const std::string& r : shadowTestReads()) common.push_back(r);

        PassDesc search;
        search.name = "blocker_search";
        search.doc = "blocker search over the light/receiver region (<= n x n texels), average blocker depth, eq. 1 "
                     "penumbra and PCF kernel";
        search.reads = common;
        search.reads.push_back("param:blocker_kernel");
        search.reads.push_back("param:filter_kernel");
        search.creates = {
            ResourceDesc::texture(
                "pcss_blockers", Format::RGBA32F, SizeRule::frame(),
                "per pixel: average blocker depth z_avg (-1: none), blocker count, search width and filter kernel (texels)"),
            markResource("pcss_mask", "stencil marks: 1 geometry, 2 with a blocker (the pixels each draw shades)")};
        search.soft = true;
        search.create = [] { return std::make_unique<BlockerSearchPass>(); };

        PassDesc filter;
        filter.name = "filter";
        filter.doc = "PCF over the penumbra kernel of the blocker search (<= m x m texels)";
        filter.reads = common;
        filter.reads.push_back("pcss_blockers");
        filter.modifies = {"pcss_mask"};
        filter.creates = {visibilityResource()};
        filter.soft = true;
        filter.create = [] { return std::make_unique<FilterPass>(); };
        d.passes = {shadowMapPass(), search, filter};
        d.kernelCaps = {pcssFilterKernelCap()};

        d.internals = shadowMapInternals();
        InternalDesc blockers;
        blockers.name = "blockers";
        blockers.kind = InternalDesc::Kind::Image;
        blockers.resource = "pcss_blockers";
        blockers.channels = {"avg_blocker_depth", "blocker_count", "search_width", "kernel_size"};
        blockers.doc = "per pixel: average blocker depth z_avg (world, -1 = no blocker), blockers found, blocker-search "
                       "width and PCF kernel width (texels)";
        d.internals.push_back(blockers);
        d.internals.push_back(pcssPixelRecord());
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
