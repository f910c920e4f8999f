// Soft shadow mapping by back-projection (guennebaud2007 sections 3-4; GBP06), the math shared by
// the shaders of `ssm-gbp06` and `ssm-contour` and by the C++ per-pixel records and tests. Common
// GLSL/C++ subset: see shaders/shared/shared.h (no out parameters, no swizzles, f-suffixed floats).
//
// Frames used throughout:
//  - light frame: the light-view axes (x = the light's right, y = its up) with z the DEPTH along
//    the light's axis (positive in front of the light); the light centre is the origin and the
//    light lies in the plane z = 0. A receiver p is (p_x, p_y, z_p).
//  - texel coordinates: shadow-map coordinates in texels, (0,0) the map's lower-left corner, texel
//    (i, j) covering [i, i+1] x [j, j+1] with its sample at the centre (i + 0.5, j + 0.5).
//  - light coordinates: the light plane scaled so that the square light is [-1,1]^2 (unit: half its
//    width w_l / 2) and the disk light the unit disk (unit: its radius). Areas are in these units:
//    the square has area 4, the disk pi.
#ifndef SHADOWLAB_BACKPROJECTION_GLSL
#define SHADOWLAB_BACKPROJECTION_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif
#include "shadow_projection.glsl"

// Light shapes (the numbers of light_sampling.glsl's LIGHT_SHAPE_*): a sphere light is handled as
// the disk through its centre facing the light direction, as `reference` samples it.
const int BP_LIGHT_SQUARE = 1;
const int BP_LIGHT_DISK = 2;
const int BP_LIGHT_SPHERE = 3;
const float BP_PI = 3.14159265358979f;
// Depth standing for "no bound" (the shadow map's no-caster marker is FLT_MAX, larger still).
const float BP_FAR = 1e30f;
// Classification values, chosen so the image reads like a three-level visibility buffer.
const float BP_CLASS_UMBRA = 0.0f;
const float BP_CLASS_PENUMBRA = 0.5f;
const float BP_CLASS_LIT = 1.0f;
// Symbolic perturbation of the light centre (Edelsbrunner and Muecke's simulation of simplicity):
// the centre is taken at epsilon * BP_PERTURBATION, so an edge passing exactly through the centre,
// or ending on it, still has the centre on a definite side. An irrational direction, parallel to
// no edge a shadow map produces in practice.
const vec2 BP_PERTURBATION = vec2(0.9486833f, 0.3162278f);

// ---- 1. the kernel (guennebaud2007 sec. 3, eq. 1; GBP06's "search area") -----------------------

// Light area in light coordinates: 4 for the square [-1,1]^2, pi for the unit disk.
SHARED_FN float bpLightArea(int shape) {
    return shape == BP_LIGHT_SQUARE ? 4.0f : BP_PI;
}

// Width of the light's bounding square in world units: w_l for a square light, 2r for a disk.
SHARED_FN float bpLightWidth(int shape, float size) {
    return shape == BP_LIGHT_SQUARE ? size : 2.0f * size;
}

// guennebaud2007 eq. 1: w_k = w_l (z_n r / w_n) (1/z_min - 1/z_p), the width in texels of the
// projection onto the shadow map of the pyramid (light, p) cut at depth z_min. The near plane's
// width is w_n = 2 z_n tan(half fov), so z_n cancels: w_k = w_l r / (2 tan) (1/z_min - 1/z_p).
SHARED_FN float hsmKernelTexels(float lightWidth, float smSize, float tanHalfFov, float zMin, float zReceiver) {
    return lightWidth * smSize / (2.0f * tanHalfFov) * (1.0f / zMin - 1.0f / zReceiver);
}

// guennebaud2007 sec. 3: the HSM level whose texels make the kernel "just below one pixel",
// floor(log2(w_k)), clamped to [0, topLevel]. At that level the kernel spans one to two texels, so
// it overlaps at most 3 x 3 of them.
SHARED_FN int hsmRefinementLevel(float kernelTexels, int topLevel) {
    if (kernelTexels < 2.0f) {
        return 0;
    }
    return min(int(floor(log2(kernelTexels))), topLevel);
}

// Texels across HSM level `level` of a map smSize texels across: level 0 is the map, level 1 has
// ceil(smSize / 2) texels and each further level half the one before, rounded down (the mip chain of
// the pyramid texture that holds levels 1, 2, ...).
SHARED_FN int hsmLevelSize(int level, int smSize) {
    if (level == 0) {
        return smSize;
    }
    return max(1, ((smSize + 1) / 2) >> (level - 1));
}

