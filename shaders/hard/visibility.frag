// hard: one biased depth test per pixel (Williams 1978).
// pcf (defined PCF): the mean of the tests over an n x n texel kernel centred on the receiver's
// texel (Reeves et al. 1987, percentage-closer filtering).
#include "../common/gbuffer_access.glsl"
#include "../common/shadow_lookup.glsl"
#include "../shared/tangent_plane.glsl"
#ifdef PCF
uniform int pcfKernel;  // n, odd (the parameter table enforces it)
#endif
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (isBackground(pixel)) {
        visibility = 1.0;
        return;
    }
    vec3 p = worldPosition(pixel);
    vec3 n = worldNormal(pixel);
    // The visibility convention at the light centre (tangent_plane.glsl): a receiver facing away
    // from it is in its own shadow, whatever the map says.
    if (!inFrontOfTangentPlane(p, n, lightPosition)) {
        visibility = 0.0;
        return;
    }
#ifdef PCF
    ShadowReceiver receiver = prepareShadowReceiver(p, n);
    int radius = pcfKernel / 2;
    float lit = 0.0;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) lit += shadowTestOffset(receiver, vec2(dx, dy));
    // (2r + 1)^2 taps were taken: n^2 for the odd n the table accepts, and never more than taken.
    float taps = float((2 * radius + 1) * (2 * radius + 1));
    visibility = lit / taps;
#elif defined(PLANE_TEST)
    visibility = shadowTestPlane(p, n);  // plane_test = 1 (shadow_lookup.glsl)
#else
    visibility = shadowTest(p, n);
#endif
}
