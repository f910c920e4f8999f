// guennebaud2007 sec. 3 (after GBP06): the hierarchical shadow map (HSM), "built from high to low
// resolution in a similar fashion to mipmapped textures. Each pixel stores both the minimum and
// maximum covered depth values." One dispatch per level. HSM level 0 is the shadow map itself (min =
// max = the stored depth), read in place; the pyramid texture holds HSM levels 1, 2, ... as its mip
// levels 0, 1, ..., so a 8192^2 map needs no 512 MB copy of itself.
//  FIRST_LEVEL: HSM level 1 from the shadow map (the no-caster marker FLT_MAX stays, so an empty
//               texel never lowers a max below "far").
//  otherwise:   HSM level k from level k-1.
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
#ifdef FIRST_LEVEL
uniform sampler2D shadowMap;  // light-view depth z (R32F)
#else
layout(rg32f, binding = 0) uniform readonly image2D source;  // level k - 1
#endif

vec2 sourceTexel(ivec2 t) {
#ifdef FIRST_LEVEL
    return vec2(texelFetch(shadowMap, t, 0).r);
#else
    return imageLoad(source, t).rg;
#endif
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 destinationSize = imageSize(destination);
    if (any(greaterThanEqual(p, destinationSize))) return;
#ifdef FIRST_LEVEL
    ivec2 sourceSize = textureSize(shadowMap, 0);
#else
    ivec2 sourceSize = imageSize(source);
#endif
    ivec2 lo = 2 * p;
    ivec2 hi = min(2 * p + 1, sourceSize - 1);
    if (p.x == destinationSize.x - 1) hi.x = sourceSize.x - 1;
    if (p.y == destinationSize.y - 1) hi.y = sourceSize.y - 1;
    vec2 range = vec2(3.4e38, -3.4e38);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            vec2 texel = sourceTexel(ivec2(x, y));
            range = vec2(min(range.x, texel.x), max(range.y, texel.y));
        }
    imageStore(destination, p, vec4(range, 0.0, 0.0));
#ifdef MIN_LEVELS
    imageStore(minDestination, p + ivec2(atlasX, 0), vec4(range.x, 0.0, 0.0, 0.0));
#endif
}