// Where HSM level `level` >= 1 starts in the second layer of the `depth_levels` atlas: the levels
// 1, 2, ... side by side along x from 0 (level k at x = n_1 + ... + n_(k-1), y = 0), so that the
// visibility walk reads any level with a fetch at level of detail 0 (a mip level chosen per pixel
// costs llvmpipe a per-lane mip offset and stride on every fetch). With h = ceil(N / 2), n_j =
// h >> (j - 1) up to the top level, and sum_(i >= 0) floor(x / 2^i) = 2 x - popcount(x), the sum of
// the first m = level - 1 sizes is 2 h - popcount(h) - (2 (h >> m) - popcount(h >> m)). The levels
// fit in N x N: their widths sum to at most 2 h - 1 <= N (the top level's 1 included) and each is at
// most h high (tests/techniques/test_light_levels.cpp checks every N up to 8192). Level 0 (the map) is
// the first layer; 0 is returned for it.
SHARED_FN int hsmLevelAtlasX(int level, int smSize) {
    if (level <= 1) {
        return 0;
    }
    int h = (smSize + 1) / 2;
    int rest = h >> (level - 1);
    return 2 * h - bitCount(h) - (2 * rest - bitCount(rest));
}

// Level-0 texels overlapped by a kernel of width kernelTexels centred at `centre` (texel
// coordinates): (x0, y0, x1, y1), inclusive, clamped to the map [0, smSize - 1].
SHARED_FN ivec4 kernelTexelRange(vec2 centre, float kernelTexels, int smSize) {
    float h = 0.5f * kernelTexels;
    int last = smSize - 1;
    int x0 = clamp(int(floor(centre.x - h)), 0, last);
    int y0 = clamp(int(floor(centre.y - h)), 0, last);
    int x1 = clamp(int(floor(centre.x + h)), 0, last);
    int y1 = clamp(int(floor(centre.y + h)), 0, last);
    return ivec4(x0, y0, x1, y1);
}

// The texels of HSM level `level` (levelSize texels across) covering a level-0 range. A level's last
// texel also covers the left-over level-0 texels of an odd size (see hsm.comp), hence the clamp.
SHARED_FN ivec4 levelTexelRange(ivec4 range0, int level, int levelSize) {
    int last = levelSize - 1;
    return ivec4(min(range0.x >> level, last), min(range0.y >> level, last), min(range0.z >> level, last),
                 min(range0.w >> level, last));
}

// ---- 2. which samples occlude -------------------------------------------------------------------

// Light-frame direction (depth-normalised: z = 1) of the ray from the light centre through texel
// coordinates `texel` of a map of smSize texels with half-angle atan(tanHalfFov).
SHARED_FN vec3 texelRay(vec2 texel, float smSize, float tanHalfFov) {
    float nx = texel.x / smSize * 2.0f - 1.0f;
    float ny = texel.y / smSize * 2.0f - 1.0f;
    return vec3(nx * tanHalfFov, ny * tanHalfFov, 1.0f);
}

// The receiver's normal in the light frame, turned to face the light centre (two-sided surfaces
// receive light on the side the light is on).
SHARED_FN vec3 receiverNormalTowardLight(vec3 normalLight, vec3 receiver) {
    return dot(normalLight, receiver) > 0.0f ? -normalLight : normalLight;
}

// Depth, along the ray through `texel`, of the receiver's tangent plane (n . (x - p) = 0):
// BP_FAR when the ray never meets the plane in front of the light.
SHARED_FN float receiverPlaneDepth(vec3 normalLight, vec3 receiver, vec2 texel, float smSize, float tanHalfFov) {
    vec3 d = texelRay(texel, smSize, tanHalfFov);
    float nd = dot(normalLight, d);
    float np = dot(normalLight, receiver);
    if (nd >= 0.0f || np >= 0.0f) {
        return BP_FAR;
    }
    return np / nd;
}

// A shadow-map sample of depth zSample occludes the receiver at depth zReceiver when it is nearer to
// the light than the receiver by the bias (guennebaud2007 sec. 3: "occluding samples, i.e. samples
// s for which z_s < z_p") and is not a sample of the receiver's own surface, i.e. not within the
// bias of the receiver's tangent plane along its ray (zPlane). The second condition replaces the
// ever-growing bias a tilted receiver would need across a wide kernel; occluders behind the plane
// (the rest of a closed object, seen at its terminator) still count. On p's own ray the plane depth
// is z_p, so there this is exactly `hard`'s depth test.
SHARED_FN bool sampleOccludes(float zSample, float zReceiver, float zPlane, float bias) {
    return zSample < zReceiver - bias && abs(zSample - zPlane) > bias;
}

