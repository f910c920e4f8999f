// The screen-space blur of SSSM's steps 2 and 3 (buades2015 sec. 4.2, partial_soft_shadow).
#ifndef SHADOWLAB_SSSM_BLUR_GLSL
#define SHADOWLAB_SSSM_BLUR_GLSL
#include "sssm_common.glsl"
uniform sampler2D hardShadows;  // step 1: (hard shadow, camera depth; -1 on background)
uniform float beta;             // reuse threshold (camera depth, world units)
uniform int filterKind;         // FILTER_GAUSSIAN or FILTER_MEAN
uniform float sigma;            // Gaussian sigma over the kernel's half-width

// The weighted mean of the surface's hard shadow over the row of pixels centre + (i, 0), |i| <= the
// kernel's radius: step 1's value where the pixel shows this surface (beta), else the shadow map
// on the surface's tangent plane. The shadow-map taps are gathered in a bit set and taken after
// the row (takeLowestBit).
float blurRow(Surface s, ivec2 centre, float width) {
    int r = kernelRadius(width);
    float sum = 0.0, weights = 0.0;
    uvec4 missed = uvec4(0u);
    for (int i = -r; i <= r; ++i) {
        float w = kernelWeight(float(i), width, filterKind, sigma);
        weights += w;
        ivec2 q = centre + ivec2(i, 0);
        bool ok = false;
        if (onScreen(q)) {
            vec2 hd = texelFetch(hardShadows, q, 0).rg;
            if (showsSurface(s, q, hd.y, beta)) {
                sum += w * hd.x;
                ok = true;
            }
        }
        if (!ok) missed = markBit(missed, i + r);
    }
    while (any(notEqual(missed, uvec4(0u)))) {
        int i = takeLowestBit(missed) - r;
        sum += kernelWeight(float(i), width, filterKind, sigma) * hardShadowOnPlane(s, centre + ivec2(i, 0));
    }
    return clamp(sum / weights, 0.0, 1.0);
}
#endif
