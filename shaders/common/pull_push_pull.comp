// Pull-push reconstruction, the pull phase (guennebaud2007 sec. 5.2 after Gortler et al. 1996): one
// dispatch per level, level k + 1 from level k, each texel the weighted mean of the 2x2 fine texels
// it covers (the last row and column also take an odd level's left-over texels), its weight the
// saturated sum min(1, sum w_i). Math: shaders/shared/pull_push.glsl; host: PullPush::run
// (techniques/core/visibility/pull_push.cpp).
//  FIRST_LEVEL: pull level 1 from the frame-size (v, w) input (RG32F, sampled by texelFetch);
//  otherwise:   pull level k + 1 from pull level k (both mip levels of the "pull" pyramid).
layout(local_size_x = 8, local_size_y = 8) in;
#include "../shared/pull_push.glsl"

layout(rg32f, binding = 1) uniform writeonly image2D destination;  // level k + 1: (v', w')
#ifdef FIRST_LEVEL
uniform sampler2D inputVisibilityWeight;  // level 0: (v, w) per pixel
#else
layout(rg32f, binding = 0) uniform readonly image2D source;  // level k: (v, w)
#endif

vec2 sourceTexel(ivec2 t) {
#ifdef FIRST_LEVEL
    return texelFetch(inputVisibilityWeight, t, 0).rg;
#else
    return imageLoad(source, t).rg;
#endif
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 destinationSize = imageSize(destination);
    if (any(greaterThanEqual(p, destinationSize))) return;
#ifdef FIRST_LEVEL
    ivec2 sourceSize = textureSize(inputVisibilityWeight, 0);
#else
    ivec2 sourceSize = imageSize(source);
#endif
    ivec4 block = pullBlock(p, destinationSize, sourceSize);
    vec2 sums = vec2(0.0f);
    for (int y = block.y; y <= block.w; ++y)
        for (int x = block.x; x <= block.z; ++x) sums = pullAccumulate(sums, sourceTexel(ivec2(x, y)));
    imageStore(destination, p, vec4(pullResult(sums), 0.0, 0.0));
}