// What every per-pixel step needs to know of the receiver p.
struct BpReceiver {
    float inside;   // 1 when p is in the light's frustum; outside it is lit (as for `hard`)
    vec3 position;  // light frame (x, y, z_p)
    vec3 normal;    // light frame, facing the light centre
    vec2 centre;    // p', p's projection into the shadow map, in texel coordinates (the kernel's centre)
    float bias;     // depth bias in world units (`hard`'s: constant + slope, in texels at p)
};

SHARED_FN BpReceiver bpReceiver(mat4 lightViewFromWorld, mat4 lightClipFromView, vec3 worldPos, vec3 worldNormal,
                                vec3 lightPosition, float tanHalfFov, float smSize, float biasConst, float biasSlope) {
    BpReceiver r;
    vec4 coord = shadowMapCoord(lightViewFromWorld, lightClipFromView, worldPos);
    vec4 view = lightViewFromWorld * vec4(worldPos, 1.0f);
    r.inside = coord.w;
    r.position = vec3(view.x, view.y, -view.z);
    vec3 n = mat3(lightViewFromWorld) * worldNormal;
    r.normal = receiverNormalTowardLight(vec3(n.x, n.y, -n.z), r.position);
    r.centre = vec2(coord.x, coord.y) * smSize;
    float texelWorld = shadowTexelWorldSize(coord.z, tanHalfFov, smSize);
    float cosTheta = abs(dot(worldNormal, normalize(lightPosition - worldPos)));
    r.bias = shadowDepthBias(texelWorld, biasConst, biasSlope, cosTheta);
    return r;
}

// Whether the sample of depth zSample at texel coordinates texelCentre occludes the receiver.
SHARED_FN bool bpSampleOccludes(BpReceiver r, vec2 texelCentre, float zSample, float smSize, float tanHalfFov) {
    if (zSample >= r.position.z - r.bias) {
        return false;  // the plane test below only adds a condition
    }
    float zPlane = receiverPlaneDepth(r.normal, r.position, texelCentre, smSize, tanHalfFov);
    return sampleOccludes(zSample, r.position.z, zPlane, r.bias);
}

// The level-0 texel-coordinate rectangle (x0, y0, x1, y1) that a level range covers.
SHARED_FN vec4 levelRegionTexels(ivec4 rangeL, int level, int levelSize, int smSize) {
    float x1 = rangeL.z == levelSize - 1 ? float(smSize) : float((rangeL.z + 1) << level);
    float y1 = rangeL.w == levelSize - 1 ? float(smSize) : float((rangeL.w + 1) << level);
    return vec4(float(rangeL.x << level), float(rangeL.y << level), x1, y1);
}

// The nearest depth of the receiver's tangent plane over a rectangle of the map: 1 / depth is
// linear across the map, so it is at a corner.
SHARED_FN float regionPlaneDepthMin(BpReceiver r, vec4 region, float smSize, float tanHalfFov) {
    float z = receiverPlaneDepth(r.normal, r.position, vec2(region.x, region.y), smSize, tanHalfFov);
    z = min(z, receiverPlaneDepth(r.normal, r.position, vec2(region.z, region.y), smSize, tanHalfFov));
    z = min(z, receiverPlaneDepth(r.normal, r.position, vec2(region.x, region.w), smSize, tanHalfFov));
    z = min(z, receiverPlaneDepth(r.normal, r.position, vec2(region.z, region.w), smSize, tanHalfFov));
    return z;
}

// guennebaud2007 sec. 3: "the comparison of the depth of p with the depth bounds of the optimized
// kernel" (bounds = HSM (min, max) over it): lit when no sample can occlude, umbra when every
// sample does (conservatively, by the nearest plane depth over the region), else penumbra.
SHARED_FN float bpClassify(BpReceiver r, vec2 bounds, float planeDepthMin) {
    if (bounds.x >= r.position.z - r.bias) {
        return BP_CLASS_LIT;
    }
    if (bounds.y < min(r.position.z, planeDepthMin) - r.bias) {
        return BP_CLASS_UMBRA;
    }
    return BP_CLASS_PENUMBRA;
}

// ---- 3. back-projection onto the light ------------------------------------------------------------

