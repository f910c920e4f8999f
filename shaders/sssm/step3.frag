// SSSM step 3 (buades2015 sec. 4.2, Table 1 "Step3"): the vertical blur. Row t of the m x m kernel
// reuses the horizontal blur of step 2 at (x, y + t) when that pixel's camera depth, adjusted by
// this pixel's normal (its tangent plane), is within beta; otherwise the row is filtered again from
// the hard shadows, and from the shadow map where the screen does not show this surface. Pixels
// without a penumbra are discarded: the pass's first draw (keep_hard.frag) gave them the hard shadow.
#include "sssm_blur.glsl"
#include "../common/light_front.glsl"
uniform sampler2D penumbras;    // step 2: (z_avg, w_penumbra)
uniform sampler2D kernels;      // step 2: kernel width in x and y (pixels)
uniform sampler2D horizontals;  // step 2: horizontal blur
layout(location = 0) out float visibility;
layout(location = 1) out float reuse;  // fraction of the rows taken from step 2 (-1: no filtering)

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (texelFetch(penumbras, pixel, 0).y <= 0.0) discard;  // "soft_shadow_value = hard_shadow_value"
    Surface s = withLightLookups(surfaceAt(pixel, texelFetch(hardShadows, pixel, 0).r));
    vec2 k = texelFetch(kernels, pixel, 0).xy;
    float kx = k.x, ky = k.y;
    int ry = kernelRadius(ky);
    float sum = 0.0, weights = 0.0;
    int reused = 0;
    uvec4 missed = uvec4(0u);  // rows filtered again after the loop (see blurRow)
    for (int t = -ry; t <= ry; ++t) {
        float w = kernelWeight(float(t), ky, filterKind, sigma);
        weights += w;
        ivec2 q = pixel + ivec2(0, t);
        bool ok = false;
        if (onScreen(q)) {
            if (showsSurface(s, q, texelFetch(hardShadows, q, 0).g, beta)) {
                sum += w * texelFetch(horizontals, q, 0).r;
                ok = true;
                ++reused;
            }
        }
        if (!ok) missed = markBit(missed, t + ry);
    }
    while (any(notEqual(missed, uvec4(0u)))) {
        int t = takeLowestBit(missed) - ry;
        sum += kernelWeight(float(t), ky, filterKind, sigma) * blurRow(s, pixel + ivec2(0, t), kx);
    }
    // Float rounding of the weights can pass 1 by an ulp; times the light's fraction in front of
    // the receiver's tangent plane (the visibility convention, common/light_front.glsl).
    visibility = clamp(sum / weights, 0.0, 1.0) * lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
    reuse = float(reused) / float(2 * ry + 1);
}
