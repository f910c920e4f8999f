// PCSS step 2, percentage-closer filtering with the kernel of step 1 (Fernando 2005; buades2015
// sec. 2): the weighted fraction of depth tests that pass over a kernel as wide as the penumbra of
// eq. 1. Regular pattern: every texel of the kernel, box weights with fractional edge taps
// (kernelWeight, so the kernel widens and moves continuously); Poisson: POISSON_COUNT taps in a disk.
#include "../common/gbuffer_access.glsl"
#include "../common/light_front.glsl"
#include "pcss_common.glsl"
uniform sampler2D blockers;  // (z_avg, count, search width, kernel) of blocker_search
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    // No blocker (and background): "considered as being totally illuminated" (buades2015 sec.
    // 4.2): discarded here (see blocker_search.frag); the pass gives them the light's fraction in
    // front of their tangent plane (common/light_front.frag), the background its clear value 1.
    vec4 b = texelFetch(blockers, pixel, 0);
    if (b.x < 0.0) discard;
    ShadowReceiver receiver = prepareShadowReceiver(worldPosition(pixel), worldNormal(pixel));
    TapPlane plane = tapPlane(receiver, worldPosition(pixel), worldNormal(pixel));
    float kernel = b.w;
    if (pattern == PATTERN_POISSON) {
        float lit = 0.0;
        for (int i = 0; i < POISSON_COUNT; ++i) lit += shadowTestTap(receiver, plane, poissonDisk[i] * (0.5 * kernel));
        visibility = lit / float(POISSON_COUNT) * lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
        return;
    }
    // The box is centred on the receiver's own position in the map, not on its texel's centre: tap
    // (dx, dy) reads the texel whose centre lies (dx, dy) - f from the receiver (f: its offset from
    // its texel's centre) and weighs it by the share of that texel's cell inside the box. Centred
    // on the texel, every pixel within one texel read the same taps with the same weights: where a
    // tilted light spreads a 512^2 map's texels over many pixels of the floor, the penumbra and the
    // lit floor around it showed a grid of texel-sized squares. One more tap on each side covers the
    // shifted box.
    vec2 f = fract(receiver.coord.xy * shadowMapSize) - 0.5;
    int r = kernelRadius(kernel) + 1;
    float lit = 0.0, weights = 0.0;
    for (int dy = -r; dy <= r; ++dy) {
        float wy = kernelWeight(float(dy) - f.y, kernel, FILTER_MEAN, 1.0);
        for (int dx = -r; dx <= r; ++dx) {
            float w = wy * kernelWeight(float(dx) - f.x, kernel, FILTER_MEAN, 1.0);
            if (w > 0.0) lit += w * shadowTestTap(receiver, plane, vec2(dx, dy));
            weights += w;
        }
    }
    // Float rounding of the weights can pass 1 by an ulp. The visibility convention: times the
    // fraction of the light in front of the receiver's tangent plane (light_front.glsl).
    visibility = clamp(lit / weights, 0.0, 1.0) * lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
}