// The point at texel coordinates `texel` and light-frame depth `depth`, back-projected from the
// receiver (x, y, z_p) onto the light plane, in light coordinates (lightHalfSize: w_l / 2 or r).
// The ray from p through q = (x_q, y_q, z) meets z = 0 at p + (q - p) z_p / (z_p - z), which is
// (q z_p - p z) / (z_p - z). Needs depth < z_p (occluding samples only).
SHARED_FN vec2 backprojectToLight(vec3 receiver, vec2 texel, float depth, float smSize, float tanHalfFov,
                                  float lightHalfSize) {
    vec3 d = texelRay(texel, smSize, tanHalfFov);
    float qx = d.x * depth;
    float qy = d.y * depth;
    float s = 1.0f / ((receiver.z - depth) * lightHalfSize);
    return vec2((qx * receiver.z - receiver.x * depth) * s, (qy * receiver.z - receiver.y * depth) * s);
}

// ---- 4. clipping to the light (parametric: the kept part of a + s (b - a) is s in [s0, s1]) ------

// One slab -1 <= p + s d <= 1 of Liang-Barsky clipping, applied to the range (s0, s1).
SHARED_FN vec2 clipSlab(vec2 range, float p, float d) {
    if (d == 0.0f) {
        return abs(p) > 1.0f ? vec2(1.0f, 0.0f) : range;
    }
    float sa = (-1.0f - p) / d;
    float sb = (1.0f - p) / d;
    return vec2(max(range.x, min(sa, sb)), min(range.y, max(sa, sb)));
}

// The part of segment a-b inside the light square [-1,1]^2, as (s0, s1); empty when s0 > s1.
// Points exactly on the border are inside.
SHARED_FN vec2 clipSegmentToSquare(vec2 a, vec2 b) {
    vec2 range = vec2(0.0f, 1.0f);
    range = clipSlab(range, a.x, b.x - a.x);
    range = clipSlab(range, a.y, b.y - a.y);
    return range;
}

// The part of segment a-b inside the unit disk, as (s0, s1); empty when s0 > s1.
SHARED_FN vec2 clipSegmentToDisk(vec2 a, vec2 b) {
    vec2 d = b - a;
    float qa = dot(d, d);
    float qb = dot(a, d);  // half the linear coefficient
    float qc = dot(a, a) - 1.0f;
    if (qa == 0.0f) {
        return qc > 0.0f ? vec2(1.0f, 0.0f) : vec2(0.0f, 1.0f);
    }
    float disc = qb * qb - qa * qc;
    if (disc < 0.0f) {
        return vec2(1.0f, 0.0f);
    }
    float root = sqrt(disc);
    return vec2(max(0.0f, (-qb - root) / qa), min(1.0f, (-qb + root) / qa));
}

SHARED_FN vec2 clipSegmentToLight(int shape, vec2 a, vec2 b) {
    return shape == BP_LIGHT_SQUARE ? clipSegmentToSquare(a, b) : clipSegmentToDisk(a, b);
}

// ---- 5. radial area integration (guennebaud2007 sec. 4.2, Fig. 5a) --------------------------------

