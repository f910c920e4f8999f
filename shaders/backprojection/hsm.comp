// guennebaud2007 sec. 3 (after GBP06): the hierarchical shadow map (HSM), "built from high to low
// resolution in a similar fashion to mipmapped textures. Each pixel stores both the minimum and
// maximum covered depth values." One dispatch per level from level 2 on. HSM level 0 is the shadow map itself (min =
// max = the stored depth), read in place; the pyramid texture holds HSM levels 1, 2, ... as its mip
// levels 0, 1, ..., so a 8192^2 map needs no 512 MB copy of itself.
// Level 1 comes from the shadow map by a full-screen draw (hsm_first.frag; the no-caster marker
// FLT_MAX stays, so an empty texel never lowers a max below "far"); here HSM level k from level k-1.
// Texel p covers the 2x2 texels below it, widened on a level's last row or column when the level
// below has an odd size, so no texel is left out (the rule tests/core/test_gpu_features.cpp checks for
// tests/minmax_pyramid.comp).
layout(local_size_x = 8, local_size_y = 8) in;
layout(rg32f, binding = 1) uniform writeonly image2D destination;  // level k
#ifdef MIN_LEVELS
// light_multires: the min depths again, into the second layer of the `depth_levels` atlas at
// x = atlasX (hsmLevelAtlasX: the levels side by side; its first layer is the shadow map itself),
// so the visibility walk reads any level with one fetch at level of detail 0 (visibility_common.glsl).
layout(r32f, binding = 2) uniform writeonly image2D minDestination;
uniform int atlasX;
#endif
layout(rg32f, binding = 0) uniform readonly image2D source;  // level k - 1

vec2 sourceTexel(ivec2 t) { return imageLoad(source, t).rg; }

#include "hsm_reduce.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 destinationSize = imageSize(destination);
    if (any(greaterThanEqual(p, destinationSize))) return;
    ivec2 sourceSize = imageSize(source);
    vec2 range = hsmReduce(p, destinationSize, sourceSize);
    imageStore(destination, p, vec4(range, 0.0, 0.0));
#ifdef MIN_LEVELS
    imageStore(minDestination, p + ivec2(atlasX, 0), vec4(range.x, 0.0, 0.0, 0.0));
#endif
}
