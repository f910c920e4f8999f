// The visibility convention (DESIGN.md section 5, "Visibility, exactly"): v(p) is the fraction of
// the light's area that p sees through the scene AND in front of p's own tangent plane,
// n . (l - p) > 0. The part of the light behind the plane is hidden by the receiver's own surface:
// for a closed mesh a ray tracer finds that anyway; for an open, single-sided surface (a leaf, a
// plate's side face) it makes the side facing away dark, as an opaque surface is. n is the
// G-buffer's normal, turned towards the camera (shaders/common/gbuffer.frag).
// Both references test it per light sample (inFrontOfTangentPlane); `hard` and `pcf` at the light
// centre; the filtering and back-projection techniques multiply their v by lightFractionInFront.
// Common GLSL/C++ subset: see shaders/shared/shared.h.
#ifndef SHADOWLAB_TANGENT_PLANE_GLSL
#define SHADOWLAB_TANGENT_PLANE_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif
#include "light_sampling.glsl"

// Whether the light point l is strictly in front of the tangent plane through p with normal n.
// A point on the plane is not: it is seen at grazing incidence and contributes nothing.
SHARED_FN bool inFrontOfTangentPlane(vec3 receiver, vec3 normal, vec3 lightPoint) {
    return dot(normal, lightPoint - receiver) > 0.0f;
}

// Fraction of the square [-1,1]^2 where g . x + d > 0: the square clipped by the line
// g . x + d = 0 (one Sutherland-Hodgman step), its area by the shoelace formula over 4.
// Exact up to rounding; g = 0 gives 1 when d > 0 and 0 otherwise.
SHARED_FN float squareFractionInFront(vec2 g, float d) {
    vec2 corners[4];
    corners[0] = vec2(-1.0f, -1.0f);
    corners[1] = vec2(1.0f, -1.0f);
    corners[2] = vec2(1.0f, 1.0f);
    corners[3] = vec2(-1.0f, 1.0f);
    vec2 kept[6];
    int count = 0;
    for (int i = 0; i < 4; ++i) {
        vec2 a = corners[i];
        vec2 b = corners[(i + 1) % 4];
        float fa = dot(g, a) + d;
        float fb = dot(g, b) + d;
        if (fa > 0.0f) {
            kept[count] = a;
            count += 1;
        }
        if ((fa > 0.0f) != (fb > 0.0f)) {
            // The crossing on a-b; fa != fb here, since exactly one of them is > 0.
            float s = fa / (fa - fb);
            kept[count] = a + s * (b - a);
            count += 1;
        }
    }
    float twiceArea = 0.0f;
    for (int i = 0; i < count; ++i) {
        vec2 a = kept[i];
        vec2 b = kept[(i + 1) % count];
        twiceArea += a.x * b.y - a.y * b.x;
    }
    return clamp(0.125f * twiceArea, 0.0f, 1.0f);
}

// Fraction of the unit disk where g . x + d > 0: a circular segment. With the line at signed
// distance k = -d / |g| from the centre along g, the part beyond it has area acos(k) - k sqrt(1 - k^2).
SHARED_FN float diskFractionInFront(vec2 g, float d) {
    float len = length(g);
    if (!(len > 0.0f)) {
        return d > 0.0f ? 1.0f : 0.0f;
    }
    float k = -d / len;
    if (k >= 1.0f) {
        return 0.0f;
    }
    if (k <= -1.0f) {
        return 1.0f;
    }
    const float pi = 3.14159265358979323846f;
    float segment = acos(k) - k * sqrt(max(1.0f - k * k, 0.0f));
    return clamp(segment / pi, 0.0f, 1.0f);
}

// Fraction of the light's area in front of p's tangent plane, exactly, for the light as every
// technique and both references sample it (light_sampling.glsl's lightSampleOffset): a square of
// width `size` spanned by (right, up) around the centre; a disk of radius `size`; a sphere light as
// the disk through its centre facing the light direction (the same disk `reference` and
// `raytraced` sample, so the three agree; a true sphere seen from p would show a slightly different
// cap near its terminator); a point light 1 or 0 by its centre.
SHARED_FN float lightFractionInFront(int shape, vec3 centre, vec3 right, vec3 up, float size, vec3 receiver,
                                     vec3 normal) {
    float d = dot(normal, centre - receiver);
    if (shape == LIGHT_SHAPE_SQUARE) {
        float halfWidth = 0.5f * size;
        return squareFractionInFront(vec2(halfWidth * dot(normal, right), halfWidth * dot(normal, up)), d);
    }
    if (shape == LIGHT_SHAPE_DISK || shape == LIGHT_SHAPE_SPHERE) {
        return diskFractionInFront(vec2(size * dot(normal, right), size * dot(normal, up)), d);
    }
    return d > 0.0f ? 1.0f : 0.0f;
}

#endif
