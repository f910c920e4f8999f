// What the PCSS passes share: the light's size, the search caps and the sampling pattern.
#ifndef SHADOWLAB_PCSS_COMMON_GLSL
#define SHADOWLAB_PCSS_COMMON_GLSL
#include "../common/shadow_lookup.glsl"
#include "../shared/penumbra.glsl"

uniform float lightWidthWorld;  // w_light of eq. 1 (square: its width; disk, sphere: the diameter)
uniform float lightNearZ;       // near plane of the light frustum: the nearest a caster can be
uniform int pattern;            // PATTERN_REGULAR or PATTERN_POISSON
const int POISSON_COUNT = 32;
uniform vec2 poissonDisk[POISSON_COUNT];  // in the unit disk (techniques/pcss/pcss.cpp)

// The stored light-view depth at a texel offset from the receiver's texel (clamped to the map).
float storedDepthOffset(ShadowReceiver r, vec2 offset) {
    ivec2 texel = ivec2(floor(r.coord.xy * shadowMapSize + offset));
    int last = int(shadowMapSize) - 1;
    return texelFetch(shadowMap, clamp(texel, ivec2(0), ivec2(last)), 0).r;
}

// The bias of a tap at `offset` (texels): the receiver's bias plus how much nearer the light the
// receiver's tangent plane is under that tap (a directional receiver-plane bias: taps where the
// plane recedes need none, so blockers there are still found), at most the isotropic
// receiverPlaneBias of shaders/common/shadow_lookup.glsl. On a surface almost parallel to the light
// (a pot's side) the isotropic bias grows to hundreds of texels across a 41-texel kernel and hides
// every blocker; the directional one keeps the half of the kernel that looks away from the surface.
struct TapPlane {
    float invZ0;          // 1 / (the plane's light depth) under the receiver's own position
    vec2 invZPerTexel;    // its change per texel of offset (planeInverseDepth)
    float isoPerTexel;    // receiverPlaneBias per texel of offset: the cap
};

TapPlane tapPlane(ShadowReceiver r, vec3 worldPos, vec3 normal) {
    vec3 p = (lightViewFromWorld * vec4(worldPos, 1.0)).xyz;
    vec3 n = normalize(mat3(lightViewFromWorld) * normal);
    vec3 inv = planeInverseDepth(p, n, r.coord.xy * 2.0 - 1.0, lightTanHalfFov, 1.0);
    TapPlane t;
    t.invZ0 = inv.x;
    t.invZPerTexel = inv.yz * (2.0 / shadowMapSize);  // d ndc / d texel = 2 / size
    t.isoPerTexel = receiverPlaneBias(r.texelWorld, r.cosTheta, 1.0);
    return t;
}

float tapBias(ShadowReceiver r, TapPlane plane, vec2 offset) {
    float isotropic = plane.isoPerTexel * length(offset);
    float invZ = plane.invZ0 + dot(plane.invZPerTexel, offset);
    float extra = invZ <= 0.0 ? isotropic : clamp(r.coord.z - 1.0 / invZ, 0.0, isotropic);
    return r.bias + extra;
}

// Hard visibility of a tap (PCF) with the directional bias; receivers outside the frustum are lit.
float shadowTestTap(ShadowReceiver r, TapPlane plane, vec2 offset) {
    if (r.coord.w == 0.0) return 1.0;
    return shadowDepthTest(r.coord.z, storedDepthOffset(r, offset), tapBias(r, plane, offset));
}
#endif
