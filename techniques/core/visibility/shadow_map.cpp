#include "visibility/shadow_map.h"

#include <cfloat>
#include <cmath>

namespace shadowlab {

const Framebuffer& ShadowMapRenderer::framebuffer(const Texture& color, const Texture& depth) {
    auto key = std::make_pair(color.id(), depth.id());
    auto it = fbos_.find(key);
    if (it == fbos_.end()) {
        if (fbos_.size() > 16) fbos_.clear();  // textures were reallocated: drop stale framebuffers
        it = fbos_.emplace(key, Framebuffer({&color}, &depth)).first;
    }
    return it->second;
}

void ShadowMapRenderer::render(PassContext& ctx, const LightView& view, const Texture& first, const Texture& zbuffer,
                               const Texture* second) {
    const float farValue = FLT_MAX;  // no caster: lit
    const float zero = 0.0f;
    int size = first.width();
    // Reversed depth (see fitLightView): depth 1 at the near plane, keep the greatest. The pass's
    // declared state (PipelineState::depthGreaterReversed) sets the depth test and clip control.
    const ShaderProgram& program = ctx.programs().get("common/shadow_depth.vert", "common/shadow_depth.frag");
    program.use();
    program.set("lightViewFromWorld", view.viewFromWorld);
    program.set("lightClipFromView", view.clipFromView);
    program.set("peel", 0);
    const Framebuffer& firstFbo = framebuffer(first, zbuffer);
    firstFbo.bind(size, size);
    glClearNamedFramebufferfv(firstFbo.id(), GL_COLOR, 0, &farValue);
    glClearNamedFramebufferfv(firstFbo.id(), GL_DEPTH, 0, &zero);
    ctx.drawScene(program, true);

    if (second) {
        // Second pass: the nearest surface strictly behind the first one (depth peeling).
        program.set("peel", 1);
        glBindTextureUnit(0, first.id());
        program.set("firstDepth", 0);
        const Framebuffer& secondFbo = framebuffer(*second, zbuffer);
        secondFbo.bind(size, size);
        glClearNamedFramebufferfv(secondFbo.id(), GL_COLOR, 0, &farValue);
        glClearNamedFramebufferfv(secondFbo.id(), GL_DEPTH, 0, &zero);
        ctx.drawScene(program, true);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

namespace {
class ShadowMapPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const Texture* second = ctx.paramBool("second_depth") ? &ctx.texture("shadow_map_second_depth") : nullptr;
        renderer_.render(ctx, ctx.lightView(), ctx.texture("shadow_map"), ctx.texture("shadow_map_zbuffer"), second);
    }

private:
    ShadowMapRenderer renderer_;
};
}  // namespace

PassDesc shadowMapPass() {
    PassDesc p;
    p.name = "shadow_map";
    p.doc = "light-view depth of the casters from the light's centre (techniques/core/visibility/shadow_map.h)";
    p.reads = {"scene.casters", "light", "param:sm_size", "param:second_depth"};
    p.creates = {
        ResourceDesc::texture("shadow_map", Format::R32F, SizeRule::shadowMap(),
                              "light-view depth z of the nearest caster per texel (world units; FLT_MAX = no caster)"),
        ResourceDesc::texture("shadow_map_zbuffer", Format::DEPTH32F, SizeRule::shadowMap(),
                              "reversed-depth z-buffer of the shadow-map render (scratch)"),
        ResourceDesc::texture("shadow_map_second_depth", Format::R32F, SizeRule::shadowMap(),
                              "light-view depth of the second-nearest caster surface (second-depth shadow mapping)"),
    };
    p.creates[2].appliesWhen = "second_depth == 1";
    p.state = PipelineState::depthGreaterReversed();
    p.create = [] { return std::make_unique<ShadowMapPass>(); };
    return p;
}

void farMarkerToInfinity(Image& image) {
    for (float& z : image.data)
        if (z > 1e30f) z = INFINITY;
}

std::vector<InternalDesc> shadowMapInternals() {
    InternalDesc first;
    first.name = "shadow_map";
    first.kind = InternalDesc::Kind::Image;
    first.resource = "shadow_map";
    first.channels = {"depth"};
    first.doc = "light-view depth z of the nearest caster per texel (world units; inf = no caster)";
    first.convert = farMarkerToInfinity;
    InternalDesc second = first;
    second.name = "shadow_map_second_depth";
    second.resource = "shadow_map_second_depth";
    second.doc = "light-view depth of the second-nearest caster surface (second-depth option; inf = none)";
    second.appliesWhen = "second_depth == 1";
    return {first, second};
}

std::string shadowTestMap(PassContext& ctx) {
    return ctx.paramBool("second_depth") ? "shadow_map_second_depth" : "shadow_map";
}

std::vector<std::string> shadowTestReads() { return {"shadow_map", "shadow_map_second_depth", "param:second_depth"}; }

void setShadowLookupUniforms(const ShaderProgram& program, const LightView& view, int size, const Light& light) {
    program.set("lightViewFromWorld", view.viewFromWorld);
    program.set("lightClipFromView", view.clipFromView);
    program.set("lightTanHalfFov", view.tanHalfFov);
    program.set("shadowMapSize", float(size));
    program.set("lightPosition", light.position);
}

void setLightFrontUniforms(const ShaderProgram& program, const Light& light) {
    program.set("frontLightShape", light.isPoint() ? int(LightShape::Point) : int(light.shape));
    program.set("frontLightCentre", light.position);
    program.set("frontLightRight", light.isPoint() ? glm::vec3(0.0f) : light.right());
    program.set("frontLightUp", light.up);
    program.set("frontLightSize", light.isPoint() ? 0.0f : light.size);
}

}  // namespace shadowlab