SHARED_FN float cross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Which way the light centre sees edge a -> b turn: > 0 counter-clockwise (the centre on the edge's
// left), < 0 clockwise. Exactly 0 (the edge's line through the centre) is decided by the perturbed
// centre epsilon * BP_PERTURBATION: cross(a - e, b - e) = cross(a, b) + epsilon cross(b - a, e).
SHARED_FN float edgeTurn(vec2 a, vec2 b) {
    float turn = cross2(a, b);
    if (turn == 0.0f) {
        turn = cross2(b - a, BP_PERTURBATION);
    }
    return turn;
}

// Position of the direction d on the square's border, walking counter-clockwise from the corner
// (1, -1): the right side x = 1 is [0, 2), the top [2, 4), the left [4, 6), the bottom [6, 8).
// Every side is at distance 1 from the centre, so the light area swept from the centre between two
// border positions is half the border length between them.
SHARED_FN float squareBorderPosition(vec2 d) {
    float ax = abs(d.x);
    float ay = abs(d.y);
    if (ax >= ay) {
        float y = d.y / ax;
        return d.x > 0.0f ? y + 1.0f : 5.0f - y;
    }
    float x = d.x / ay;
    return d.y > 0.0f ? 3.0f - x : 7.0f + x;
}

// Signed light area swept by the ray from the centre as it turns from direction a to direction b,
// the way `turn` says (counter-clockwise positive; half the light when a and b are opposite). A
// zero direction (an end point on the centre) is the direction from the perturbed centre, -e.
SHARED_FN float radialSweep(int shape, vec2 a, vec2 b, float turn) {
    vec2 da = (a.x == 0.0f && a.y == 0.0f) ? -BP_PERTURBATION : a;
    vec2 db = (b.x == 0.0f && b.y == 0.0f) ? -BP_PERTURBATION : b;
    if (shape == BP_LIGHT_SQUARE) {
        float ds = squareBorderPosition(db) - squareBorderPosition(da);
        if (ds > 4.0f) ds -= 8.0f;
        if (ds <= -4.0f) ds += 8.0f;  // now in (-4, 4]: the shorter way round
        // Rounding may put ds on the wrong side of 0 (near 0) or of +-4 (near-opposite directions).
        if (turn > 0.0f && ds < 0.0f) ds = ds < -2.0f ? ds + 8.0f : 0.0f;
        if (turn <= 0.0f && ds > 0.0f) ds = ds > 2.0f ? ds - 8.0f : 0.0f;
        return 0.5f * ds;
    }
    float angle = atan(cross2(da, db), dot(da, db));  // (-pi, pi]
    if (turn > 0.0f && angle < 0.0f) angle = angle < -0.5f * BP_PI ? angle + 2.0f * BP_PI : 0.0f;
    if (turn <= 0.0f && angle > 0.0f) angle = angle > 0.5f * BP_PI ? angle - 2.0f * BP_PI : 0.0f;
    return 0.5f * angle;  // unit disk: a sector of angle theta has area theta / 2
}

// The occluded light area an oriented contour edge a -> b contributes (light coordinates, the
// occluder on the edge's LEFT), to be added to the initial area (the full light when the centre
// is occluded, zero otherwise). Going out from the centre along a ray, crossing such an edge
// leaves the occluder when the edge turns counter-clockwise and enters it when it turns clockwise;
// the part of the light beyond the crossing, inside the wedge of the edge, is
// sweep - triangle(centre, a', b') for the edge a'-b' clipped to the light. So the contribution is
// triangle - sweep: negative (light uncovered) for counter-clockwise edges, positive for clockwise
// ones (Fig. 5a's blue and red edges). Parts outside the light contribute nothing; an edge on the
// light border contributes zero; an edge through the centre half the light, on the side the
// perturbed centre decides (consistently with contourCentreOccluded / rectCentreOccluded).
SHARED_FN float edgeOccludedArea(int shape, vec2 a, vec2 b) {
    vec2 range = clipSegmentToLight(shape, a, b);
    if (range.x > range.y) {
        return 0.0f;
    }
    float turn = edgeTurn(a, b);
    vec2 d = b - a;
    vec2 ca = a + d * range.x;
    vec2 cb = a + d * range.y;
    return 0.5f * cross2(ca, cb) - radialSweep(shape, ca, cb, turn);
}

// ---- 6. the 2x2 contour rule table (guennebaud2007 sec. 4.1, Fig. 3-4) ---------------------------
// A block is 2x2 samples around a shared corner, the block centre. Samples are numbered counter-
// clockwise: 0 (-1/2, -1/2), 1 (+1/2, -1/2), 2 (+1/2, +1/2), 3 (-1/2, +1/2) in the block's frame
// (texel units); side k joins sample k to sample k + 1 (mod 4). Mask bit k is 1 when sample k
// occludes. Each edge runs from the crossing of an "exit" side (sample k occluder, k + 1 not) to
// the crossing of an "entry" side (k not, k + 1 occluder), which puts the occluder on its LEFT.

// Sample k's position in the block frame.
SHARED_FN vec2 contourSamplePosition(int k) {
    float x = (k == 1 || k == 2) ? 0.5f : -0.5f;
    float y = (k >= 2) ? 0.5f : -0.5f;
    return vec2(x, y);
}

// The rule table: (number of edges, exit side of the first edge, entry side of the first edge).
// The second edge of the two-edge (saddle) masks 5 and 10 is the first's central symmetry (negated
// coordinates, sides and holders + 2). Saddles join the two occluders through the block centre
// (the diagonal a thin rasterised line leaves); masks 0 and 15 have no edge.
SHARED_FN ivec3 contourRule(int mask) {
    switch (mask) {
        case 1: return ivec3(1, 0, 3);   // occluder 0
        case 2: return ivec3(1, 1, 0);   // occluder 1
        case 3: return ivec3(1, 1, 3);   // occluders 0, 1 (bottom row)
        case 4: return ivec3(1, 2, 1);   // occluder 2
        case 5: return ivec3(2, 0, 1);   // occluders 0, 2 (saddle)
        case 6: return ivec3(1, 2, 0);   // occluders 1, 2 (right column)
        case 7: return ivec3(1, 2, 3);   // all but 3
        case 8: return ivec3(1, 3, 2);   // occluder 3
        case 9: return ivec3(1, 0, 2);   // occluders 0, 3 (left column)
        case 10: return ivec3(2, 1, 2);  // occluders 1, 3 (saddle)
        case 11: return ivec3(1, 1, 2);  // all but 2
        case 12: return ivec3(1, 3, 1);  // occluders 2, 3 (top row)
        case 13: return ivec3(1, 0, 1);  // all but 1
        case 14: return ivec3(1, 3, 0);  // all but 0
        default: return ivec3(0, -1, -1);  // 0 and 15: no edge
    }
}

// The extremity on side `side` whose occluding sample is `occluder` (one of the side's two ends),
// for the global parameter t in [-1, 1]: on the segment between the two samples' centres,
// midpoint + t (occluder - other) / 2, i.e. the samples' shared border for t = 0, the occluder's
// centre for t = 1 (shrunk contour) and the other sample's centre for t = -1 (grown contour).
SHARED_FN vec2 contourCrossing(int side, int occluder, float t) {
    int other = occluder == side ? (side + 1) % 4 : side;
    vec2 o = contourSamplePosition(occluder);
    vec2 q = contourSamplePosition(other);
    return 0.5f * (o + q) + 0.5f * t * (o - q);
}

// Edge `which` (0 or 1) of mask `mask`: (a.x, a.y, b.x, b.y) in the block frame, a -> b with the
// occluder on the left. Only valid for which < contourRule(mask).x.
SHARED_FN vec4 contourEdge(int mask, float t, int which) {
    ivec3 rule = contourRule(mask);
    int exitSide = rule.y;
    int entrySide = rule.z;
    vec2 a = contourCrossing(exitSide, exitSide, t);
    vec2 b = contourCrossing(entrySide, (entrySide + 1) % 4, t);
    if (which == 1) {
        a = -a;
        b = -b;
    }
    return vec4(a.x, a.y, b.x, b.y);
}

// The samples holding edge `which`'s extremities (their depths give the edge its 3D position).
SHARED_FN ivec2 contourEdgeHolders(int mask, int which) {
    ivec3 rule = contourRule(mask);
    ivec2 holders = ivec2(rule.y, (rule.z + 1) % 4);
    if (which == 1) {
        holders = ivec2((holders.x + 2) % 4, (holders.y + 2) % 4);
    }
    return holders;
}

// Whether edge `which` of the mask has zero length in the shadow map (t = 1 shrinks a lone
// occluder to its centre, t = -1 grows three occluders over the fourth sample's centre). Such an
// edge still joins two depths and is integrated, but it bounds no area of the block.
SHARED_FN bool contourEdgeDegenerate(int mask, float t, int which) {
    vec4 e = contourEdge(mask, t, which);
    return e.x == e.z && e.y == e.w;
}

// Hard shadow from the light centre with the contour (Fig. 5b): whether the light centre is inside
// the occluder region of the block around the receiver's projection p'. `turn0` and `turn1` are
// edgeTurn() of the block's two edges back-projected onto the light (the sign of the 2D cross
// product between p' and each edge, measured where the integration measures it, so the two agree
// even when p' lies on an edge). Inside means on the left of every non-degenerate edge; a block
// whose edges are all degenerate is inside exactly when t < 0 had grown its occluders over it.
SHARED_FN bool contourCentreOccluded(int mask, float t, float turn0, float turn1) {
    ivec3 rule = contourRule(mask);
    if (rule.x == 0) {
        return mask == 15;
    }
    bool any = false;
    bool inside = true;
    for (int which = 0; which < rule.x; ++which) {
        if (contourEdgeDegenerate(mask, t, which)) {
            continue;
        }
        any = true;
        float turn = which == 0 ? turn0 : turn1;
        if (!(turn > 0.0f)) {
            inside = false;
        }
    }
    return any ? inside : t < 0.0f;
}

// ---- 7. GBP06's back-projected sample quads (guennebaud2007 sec. 3) --------------------------------

// Occluded light area of an axis-aligned rectangle (x0, y0, x1, y1) in light coordinates (a
// back-projected shadow-map sample: its texel is parallel to the light). Square light: the overlap
// of the two intervals. Disk light: the radial integration of its four counter-clockwise edges.
SHARED_FN float rectOccludedArea(int shape, vec4 rect) {
    if (rect.z <= rect.x || rect.w <= rect.y) {
        return 0.0f;
    }
    if (shape == BP_LIGHT_SQUARE) {
        float w = max(0.0f, min(rect.z, 1.0f) - max(rect.x, -1.0f));
        float h = max(0.0f, min(rect.w, 1.0f) - max(rect.y, -1.0f));
        return w * h;
    }
    vec2 p00 = vec2(rect.x, rect.y);
    vec2 p10 = vec2(rect.z, rect.y);
    vec2 p11 = vec2(rect.z, rect.w);
    vec2 p01 = vec2(rect.x, rect.w);
    bool centreInside = edgeTurn(p00, p10) > 0.0f && edgeTurn(p10, p11) > 0.0f && edgeTurn(p11, p01) > 0.0f &&
                        edgeTurn(p01, p00) > 0.0f;
    float area = centreInside ? BP_PI : 0.0f;
    area += edgeOccludedArea(shape, p00, p10);
    area += edgeOccludedArea(shape, p10, p11);
    area += edgeOccludedArea(shape, p11, p01);
    area += edgeOccludedArea(shape, p01, p00);
    return area;
}

// Visibility from the occluded area (clamped: GBP06's overlaps can cover the light more than once,
// and occluders at different depths need not close up exactly on the light).
SHARED_FN float bpVisibility(float occludedArea, int shape) {
    return clamp(1.0f - occludedArea / bpLightArea(shape), 0.0f, 1.0f);
}

// ---- 8. light-space multi-resolution (guennebaud2007 sec. 5.1) -----------------------------------
// A coarse HSM level L stands for a shadow map 2^L times coarser: its texel (i, j) covers the map
// texels [i 2^L, (i+1) 2^L] x [j 2^L, (j+1) 2^L] and holds their MIN depth (as GBP06 suggests; the
// paper's sec. 5.1). Level coordinates times 2^L are map texel coordinates (the last texel of an odd
// size covers one map texel more, hsm.comp; the back-projection ignores that one-texel sliver).

// Eq. 2: the finest level whose kernel is at most t_k of its texels: ceil(log2(w_k / t_k)), 0 when
// w_k <= t_k, clamped to the top level.
SHARED_FN int lightLevelForKernel(float kernelTexels, float tk, int topLevel) {
    if (kernelTexels <= tk) {
        return 0;
    }
    return min(int(ceil(log2(kernelTexels / tk))), topLevel);
}

// Eq. 3: the continuous level lambda = log2(w~_k / t_k), w~_k the kernel of eq. 1 from the smooth
// occluder depth z_occ. Clamped to [lo, topLevel] with lo = max(0, log2(w_k / (4 t_k))), w_k the
// conservative kernel (from z_min): the level walked (floor(lambda), or floor(lambda) - 1 inside
// the blending band) never has a kernel wider than 8 t_k of its texels (2^(3 + beta) t_k in the band),
// so the cost stays bounded
// (sec. 5.2: "the kernel size is bounded") even where z_occ lies far behind the kernel's nearest
// occluder. The floor is continuous in w_k and sits two levels under eq. 2's, so it only acts where
// z_occ is that far off: a clamp to eq. 2's discrete level itself would bring back the seams of
// Fig. 6a wherever it acts (ScreenAdaptiveRender.BlendingRemovesTheSeamsAtLevelTransitions).
SHARED_FN float lightLevelContinuous(float smoothKernelTexels, float kernelTexels, float tk, int topLevel) {
    float lambda = smoothKernelTexels > 0.0f ? log2(smoothKernelTexels / tk) : 0.0f;
    float lo = kernelTexels > 4.0f * tk ? log2(kernelTexels / (4.0f * tk)) : 0.0f;
    return clamp(lambda, min(lo, float(topLevel)), float(topLevel));
}

// The blending of sec. 5.1's pseudo-code: (lod, the other level, the other level's weight). Within
// beta of the level below, mix toward it with weight (1 - d / beta) / 2; within beta of the level
// above, toward it with weight (1 - (1 - d) / beta) / 2. The paper prints the second weight as
// (d / beta) / 2, which is not continuous (it reaches 1 / (2 beta) at d = 1); ours is 1/2 on both
// sides of every integer lambda, so v is continuous across transitions. beta = 0: no blending.
SHARED_FN vec3 lightLevelBlend(float lambda, float beta, int topLevel) {
    float lod = floor(lambda);
    float d = lambda - lod;
    if (beta > 0.0f) {
        if (d < beta && lod >= 1.0f) {
            return vec3(lod, lod - 1.0f, 0.5f * (1.0f - d / beta));
        }
        if (1.0f - d < beta && lod + 1.0f <= float(topLevel)) {
            return vec3(lod, lod + 1.0f, 0.5f * (1.0f - (1.0f - d) / beta));
        }
    }
    return vec3(lod, lod, 0.0f);
}

// The continuous occluder depth z_occ of sec. 5.1 ("linear filtering of the occluder depth values
// fetched in the appropriate HSM level"): the bilinear weights at f (the fractional position of p'
// among the four texel centres 00, 10, 11, 01 of the kernel's refinement level) over the texels
// whose min depth is nearer than zLimit (z_p - bias), renormalised; zMin (the kernel's min) when
// none is, and never nearer than zMin, so the smooth kernel w~_k is at most w_k. Only a hint: the
// kernel itself is still eq. 1 from zMin.
SHARED_FN float occluderDepthHint(vec4 depths, vec2 f, float zLimit, float zMin) {
    vec4 w = vec4((1.0f - f.x) * (1.0f - f.y), f.x * (1.0f - f.y), f.x * f.y, (1.0f - f.x) * f.y);
    float sw = 0.0f;
    float sz = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (depths[k] < zLimit) {
            sw += w[k];
            sz += w[k] * depths[k];
        }
    }
    float z = sw > 0.0f ? sz / sw : zMin;
    return max(z, zMin);
}

