// HSM level 1 from the shadow map (hsm.comp's FIRST_LEVEL as a full-screen draw over the level's
// texels): its (min, max) into the pyramid's mip level 0 and, with MIN_LEVELS (light_multires), its
// min into the second layer of the `depth_levels` atlas, whose level 1 starts at x = 0
// (hsmLevelAtlasX), so both targets share the texel coordinates. The largest level, a quarter of
// the map's texels: llvmpipe writes a fragment shader's outputs a block at a time, a compute
// shader's imageStore lane by lane. The coarser levels stay compute dispatches (hsm.comp).
uniform sampler2D shadowMap;  // light-view depth z (R32F)
layout(location = 0) out vec2 range;
#ifdef MIN_LEVELS
layout(location = 1) out float minDepth;
#endif

vec2 sourceTexel(ivec2 t) { return vec2(texelFetch(shadowMap, t, 0).r); }
#include "hsm_reduce.glsl"

void main() {
    ivec2 sourceSize = textureSize(shadowMap, 0);
    range = hsmReduce(ivec2(gl_FragCoord.xy), (sourceSize + 1) / 2, sourceSize);
#ifdef MIN_LEVELS
    minDepth = range.x;
#endif
}
