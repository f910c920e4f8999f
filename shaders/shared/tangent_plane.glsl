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
// g . x + d = 0, its area by Green's theorem over the clipped boundary, divided by 4. The boundary
// is the kept part of each edge a -> b (from a, or from the crossing where the edge enters the
// half-plane, to b, or to the crossing where it leaves) and the chord along the line from the exit
// crossing back to the entry crossing; the sum of their cross products is twice the area (the
// shoelace formula of the Sutherland-Hodgman polygon, the same points in the same order). No
// local arrays: a SIMD CPU (llvmpipe) spills dynamically indexed arrays to memory, and every pixel
// of the filtering and back-projection passes runs this. Exact up to rounding; g = 0 gives 1 when
// d > 0 and 0 otherwise.
SHARED_FN float squareFractionInFront(vec2 g, float d) {
    float twiceArea = 0.0f;
    vec2 exitPoint = vec2(0.0f, 0.0f);
    vec2 entryPoint = vec2(0.0f, 0.0f);
    for (int i = 0; i < 4; ++i) {
        // Corners counter-clockwise from (-1, -1): corner k is (k == 1 or 2 ? 1 : -1, k >= 2 ? 1 : -1).
        int j = (i + 1) % 4;
        vec2 a = vec2((i == 1 || i == 2) ? 1.0f : -1.0f, i >= 2 ? 1.0f : -1.0f);
        vec2 b = vec2((j == 1 || j == 2) ? 1.0f : -1.0f, j >= 2 ? 1.0f : -1.0f);
        float fa = dot(g, a) + d;
        float fb = dot(g, b) + d;
        bool inA = fa > 0.0f;
        bool inB = fb > 0.0f;
        // The crossing on a-b (used only when exactly one end is in front: then fa != fb).
        float den = fa - fb;
        vec2 crossing = a + (den != 0.0f ? fa / den : 0.0f) * (b - a);
        vec2 from = inA ? a : crossing;
        vec2 to = inB ? b : crossing;
        if (inA || inB) twiceArea += from.x * to.y - from.y * to.x;
        if (inA && !inB) exitPoint = crossing;
        if (!inA && inB) entryPoint = crossing;
    }
    twiceArea += exitPoint.x * entryPoint.y - exitPoint.y * entryPoint.x;
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