// Whether the sample of level `level` at texel t, of min depth zSample, occludes the receiver: the
// level-0 test (bpSampleOccludes) at the texel's centre in map coordinates with the depth bias in
// texels of the level, i.e. times 2^level, since the min over a texel 2^level map texels wide of the
// receiver's own tilted surface lies up to 2^level times further from the plane at its centre. On
// level 0 this is exactly bpSampleOccludes.
SHARED_FN bool bpLevelSampleOccludes(BpReceiver r, int level, ivec2 t, float zSample, float smSize, float tanHalfFov) {
    float s = float(1 << level);
    float bias = r.bias * s;
    if (zSample >= r.position.z - bias) {
        return false;
    }
    vec2 centre = vec2((float(t.x) + 0.5f) * s, (float(t.y) + 0.5f) * s);
    float zPlane = receiverPlaneDepth(r.normal, r.position, centre, smSize, tanHalfFov);
    return sampleOccludes(zSample, r.position.z, zPlane, bias);
}

// ---- 9. The kernel walked row by row with occlusion bits ------------------------------------------
// llvmpipe (and any SIMD GPU) runs both sides of a branch whenever one lane of a group takes it, so
// a walk that tests "is this block on the contour?" per block pays the edge work (rules,
// back-projection, clipping, area) for every block of the kernel. The walk instead reads one row of
// a chunk of samples into the bits of a uint (bit i: sample x0 + i occludes), finds the blocks or
// samples that need work with bit operations, and loops over the set bits only: the loop runs as
// many times as the lane with the most work in that row needs (a few on a shadow edge), not the
// kernel's width. The results are those of the plain walk; the order of the sums is the plain
// walk's within a chunk, chunk by chunk (the CPU mirrors run the same order). The GPU reads the
// bits of two rows at a time, one textureGather per 2x2 samples (visibility_common.glsl
// rowPairOcclusionBits), and then walks the two rows one after the other: the same bits, sums and order.

