// HSM level 1 from the shadow map (hsm.comp's FIRST_LEVEL as a full-screen draw over the level's
// texels): its (min, max) into the pyramid's mip level 0 and, with MIN_LEVELS (light_multires), its
// min into the second layer of the `depth_levels` atlas, whose level 1 starts at x = 0
// (hsmLevelAtlasX), so both targets share the texel coordinates. The largest level, a quarter of
// the map's texels: llvmpipe writes a fragment shader's outputs a block at a time, a compute
// shader's imageStore lane by lane. The coarser levels stay compute dispatches (hsm.comp). The four
// map texels come from one textureGather, not hsm_reduce.glsl's loop of four fetches: on plant at
// 384x384 with ssm-gbp06 (sm_size 1024) the hsm pass went from 8.4-9.5 to 4.8-6.3 ms.
uniform sampler2D shadowMap;  // light-view depth z (R32F)
layout(location = 0) out vec2 range;
#ifdef MIN_LEVELS
layout(location = 1) out float minDepth;
#endif

void main() {
    // The level-1 texel p covers the map's texels 2p .. 2p + 1 (hsm_reduce.glsl's rule: a map of odd
    // size has (size + 1) / 2 level-1 texels, the last covering the map's last texel alone), all four
    // in one gather at their shared corner; past an odd map's last row or column the clamp to the
    // edge (every texture's wrap mode, gl/texture.cpp) repeats that texel, which changes no min or max.
    vec2 sourceSize = vec2(textureSize(shadowMap, 0));
    vec4 z = textureGather(shadowMap, (2.0 * floor(gl_FragCoord.xy) + 1.0) / sourceSize);
    // The min starts from hsm_reduce.glsl's 3.4e38, as the coarser levels (hsm.comp) do: a texel
    // with no caster keeps that value, not the map's FLT_MAX marker.
    range = vec2(min(min(min(z.x, z.y), min(z.z, z.w)), 3.4e38), max(max(z.x, z.y), max(z.z, z.w)));
#ifdef MIN_LEVELS
    minDepth = range.x;
#endif
}
