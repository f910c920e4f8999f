// `hard`: shadow mapping from the light's centre (Williams 1978; background in cournia2005 sec. 3 (Fig. 3.1)).
// Pass 1 renders the casters' light-view depth; pass 2 compares each receiver's depth with it.
#include "hard/hard.h"

#include "shared/shared.h"

namespace shadowlab {

namespace {

// One depth test per pixel (pcf: the mean of an n x n kernel of them).
class DepthTestPass : public Pass {
public:
    explicit DepthTestPass(bool pcf) : pcf_(pcf) {}
    void execute(PassContext& ctx) override {
        Texture& visibility = ctx.texture("visibility");
        const Framebuffer& fbo = fbo_.get({&visibility}, nullptr);
        std::vector<std::string> defines;
        if (pcf_) defines.push_back("PCF");
        if (!pcf_ && ctx.paramBool("plane_test")) defines.push_back("PLANE_TEST");
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "hard/visibility.frag", defines);
        program.use();
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setShadowLookupUniforms(program, ctx.lightView(), map.width(), ctx.light());
        program.set("biasConstTexels", float(ctx.param("bias_const")));
        program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
        if (pcf_) program.set("pcfKernel", ctx.paramInt("pcf_kernel"));
        ctx.bindGBuffer(program);
        glBindTextureUnit(3, map.id());
        program.set("shadowMap", 3);
        fbo.bind(ctx.width(), ctx.height());
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    bool pcf_;
    FramebufferCache fbo_;
};

}  // namespace

PassDesc depthTestPass(bool pcf) {
    PassDesc p;
    p.name = pcf ? "filter" : "visibility";
    p.doc = pcf ? "mean of n x n depth tests around the receiver's texel" : "depth test of each receiver against the shadow map";
    p.reads = {"gbuffer", "light", "param:bias_const", "param:bias_slope"};
    for (const std::string& r : shadowTestReads()) p.reads.push_back(r);
    if (pcf) p.reads.push_back("param:pcf_kernel");
    if (!pcf) p.reads.push_back("param:plane_test");
    p.creates = {visibilityResource()};
    p.soft = pcf;
    p.create = [pcf] { return std::make_unique<DepthTestPass>(pcf); };
    return p;
}

InternalDesc shadowMapPixelRecord(bool pcf) {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's shadow-map look-up (--pixel x,y)";
    r.schema = {{"background", "true when no geometry covers the pixel (then no other field)"},
                {"shadow_map_uv", "the receiver's position in the shadow map, [0,1]^2"},
                {"shadow_map_texel", "the texel it falls in (x, y from the bottom)"},
                {"receiver_depth", "the receiver's light-view depth z (world units)"},
                {"stored_depth", "the depth stored in that texel (null: no caster)"},
                {"texels_read", "rectangles [x0, y0, x1, y1] (inclusive, from the bottom) of the texels the depth "
                                "tests fetched: the receiver's texel, or the n x n kernel clamped to the map (pcf); "
                                "empty outside the light's frustum (lit without a test)"},
                {"visibility", "this light's visibility at the pixel"}};
    r.reads = {"gbuffer", "light", "shadow_map", "shadow_map_second_depth", "param:second_depth", "visibility"};
    if (pcf) r.reads.push_back("param:pcf_kernel");
    r.record = [pcf](PassContext& ctx, glm::ivec2 pixel) {
        int row = ctx.height() - 1 - pixel.y;
        glm::vec4 position(0.0f);
        resetPackState();  // into client memory (gl/texture.h)
        glGetTextureSubImage(ctx.gbuffer().position->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT,
                             sizeof position, &position);
        nlohmann::json j;
        if (position.w == 0.0f) {
            j["background"] = true;
            return j;
        }
        const LightView& view = ctx.lightView();
        glm::vec4 v = view.viewFromWorld * glm::vec4(glm::vec3(position), 1.0f);
        glm::vec4 clip = view.clipFromView * v;
        glm::vec2 uv = glm::vec2(clip) / clip.w * 0.5f + 0.5f;
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        int size = map.width();
        glm::ivec2 t = glm::clamp(glm::ivec2(glm::floor(uv * float(size))), glm::ivec2(0), glm::ivec2(size - 1));
        float stored = 0.0f;
        glGetTextureSubImage(map.id(), 0, t.x, t.y, 0, 1, 1, 1, GL_RED, GL_FLOAT, sizeof stored, &stored);
        j["shadow_map_uv"] = {uv.x, uv.y};
        j["shadow_map_texel"] = {t.x, t.y};
        j["receiver_depth"] = -v.z;
        j["stored_depth"] = stored > 1e30f ? nlohmann::json(nullptr) : nlohmann::json(stored);
        // What shaders/common/shadow_lookup.glsl fetches: texel floor(uv * size) + offset, clamped, for
        // offsets in [-r, r]^2 (r = n / 2 with pcf, 0 otherwise), and nothing outside the frustum.
        int radius = pcf ? ctx.paramInt("pcf_kernel") / 2 : 0;
        bool inside = shared::shadowMapCoord(view.viewFromWorld, view.clipFromView, glm::vec3(position)).w != 0.0f;
        j["texels_read"] = nlohmann::json::array();
        if (inside) {
            glm::ivec2 base(glm::floor(uv * float(size)));  // before the clamp, as the shader adds the offset
            glm::ivec2 lo = glm::clamp(base - radius, glm::ivec2(0), glm::ivec2(size - 1));
            glm::ivec2 hi = glm::clamp(base + radius, glm::ivec2(0), glm::ivec2(size - 1));
            j["texels_read"].push_back({lo.x, lo.y, hi.x, hi.y});
        }
        j["visibility"] = ctx.pixelValue("visibility", pixel);
        return j;
    };
    return r;
}

ParamDesc planeTestParam(bool on) {
    return {"plane_test", "", ParamDesc::Type::Bool, "", on ? 1.0 : 0.0, 0, 1, 1,
            "depth test against the receiver's tangent plane at the tested texel's centre, so tilted and grazing "
            "receivers need no slope bias and contacts keep their shadow (off: the classic slope-biased test)",
            ""};
}

const TechniqueDesc& hardTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "hard";
        d.name = "Hard shadow map";
        d.citation = "Williams 1978, Casting curved shadows on curved surfaces; background in cournia2005 sec. 3 (Fig. 3.1)";
        d.summary = "one shadow map from the light's centre and one depth test per pixel: the umbra-only limit "
                    "every soft technique converges to as the light shrinks";
        d.soft = false;
        d.params = shadowMapParams();
        d.params.push_back(planeTestParam(false));
        d.passes = {shadowMapPass(), depthTestPass(false)};
        d.internals = shadowMapInternals();
        d.internals.push_back(shadowMapPixelRecord());
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
