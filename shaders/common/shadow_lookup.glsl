// Shadow-map look-up shared by hard, pcf and reference: projection and biased depth test from
// shaders/shared/shadow_projection.glsl (the same functions the C++ tests run).
#ifndef SHADOWLAB_SHADOW_LOOKUP_GLSL
#define SHADOWLAB_SHADOW_LOOKUP_GLSL
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

// Hard visibility (0 or 1) of a receiver from the shadow map's viewpoint, with texel offset
// `offset` (PCF). The bias grows with the offset along the receiver's slope, since a tilted
// receiver's depth changes across the kernel (a receiver-plane bias).
float shadowTestOffset(vec3 worldPos, vec3 normal, vec2 offset) {
    vec4 coord = shadowMapCoord(lightViewFromWorld, lightClipFromView, worldPos);
    if (coord.w == 0.0) return 1.0;  // outside the light's frustum
    float texelWorld = shadowTexelWorldSize(coord.z, lightTanHalfFov, shadowMapSize);
    float cosTheta = cosToLight(worldPos, normal);
    float bias = shadowDepthBias(texelWorld, biasConstTexels, biasSlopeTexels, cosTheta) +
                 receiverPlaneBias(texelWorld, cosTheta, length(offset));
    ivec2 texel = ivec2(floor(coord.xy * shadowMapSize + offset));
    int last = int(shadowMapSize) - 1;
    texel = clamp(texel, ivec2(0), ivec2(last));
    float stored = texelFetch(shadowMap, texel, 0).r;
    return shadowDepthTest(coord.z, stored, bias);
}

float shadowTest(vec3 worldPos, vec3 normal) {
    return shadowTestOffset(worldPos, normal, vec2(0.0));
}
#endif