// Samples per chunk of a row: 32 bits hold 32 samples, i.e. the 31 blocks of 2x2 samples between
// them (ssm-contour) or 31 samples with their right neighbours (ssm-gbp06).
#define BP_ROW_CHUNK 31

// The blocks of a chunk whose four samples neither all occlude nor all miss (contour blocks: the
// rule table gives them edges): bit i for the block of samples i, i + 1 of the rows `below` and
// `above` (bit i: sample i occludes); `blocks` <= 31 blocks in the chunk.
SHARED_FN uint contourBlockBits(uint below, uint above, int blocks) {
    uint any = below | above;
    any = any | (any >> 1u);
    uint all = below & above;
    all = all & (all >> 1u);
    uint valid = (1u << uint(blocks)) - 1u;
    return any & ~all & valid;
}

// The 2x2 mask of contourRule (bit 0 lower-left, 1 lower-right, 2 upper-right, 3 upper-left) of the
// block whose lower-left sample is bit i of `below`.
SHARED_FN int contourBlockMask(uint below, uint above, int i) {
    uint b = below >> uint(i);
    uint a = above >> uint(i);
    return int((b & 1u) | (((b >> 1u) & 1u) << 1u) | (((a >> 1u) & 1u) << 2u) | ((a & 1u) << 3u));
}

#endif
