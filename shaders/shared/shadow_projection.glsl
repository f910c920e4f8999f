// Shadow-map projection and depth comparison, shared by every shadow-map technique and tested on
// the CPU. Shadow maps store the light-view depth z (distance along the light's axis, world units),
// so biases can be stated in world units of one shadow-map texel.
#ifndef SHADOWLAB_SHADOW_PROJECTION_GLSL
#define SHADOWLAB_SHADOW_PROJECTION_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// Projects a world point into the shadow map of a light: returns (u, v, z, inside) with (u, v) in
// [0,1]^2 texture coordinates, z the light-view depth (> 0 in front of the light) and inside 1 when
// the point lies in the light's frustum (0 otherwise; such points are treated as lit).
SHARED_FN vec4 shadowMapCoord(mat4 lightViewFromWorld, mat4 lightClipFromView, vec3 worldPos) {
    vec4 view = lightViewFromWorld * vec4(worldPos, 1.0f);
    vec4 clip = lightClipFromView * view;
    float z = -view.z;
    if (clip.w <= 0.0f) {
        return vec4(0.0f, 0.0f, z, 0.0f);
    }
    vec2 ndc = vec2(clip.x, clip.y) / clip.w;
    vec2 uv = ndc * 0.5f + vec2(0.5f, 0.5f);
    float inside = (uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f) ? 1.0f : 0.0f;
    return vec4(uv.x, uv.y, z, inside);
}

// World size of one shadow-map texel at light-view depth z, for a symmetric frustum of half-angle
// atan(tanHalfFov) and smSize texels across.
SHARED_FN float shadowTexelWorldSize(float z, float tanHalfFov, float smSize) {
    return 2.0f * z * tanHalfFov / smSize;
}

// Depth bias in world units: a constant part and a slope-scaled part (tan of the angle between the
// receiver normal and the direction to the light, clamped at 10), both in texels of the shadow map
// at the receiver: bias = texelWorld * (constTexels + slopeTexels * min(tan(theta), 10)).
SHARED_FN float shadowDepthBias(float texelWorld, float constTexels, float slopeTexels, float cosTheta) {
    float c = clamp(cosTheta, 1e-4f, 1.0f);
    float tanTheta = min(sqrt(max(1.0f - c * c, 0.0f)) / c, 10.0f);
    return texelWorld * (constTexels + slopeTexels * tanTheta);
}

// Extra bias of a PCF sample offsetTexels away from the receiver's own texel: a tilted receiver's
// depth changes by tan(theta) per world unit across the kernel (receiver-plane depth bias).
SHARED_FN float receiverPlaneBias(float texelWorld, float cosTheta, float offsetTexels) {
    float c = clamp(cosTheta, 1e-4f, 1.0f);
    float tanTheta = min(sqrt(max(1.0f - c * c, 0.0f)) / c, 10.0f);
    return texelWorld * tanTheta * offsetTexels;
}

// Williams 1978: a receiver at light depth z is lit when no stored occluder depth lies in front of
// it by more than the bias. Returns 1 (lit) or 0 (in shadow).
SHARED_FN float shadowDepthTest(float receiverZ, float storedZ, float bias) {
    return (receiverZ - bias <= storedZ) ? 1.0f : 0.0f;
}

#endif
