// BASELINE for benchmarks/fixed_cost.cpp: the combine pass as it was before core stage two (a loop
// over MAX_LIGHTS = 8 that llvmpipe runs in full). Not used by the renderer.
// The frame's visibility buffer v (DESIGN.md section 3): the fraction of the direct light that
// reaches the pixel, v = sum_l v_l E_l / sum_l E_l with E_l the unshadowed direct light of light l.
// With one light v is that light's visibility exactly. Background and objects that receive no
// shadows get v = 1.
#include "../common/gbuffer_access.glsl"
#include "legacy_lights.glsl"
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 n = texelFetch(gNormal, pixel, 0);
    if (isBackground(pixel) || n.w == 0.0 || lightCount == 0) {
        visibility = 1.0;
        return;
    }
    vec3 p = worldPosition(pixel);
    float weighted = 0.0, weights = 0.0, plain = 0.0;
    // A constant bound lets the compiler unroll the loop, so each sampler is indexed by a constant
    // (dynamic sampler-array indexing is slow on llvmpipe).
    for (int i = 0; i < MAX_LIGHTS; ++i) {
        if (i >= lightCount) break;
        float v = lightVisibilityAt(i, pixel);
        float e = directWeight(i, p, n.xyz);
        weighted += v * e;
        weights += e;
        plain += v;
    }
    // A receiver facing away from every light: the plain mean keeps v defined.
    visibility = weights > 0.0 ? weighted / weights : plain / float(lightCount);
}
