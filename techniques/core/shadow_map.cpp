#include "shadow_map.h"

#include <cfloat>

namespace shadowlab {

void ShadowMap::allocate(int size, bool secondDepth) {
    if (size == size_ && secondDepth == secondDepth_ && first_) return;
    size_ = size;
    secondDepth_ = secondDepth;
    first_ = Texture(size, size, GL_R32F);
    depthBuffer_ = Texture(size, size, GL_DEPTH_COMPONENT32F);
    firstFbo_ = Framebuffer({&first_}, &depthBuffer_);
    if (secondDepth) {
        second_ = Texture(size, size, GL_R32F);
        secondFbo_ = Framebuffer({&second_}, &depthBuffer_);
    } else {
        second_ = Texture();
        secondFbo_ = Framebuffer();
    }
}

void ShadowMap::render(RenderContext& ctx, const LightView& view, int size, bool secondDepth) {
    allocate(size, secondDepth);
    const float farValue = FLT_MAX;  // no caster: lit
    const float zero = 0.0f;
    // Reversed depth (see fitLightView): depth 1 at the near plane, keep the greatest.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);  // open meshes and single quads cast from both sides
    glDisable(GL_BLEND);

    const ShaderProgram& program = ctx.programs.get("common/shadow_depth.vert", "common/shadow_depth.frag");
    program.use();
    program.set("lightViewFromWorld", view.viewFromWorld);
    program.set("lightClipFromView", view.clipFromView);
    program.set("peel", 0);
    firstFbo_.bind(size, size);
    glClearNamedFramebufferfv(firstFbo_.id(), GL_COLOR, 0, &farValue);
    glClearNamedFramebufferfv(firstFbo_.id(), GL_DEPTH, 0, &zero);
    ctx.gpu.draw(program, ctx.time, true);

    if (secondDepth) {
        // Second pass: the nearest surface strictly behind the first one (depth peeling).
        program.set("peel", 1);
        glBindTextureUnit(0, first_.id());
        program.set("firstDepth", 0);
        secondFbo_.bind(size, size);
        glClearNamedFramebufferfv(secondFbo_.id(), GL_COLOR, 0, &farValue);
        glClearNamedFramebufferfv(secondFbo_.id(), GL_DEPTH, 0, &zero);
        ctx.gpu.draw(program, ctx.time, true);
    }
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void ShadowMap::appendBuffers(std::vector<std::pair<std::string, const Texture*>>& out,
                              const std::string& prefix) const {
    if (first_) out.push_back({prefix + "shadow_map", &first_});
    if (depthBuffer_) out.push_back({prefix + "shadow_map_zbuffer", &depthBuffer_});
    if (second_) out.push_back({prefix + "shadow_map_second_depth", &second_});
}

void setShadowLookupUniforms(const ShaderProgram& program, const LightView& view, int size, const Light& light) {
    program.set("lightViewFromWorld", view.viewFromWorld);
    program.set("lightClipFromView", view.clipFromView);
    program.set("lightTanHalfFov", view.tanHalfFov);
    program.set("shadowMapSize", float(size));
    program.set("lightPosition", light.position);
}

}  // namespace shadowlab
