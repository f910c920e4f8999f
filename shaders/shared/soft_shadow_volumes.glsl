// Soft shadow volumes (assarsson2004, "Visibility calculations", "Fragment shaders"): the signed
// coverage of one silhouette edge seen from the point to be shaded, the math shared by
// shaders/ssv/wedge.frag and the C++ per-pixel record and tests. Common GLSL/C++ subset (see
// shaders/shared/shared.h).
//
// Frames are those of backprojection.glsl: the light frame has the light centre at the origin, x
// the light's right, y its up and z the depth along the light's direction (positive in front of
// it); light coordinates are the light plane scaled so that the square light is [-1,1]^2 and the
// disk light the unit disk. A receiver p and an edge x0 -> x1 are given in the light frame.
//
// The slides' "projection space" (p at the origin, the light centre on the z axis at z = 1: a
// shear and a scale) followed by the perspective divide x/z, y/z is, written in the light frame,
// the central projection from p onto the light plane z = 0:
//   q = (x z_p - p z_x) / (z_p - z_x),
// a projective map whose homogeneous coordinates (x z_p - p z_x, z_p - z_x) are linear along the
// edge. As the slides do, the edge is clipped in homogeneous space first, then divided.
#ifndef SHADOWLAB_SOFT_SHADOW_VOLUMES_GLSL
#define SHADOWLAB_SOFT_SHADOW_VOLUMES_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif
#include "backprojection.glsl"

// Relative margin of the homogeneous clip: the part of the edge kept has z_p - z_x >= SSV_W_MIN z_p,
// so no projected point is farther than 1 / SSV_W_MIN light-frame depths from the centre (finite
// in float), and a point of the edge at the receiver's own depth (an edge of the receiver's own
// face) is not divided by zero.
const float SSV_W_MIN = 1e-5f;

// The part of the range (s0, s1) where f0 + s (f1 - f0) >= 0 (one linear constraint).
SHARED_FN vec2 ssvClipLinear(vec2 range, float f0, float f1) {
    if (f0 >= 0.0f && f1 >= 0.0f) {
        return range;
    }
    if (f0 < 0.0f && f1 < 0.0f) {
        return vec2(1.0f, 0.0f);
    }
    float s = f0 / (f0 - f1);  // the crossing, in (0, 1]
    if (f0 < 0.0f) {
        return vec2(max(range.x, s), range.y);
    }
    return vec2(range.x, min(range.y, s));
}

// The part of edge x0 -> x1 that can occlude the light from p: between the light plane and p,
// i.e. 0 <= z and z <= (1 - SSV_W_MIN) z_p (the slides' homogeneous clip against the near side),
// and in front of p's tangent plane (normal n, the side the visibility convention counts; DESIGN.md
// section 5): a point behind that plane can only hide light behind it, which v does not count,
// and an edge of p's own face (in the plane) would project onto the plane's horizon by rounding.
// Pass n = 0 to skip the plane.
SHARED_FN vec2 ssvOccludingRange(vec3 p, vec3 n, vec3 x0, vec3 x1) {
    vec2 range = vec2(0.0f, 1.0f);
    float zMax = (1.0f - SSV_W_MIN) * p.z;
    range = ssvClipLinear(range, zMax - x0.z, zMax - x1.z);
    range = ssvClipLinear(range, x0.z, x1.z);
    float margin = SSV_W_MIN * p.z;
    if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) {
        range = ssvClipLinear(range, dot(n, x0 - p) - margin, dot(n, x1 - p) - margin);
    }
    return range;
}

// The central projection from p of the light-frame point x onto the light plane, in light
// coordinates (lightHalfSize: w_l / 2 for a square, r for a disk or sphere). Needs x.z < p.z.
SHARED_FN vec2 ssvProjectToLight(vec3 p, vec3 x, float lightHalfSize) {
    float s = 1.0f / ((p.z - x.z) * lightHalfSize);
    return vec2((x.x * p.z - p.x * x.z) * s, (x.y * p.z - p.y * x.z) * s);
}

