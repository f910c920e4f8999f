// pvm, pass visibility (cournia2005 sec. 4.2, Listing 4.2, computeLightVisibility): a receiver behind
// the nearest penumbra volume in the PVDM is inside a volume and sees the light through the cutting
// plane of that volume's edge (intersectLight: eq. 4.1-4.2, v = 3k^2 - 2k^3); any other receiver takes
// the shadow-map test (umbra 0, lit 1). With split_sides (README.md, "Sides kept apart") the outer
// and the inner volumes have maps of their own: a receiver the shadow-map test says lit reads the
// outer maps, any other the inner ones, and the value stays on its side of 1/2 (pvmSideVisibility).
// Times the fraction of the light in front of the receiver's tangent plane (the visibility
// convention, shared/tangent_plane.glsl), as the other soft techniques.
#include "../common/gbuffer_access.glsl"
#include "../common/shadow_lookup.glsl"
#include "../shared/tangent_plane.glsl"
#include "../shared/penumbra_volumes.glsl"
uniform sampler2D volumeDepthMap;  // PVDM: light-view z of the nearest volume (FLT_MAX: none)
uniform sampler2D edgeMap0;        // PVEM: h0.xyz, edge index + 1
uniform sampler2D edgeMap1;        // PVEM: h1.xyz, side + 1
uniform sampler2D innerDepthMap;   // split_sides: the inner volumes' PVDM (the maps above: the outer)
uniform sampler2D innerEdgeMap0;
uniform sampler2D innerEdgeMap1;
uniform int splitSides;            // 1: outer and inner volumes in maps of their own
uniform float lightRadius;         // r of the disk (pvmLightRadius)
uniform int frontShape;            // LIGHT_SHAPE_* of the light
uniform vec3 lightRight;
uniform vec3 lightUp;
uniform float lightSize;           // square: width; disk and sphere: radius
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    visibility = 1.0;
    if (isBackground(pixel)) return;
    vec3 p = worldPosition(pixel);
    vec3 n = worldNormal(pixel);
    float front = lightFractionInFront(frontShape, lightPosition, lightRight, lightUp, lightSize, p, n);
    if (front == 0.0) {
        visibility = 0.0;
        return;
    }
    ShadowReceiver receiver = prepareShadowReceiver(p, n);
    if (receiver.coord.w == 0.0) {  // outside the light's frustum: lit, as the shadow-map techniques
        visibility = front;
        return;
    }
    ivec2 texel = clamp(ivec2(floor(receiver.coord.xy * shadowMapSize)), ivec2(0), ivec2(int(shadowMapSize) - 1));
    // Not in a volume: umbra where the shadow map says shadowed, else lit (lines 22-25).
    float centre = shadowTestOffset(receiver, vec2(0.0));
    bool inner = splitSides != 0 && centre < 0.5;
    float vd = inner ? texelFetch(innerDepthMap, texel, 0).r : texelFetch(volumeDepthMap, texel, 0).r;
    float v = centre;
    if (vd < receiver.coord.z) {
        // In a penumbra volume (Listing 4.2, line 15): intersectLight.
        vec3 h0 = inner ? texelFetch(innerEdgeMap0, texel, 0).xyz : texelFetch(edgeMap0, texel, 0).xyz;
        vec3 h1 = inner ? texelFetch(innerEdgeMap1, texel, 0).xyz : texelFetch(edgeMap1, texel, 0).xyz;
        v = pvmVisibility(p, h0, h1, lightPosition, lightRadius);
        if (splitSides != 0) v = pvmSideVisibility(v, centre);
    }
    visibility = v * front;
}
