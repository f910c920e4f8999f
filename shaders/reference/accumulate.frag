// reference: adds one light sample's weighted hard visibility (additive blending into R32F).
// Two departures from a plain depth test, both for exactness (techniques/reference/README.md):
//  - the visibility convention (shaders/shared/tangent_plane.glsl): a sample behind the receiver's
//    tangent plane is hidden by the receiver's own surface;
//  - with plane_test = 1 (the default), the tangent-plane depth test of shadow_lookup.glsl.
#include "../common/gbuffer_access.glsl"
#include "../common/shadow_lookup.glsl"
#include "../shared/tangent_plane.glsl"
uniform float sampleWeight;  // area of the sample's stratum on the light (the weights sum to 1)
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (isBackground(pixel)) {
        visibility = sampleWeight;
        return;
    }
    vec3 p = worldPosition(pixel);
    vec3 n = worldNormal(pixel);
    // lightPosition is this sample, where its shadow map was rendered from.
    if (!inFrontOfTangentPlane(p, n, lightPosition)) {
        visibility = 0.0;
        return;
    }
#ifdef PLANE_TEST
    visibility = sampleWeight * shadowTestPlane(p, n);
#else
    visibility = sampleWeight * shadowTest(p, n);
#endif
}