// The projected, clipped edge (n: p's tangent-plane normal in the light frame, see above) (a.x, a.y, b.x, b.y) in light coordinates; all zero
// when no part of the edge lies between the light plane and p (then it covers nothing), cut to
// the square [-2, 2]^2 around the light.
SHARED_FN vec4 ssvProjectedEdge(vec3 p, vec3 n, vec3 x0, vec3 x1, float lightHalfSize) {
    vec2 range = ssvOccludingRange(p, n, x0, x1);
    if (range.x >= range.y) {
        return vec4(0.0f);
    }
    vec3 d = x1 - x0;
    vec2 a = ssvProjectToLight(p, x0 + d * range.x, lightHalfSize);
    vec2 b = ssvProjectToLight(p, x0 + d * range.y, lightHalfSize);
    // A part of the edge near p's depth projects very far (up to 1 / SSV_W_MIN), where the disk
    // clip's quadratic loses every digit to cancellation. The segment is straight, so cutting it
    // to the square [-2, 2]^2 (which holds the square light and the disk) first, by the linear
    // Liang-Barsky clip, changes nothing the light clip keeps.
    vec2 keep = clipSegmentToSquare(0.5f * a, 0.5f * b);
    if (keep.x > keep.y) {
        return vec4(0.0f);
    }
    vec2 ab = b - a;
    vec2 ka = a + ab * keep.x;
    vec2 kb = a + ab * keep.y;
    return vec4(ka.x, ka.y, kb.x, kb.y);
}

// The edge's signed coverage ("coverage", the slides' dark grey region, added to or subtracted
// from the V-buffer): the occluded light area, in light coordinates (the square's area is 4, the
// disk's pi), that the oriented silhouette edge x0 -> x1 (the face that faces the light centre on
// its left, seen from the light) adds to the hard shadow's count times the light area. The same
// radial integration as the contour method (backprojection.glsl, edgeOccludedArea): the projected
// edge is clipped to the light, and the area beyond it as seen from the light centre counts
// positive where the edge turns clockwise about the centre (the occluder entered) and negative
// where it turns counter-clockwise. An edge that does not reach the light covers nothing.
SHARED_FN float ssvEdgeCoverage(int shape, vec3 p, vec3 n, vec3 x0, vec3 x1, float lightHalfSize) {
    vec4 e = ssvProjectedEdge(p, n, x0, x1, lightHalfSize);
    if (e.x == 0.0f && e.y == 0.0f && e.z == 0.0f && e.w == 0.0f) {
        return 0.0f;
    }
    return edgeOccludedArea(shape, vec2(e.x, e.y), vec2(e.z, e.w));
}

// The V-buffer resolved (the slides' "additive - subtractive = shadow mask"): the hard pass's
// count of shadow volumes containing p, each worth the whole light, plus the wedges' signed
// coverages, as a visibility in [0, 1] (clamped: overlapping occluders can add up to more than
// the light, the over-darkening the slides name).
// A sum below zero is not an occlusion: it means that the hard pass missed a volume the wedges
// account for. On a hard shadow's boundary the side quad of an edge passes within rounding of p,
// and the rasterizer's depth test (hard_volumes) and the wedge shader's exact side of the light
// centre (the coverage's sign) can disagree: the count is then one short and the edge's coverage
// -A/2 where it should be +A/2 with the count, v = 1 where the exact value is 1/2 (square-occluder
// at 1024x1024, pixel 352,436). Whole lights are added back until the sum is above -A/4 (a
// rounding residue of a true 0 is far smaller).
SHARED_FN float ssvVisibility(float hardCount, float coverageSum, int shape) {
    float area = bpLightArea(shape);
    float occluded = hardCount * area + coverageSum;
    occluded += area * max(0.0f, ceil(-occluded / area - 0.25f));
    return bpVisibility(occluded, shape);
}

#endif
