// Closed-form visibility of the `square-occluder` scene (DESIGN.md section 5): a square light and a
// square occluder plate, both parallel to the floor and centred on the y axis. The test oracle for
// every technique, used by the tests and by `shadowlab reference --closed-form`.
#ifndef SHADOWLAB_SQUARE_OCCLUDER_GLSL
#define SHADOWLAB_SQUARE_OCCLUDER_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// Length of the intersection of [a0, a1] and [b0, b1] (0 when they do not overlap).
SHARED_FN float intervalOverlap(float a0, float a1, float b0, float b1) {
    return max(0.0f, min(a1, b1) - max(a0, b0));
}

// Visibility of the square light (centre height lightY, width lightWidth) seen from receiver point
// p below an occluder square of half size occluderHalf at height occluderY (p.y < occluderY < lightY).
// Back-projection: the ray from p through an occluder point o meets the light plane at
// p + s (o - p) with s = (lightY - p.y) / (occluderY - p.y), so the occluder covers
// [p.x + s(-a - p.x), p.x + s(a - p.x)] x (same in z) on the light plane, and
// v(p) = 1 - |covered part of the light| / w_l^2.
// For the scene of DESIGN.md (a = 0.5, occluderY = 2, lightY = 4, p.y = 0): s = 2 and the covered
// square is [-1 - p.x, 1 - p.x] x [-1 - p.z, 1 - p.z], as DESIGN.md states.
// lightWidth 0 (a point light) gives the hard shadow: 0 inside the occluder's shadow, else 1.
SHARED_FN float squareOccluderVisibility(vec3 p, float occluderHalf, float occluderY, float lightY, float lightWidth) {
    if (p.y >= occluderY) {
        return 1.0f;
    }
    float s = (lightY - p.y) / (occluderY - p.y);
    float x0 = p.x + s * (-occluderHalf - p.x);
    float x1 = p.x + s * (occluderHalf - p.x);
    float z0 = p.z + s * (-occluderHalf - p.z);
    float z1 = p.z + s * (occluderHalf - p.z);
    float h = 0.5f * lightWidth;
    if (lightWidth <= 0.0f) {
        bool inside = x0 <= 0.0f && 0.0f <= x1 && z0 <= 0.0f && 0.0f <= z1;
        return inside ? 0.0f : 1.0f;
    }
    float covered = intervalOverlap(x0, x1, -h, h) * intervalOverlap(z0, z1, -h, h);
    return clamp(1.0f - covered / (lightWidth * lightWidth), 0.0f, 1.0f);
}

#endif
