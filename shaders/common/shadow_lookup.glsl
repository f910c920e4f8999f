// Shadow-map look-up shared by hard, pcf and reference: projection and biased depth test from
// shaders/shared/shadow_projection.glsl (the same functions the C++ tests run).
#ifndef SHADOWLAB_SHADOW_LOOKUP_GLSL
#define SHADOWLAB_SHADOW_LOOKUP_GLSL
#include "../shared/backprojection.glsl"
#include "../shared/shadow_projection.glsl"

uniform sampler2D shadowMap;      // light-view depth z (R32F)
uniform mat4 lightViewFromWorld;
uniform mat4 lightClipFromView;
uniform float lightTanHalfFov;
uniform float shadowMapSize;      // texels across
uniform vec3 lightPosition;       // where this shadow map was rendered from
uniform float biasConstTexels;
uniform float biasSlopeTexels;

// cos of the angle between the receiver normal and the direction to the light.
float cosToLight(vec3 worldPos, vec3 normal) {
    return abs(dot(normal, normalize(lightPosition - worldPos)));
}

// What a receiver's depth tests share: its projection into the map and its bias.
struct ShadowReceiver {
    vec4 coord;        // shadowMapCoord: (u, v, z, inside)
    float texelWorld;  // world size of one texel at the receiver's depth
    float cosTheta;    // receiver normal vs direction to the light
    float bias;        // constant + slope bias, world units
};

ShadowReceiver prepareShadowReceiver(vec3 worldPos, vec3 normal) {
    ShadowReceiver r;
    r.coord = shadowMapCoord(lightViewFromWorld, lightClipFromView, worldPos);
    r.texelWorld = shadowTexelWorldSize(r.coord.z, lightTanHalfFov, shadowMapSize);
    r.cosTheta = cosToLight(worldPos, normal);
    r.bias = shadowDepthBias(r.texelWorld, biasConstTexels, biasSlopeTexels, r.cosTheta);
    return r;
}

// Hard visibility (0 or 1) of a receiver at texel offset `offset` (PCF). The bias grows with the
// offset along the receiver's slope, since a tilted receiver's depth changes across the kernel (a
// receiver-plane bias). Receivers outside the light's frustum are lit.
float shadowTestOffset(ShadowReceiver r, vec2 offset) {
    if (r.coord.w == 0.0) return 1.0;
    float bias = r.bias + receiverPlaneBias(r.texelWorld, r.cosTheta, length(offset));
    ivec2 texel = ivec2(floor(r.coord.xy * shadowMapSize + offset));
    int last = int(shadowMapSize) - 1;
    texel = clamp(texel, ivec2(0), ivec2(last));
    float stored = texelFetch(shadowMap, texel, 0).r;
    return shadowDepthTest(r.coord.z, stored, bias);
}

float shadowTest(vec3 worldPos, vec3 normal) {
    return shadowTestOffset(prepareShadowReceiver(worldPos, normal), vec2(0.0));
}

// The tangent-plane depth test (`plane_test`; the reference's default): the stored depth is
// compared with the receiver's tangent plane where the tested texel's ray meets it
// (backprojection.glsl's receiverPlaneDepth), not with the receiver's own depth. The receiver's
// own surface in that texel is then within rounding of the plane, so a tilted or grazing receiver
// needs no slope bias, and a caster just above it (a contact) is not hidden by one. The plane's
// depth is kept within the bias of the receiver's own (a plane nearly along the ray would put it
// far behind p), and is p's own depth when the ray misses the plane in front of the light.
float shadowTestPlane(vec3 worldPos, vec3 normal) {
    BpReceiver r = bpReceiver(lightViewFromWorld, lightClipFromView, worldPos, normal, lightPosition, lightTanHalfFov,
                              shadowMapSize, biasConstTexels, biasSlopeTexels);
    if (r.inside == 0.0) return 1.0;  // outside the light's frustum: lit
    int last = int(shadowMapSize) - 1;
    ivec2 texel = clamp(ivec2(floor(r.centre)), ivec2(0), ivec2(last));
    float stored = texelFetch(shadowMap, texel, 0).r;
    float zPlane = receiverPlaneDepth(r.normal, r.position, vec2(texel) + 0.5, shadowMapSize, lightTanHalfFov);
    float zTest = zPlane < BP_FAR ? min(zPlane, r.position.z + r.bias) : r.position.z;
    return stored >= zTest - r.bias ? 1.0 : 0.0;
}
#endif
