// `hard`: shadow mapping from the light's centre (Williams 1978; background in cournia2005 sec. 3 (Fig. 3.1)).
// Pass 1 renders the casters' light-view depth; pass 2 compares each receiver's depth with it.
#include "hard.h"

#include "shadow_map.h"

namespace shadowlab {

HardShadowTechnique::HardShadowTechnique(std::string shaderDefine) : define_(std::move(shaderDefine)) {}

void HardShadowTechnique::run(const std::string& pass, RenderContext& ctx, LightState& light) {
    if (pass == "shadow_map") {
        shadowMap_.render(ctx, light.view, light.params.getInt("sm_size"), light.params.getBool("second_depth"));
        return;
    }
    // "visibility": one depth test per pixel (pcf: an n x n kernel of them).
    if (!visibility_ || visibility_.width() != ctx.width || visibility_.height() != ctx.height) {
        visibility_ = Texture(ctx.width, ctx.height, GL_R32F);
        fbo_ = Framebuffer({&visibility_}, nullptr);
    }
    std::vector<std::string> defines;
    if (!define_.empty()) defines.push_back(define_);
    const ShaderProgram& program = ctx.programs.get("common/fullscreen.vert", "hard/visibility.frag", defines);
    program.use();
    setShadowLookupUniforms(program, light.view, shadowMap_.size(), light.light);
    program.set("biasConstTexels", float(light.params.get("bias_const")));
    program.set("biasSlopeTexels", float(light.params.get("bias_slope")));
    if (light.desc->findParam("pcf_kernel")) program.set("pcfKernel", light.params.getInt("pcf_kernel"));
    glBindTextureUnit(0, ctx.gbuffer.position.id());
    glBindTextureUnit(1, ctx.gbuffer.normal.id());
    glBindTextureUnit(2, shadowMap_.depth().id());
    program.set("gPosition", 0);
    program.set("gNormal", 1);
    program.set("shadowMap", 2);
    fbo_.bind(ctx.width, ctx.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    drawFullscreenTriangle();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

std::vector<std::pair<std::string, const Texture*>> HardShadowTechnique::buffers() const {
    std::vector<std::pair<std::string, const Texture*>> out;
    shadowMap_.appendBuffers(out, "");
    if (visibility_) out.push_back({"visibility", &visibility_});
    return out;
}

void HardShadowTechnique::writeInternals(InternalWriter& out, RenderContext&, LightState&) const {
    Image first = readTexture(shadowMap_.firstDepth(), 1);
    for (float& z : first.data)
        if (z > 1e30f) z = INFINITY;  // no caster
    out.image("shadow_map", first, "light-view depth z of the nearest caster per texel (world units; inf = no caster)");
    if (shadowMap_.usesSecondDepth()) {
        Image second = readTexture(shadowMap_.depth(), 1);
        for (float& z : second.data)
            if (z > 1e30f) z = INFINITY;
        out.image("shadow_map_second_depth", second,
                  "light-view depth of the second-nearest caster surface (second-depth option; inf = none)");
    }
}

nlohmann::json HardShadowTechnique::pixelInfo(glm::ivec2 pixel, RenderContext& ctx, LightState& light) const {
    // One texel of the G-buffer (GL rows count from the bottom, --pixel's from the top).
    glm::vec4 position(0.0f);
    glGetTextureSubImage(ctx.gbuffer.position.id(), 0, pixel.x, ctx.height - 1 - pixel.y, 0, 1, 1, 1, GL_RGBA, GL_FLOAT,
                         sizeof position, &position);
    nlohmann::json j;
    if (position.w == 0.0f) {
        j["background"] = true;
        return j;
    }
    glm::vec3 p(position);
    glm::vec4 view = light.view.viewFromWorld * glm::vec4(p, 1.0f);
    glm::vec4 clip = light.view.clipFromView * view;
    glm::vec2 uv = glm::vec2(clip) / clip.w * 0.5f + 0.5f;
    int size = shadowMap_.size();
    glm::ivec2 texel = glm::clamp(glm::ivec2(glm::floor(uv * float(size))), glm::ivec2(0), glm::ivec2(size - 1));
    float stored = 0.0f;
    glGetTextureSubImage(shadowMap_.depth().id(), 0, texel.x, texel.y, 0, 1, 1, 1, GL_RED, GL_FLOAT, sizeof(float), &stored);
    float visibility = 0.0f;
    glGetTextureSubImage(visibility_.id(), 0, pixel.x, ctx.height - 1 - pixel.y, 0, 1, 1, 1, GL_RED, GL_FLOAT,
                         sizeof(float), &visibility);
    j["shadow_map_uv"] = {uv.x, uv.y};
    j["shadow_map_texel"] = {texel.x, texel.y};
    j["receiver_depth"] = -view.z;
    j["stored_depth"] = stored > 1e30f ? nlohmann::json(nullptr) : nlohmann::json(stored);
    j["visibility"] = visibility;
    return j;
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
        d.passes = {
            shadowMapPass(),
            {"visibility", {"shadow_map", "gbuffer", "param:bias_const", "param:bias_slope"}, {"visibility"},
             "depth test of each receiver against the shadow map", false},
        };
        d.internals = {{"shadow_map", "image", "light-view depth of the nearest caster"},
                       {"shadow_map_second_depth", "image", "second depth layer (second_depth=1)"},
                       {"visibility", "image", "this light's visibility"}};
        d.create = [] { return std::make_unique<HardShadowTechnique>(""); };
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
