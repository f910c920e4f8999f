// Light-view depth maps (Williams 1978) shared by the shadow-map techniques: R32F textures holding
// the light-view depth z of the nearest caster, or of the second-nearest (Wang and Molnar 1994's
// second-depth shadow mapping: the back faces of closed occluders, so that a lit surface never
// shadows itself and needs almost no bias).
#pragma once
#include <map>

#include "graph/frame.h"

namespace shadowlab {

// Renders the casters into depth maps, keeping one framebuffer per set of target textures.
class ShadowMapRenderer {
public:
    // Renders from `view` into `first` (and the second-nearest layer into `second` when given);
    // `zbuffer` is the DEPTH32F scratch of the same size.
    void render(PassContext& ctx, const LightView& view, const Texture& first, const Texture& zbuffer,
                const Texture* second);

private:
    const Framebuffer& framebuffer(const Texture& color, const Texture& depth);
    std::map<std::pair<GLuint, GLuint>, Framebuffer> fbos_;
};

// The pass that renders the light-centre shadow map, as every shadow-map technique declares it:
// creates "shadow_map", "shadow_map_zbuffer" and, with second_depth = 1, "shadow_map_second_depth".
PassDesc shadowMapPass();
// Their internals (the second depth only when second_depth = 1).
std::vector<InternalDesc> shadowMapInternals();
// Name of the map the depth tests read: the second depth layer when second_depth = 1.
std::string shadowTestMap(PassContext& ctx);
// Resources a depth-test pass reads: both maps (the second only exists with second_depth = 1).
std::vector<std::string> shadowTestReads();

// Binds the uniforms of shaders/common/shadow_lookup.glsl for `view` and a map of `size` texels.
void setShadowLookupUniforms(const ShaderProgram& program, const LightView& view, int size, const Light& light);
// The light as shaders/common/light_front.glsl clips it by the receiver's tangent plane (the
// visibility convention, shaders/shared/tangent_plane.glsl): shape, centre, axes and size.
void setLightFrontUniforms(const ShaderProgram& program, const Light& light);

// Raw light-view depth -> exported values (the "no caster" marker FLT_MAX becomes +inf).
void farMarkerToInfinity(Image& image);

}  // namespace shadowlab
