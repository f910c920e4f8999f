// Light-view depth maps (Williams 1978) shared by the shadow-map techniques: R32F textures holding
// the light-view depth z of the nearest caster, or of the second-nearest (Wang and Molnar 1994's
// second-depth shadow mapping: the back faces of closed occluders, so that a lit surface never
// shadows itself and needs almost no bias).
#pragma once
#include "renderer.h"

namespace shadowlab {

class ShadowMap {
public:
    // Renders the casters of ctx.scene from `view` into a size x size map.
    void render(RenderContext& ctx, const LightView& view, int size, bool secondDepth);
    const Texture& depth() const { return secondDepth_ ? second_ : first_; }
    const Texture& firstDepth() const { return first_; }
    bool usesSecondDepth() const { return secondDepth_; }
    int size() const { return size_; }
    void appendBuffers(std::vector<std::pair<std::string, const Texture*>>& out, const std::string& prefix) const;

private:
    void allocate(int size, bool secondDepth);
    int size_ = 0;
    bool secondDepth_ = false;
    Texture first_, second_, depthBuffer_;
    Framebuffer firstFbo_, secondFbo_;
};

// Binds the uniforms of shaders/common/shadow_lookup.glsl for `view` and a map of `size` texels.
void setShadowLookupUniforms(const ShaderProgram& program, const LightView& view, int size, const Light& light);

}  // namespace shadowlab
