// Pull-push reconstruction, the push phase (guennebaud2007 sec. 5.2 after Gortler et al. 1996): one
// dispatch per level, from the coarsest up; each texel becomes w v + (1 - w) c, (v, w) its pulled
// texel and c the next coarser, complete level blended bilinearly at its centre (clamped to the
// border). Math: shaders/shared/pull_push.glsl; host: PullPush::run
// (techniques/core/visibility/pull_push.cpp).
//  COARSEST: the 1x1 top level, complete by itself (c = v: with no weight at all, everything is 0);
//  FINAL:    level 0, the frame: (v, w) from the input, the completed v into the R32F output;
//  otherwise: pull-push level k >= 1: (v, w) from the pull pyramid, (completed v, w) into the push
//            pyramid, c from the push pyramid's next level.
layout(local_size_x = 8, local_size_y = 8) in;
#include "../shared/pull_push.glsl"

#ifdef FINAL
uniform sampler2D inputVisibilityWeight;                        // level 0: (v, w) per pixel
layout(r32f, binding = 2) uniform writeonly image2D destination;  // the completed visibility
#else
layout(rg32f, binding = 0) uniform readonly image2D pulled;       // level k of the pull pyramid
layout(rg32f, binding = 2) uniform writeonly image2D destination;  // level k of the push pyramid
#endif
#ifndef COARSEST
layout(rg32f, binding = 1) uniform readonly image2D coarser;  // level k + 1 of the push pyramid, complete
#endif

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(destination);
    if (any(greaterThanEqual(p, size))) return;
#ifdef FINAL
    vec2 texel = texelFetch(inputVisibilityWeight, p, 0).rg;
#else
    vec2 texel = imageLoad(pulled, p).rg;
#endif
#ifdef COARSEST
    float c = texel.x;
#else
    ivec2 coarseSize = imageSize(coarser);
    ivec4 taps = pushTaps(p, coarseSize);
    vec2 f = pushFractions(p, coarseSize);
    float c = pushBilinear(imageLoad(coarser, taps.xy).r, imageLoad(coarser, taps.zy).r, imageLoad(coarser, taps.xw).r,
                           imageLoad(coarser, taps.zw).r, f);
#endif
    float completed = pushBlend(texel, c);
#ifdef FINAL
    imageStore(destination, p, vec4(completed, 0.0, 0.0, 0.0));
#else
    imageStore(destination, p, vec4(completed, texel.y, 0.0, 0.0));
#endif
}
