// Sub-pixel shadow maps (lecocq2014): the closest triangle per shadow-map texel, packed into 128
// bits, and the look-up that decides a receiver's hard visibility from it: on the stored triangle,
// a ray/triangle hit in the texel or its neighbourhood, or a shadow edge reconstructed from the
// neighbouring triangles' vertices (the paper's Fig. 2). techniques/spsm/README.md gives the design
// where the paper is brief (the packing, the tangent estimate, the vertex selection).
// Common GLSL/C++ subset: see shaders/shared/shared.h.
//
// Coordinates: "SPSM space" is the light's shadow map in texel units, x in [0, N]^2 (texel (i, j)
// is the square [i, i+1] x [j, j+1], rows from the bottom), and the light-view depth z (world
// units along the light's axis, > 0 in front). The map is rendered from the light's centre, so the
// ray from a receiver p to the light projects onto the single point x(p): intersecting that ray
// with a stored triangle is the 2D test "x(p) inside the triangle" plus "the triangle's depth at
// x(p) is in front of p".
#ifndef SHADOWLAB_SPSM_GLSL
#define SHADOWLAB_SPSM_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// ---- The 128-bit packing (one RGBA32UI texel; all zero = no caster touches the texel)
// bits   0..83   the three vertices (x0, y0, x1, y1, x2, y2), 14-bit fixed point over
//                [-SPSM_MARGIN, N + SPSM_MARGIN] (the geometry shader clips triangles to that square)
// bits  84..104  w0 = 1/z at vertex 0: the top 21 bits of the float (8 exponent, 13 mantissa bits,
//                rounded; the sign is always 0)
// bits 105..109  e, the exponent of the depth derivatives' scale S = w0 2^-(e - 8)
// bits 110..127  the compact depth derivatives: w1 - w0 and w2 - w0 in units of S / 255, 9 bits
//                each (offset by 255, so -255..255)
// 1/z is affine in SPSM space (a plane seen through a perspective projection), so the three
// inverse depths give the exact plane depth at any x by barycentric interpolation; storing the
// differences w1 - w0, w2 - w0 on a shared scale keeps the error proportional to the triangle's own
// depth range (a triangle facing the light stores them almost exactly), and a triangle nearly
// edge-on to the light stays bounded by its vertices' depths (a stored normal would not).
#define SPSM_COORD_BITS 14u
#define SPSM_MARGIN 4.0f
#define SPSM_FAR 1e30f

struct SpsmTriangle {
    vec2 a;          // vertices in texel coordinates
    vec2 b;
    vec2 c;
    vec3 w;          // 1/z at a, b, c (light-view depth z > 0)
    float wError;    // the largest error of w as stored: spsmUnpack sets it from the stored scale (the
                     // look-up's tests add it; a triangle not read from the map: spsmInverseDepthError)
};

SHARED_FN uvec4 spsmPutBits(uvec4 words, uint offset, uint width, uint value) {
    uint v = value & ((1u << width) - 1u);
    uint word = offset / 32u;
    uint shift = offset % 32u;
    words[word] = words[word] | (v << shift);
    if (shift + width > 32u) words[word + 1u] = words[word + 1u] | (v >> (32u - shift));
    return words;
}

SHARED_FN uint spsmGetBits(uvec4 words, uint offset, uint width) {
    uint word = offset / 32u;
    uint shift = offset % 32u;
    uint v = words[word] >> shift;
    if (shift + width > 32u) v = v | (words[word + 1u] << (32u - shift));
    return v & ((1u << width) - 1u);
}

// One quantisation step of a vertex coordinate, in texels: (N + 2 margin) / (2^14 - 1).
SHARED_FN float spsmCoordStep(float smSize) {
    return (smSize + 2.0f * SPSM_MARGIN) / float((1u << SPSM_COORD_BITS) - 1u);
}

SHARED_FN uint spsmQuantizeCoord(float x, float smSize) {
    float q = floor((x + SPSM_MARGIN) / spsmCoordStep(smSize) + 0.5f);
    return uint(clamp(q, 0.0f, float((1u << SPSM_COORD_BITS) - 1u)));
}

SHARED_FN float spsmDequantizeCoord(uint q, float smSize) {
    return float(q) * spsmCoordStep(smSize) - SPSM_MARGIN;
}

// The scale exponent e (0..31) for depth differences up to m at w0: the smallest S = w0 2^-(e-8)
// with m <= S, so the 9-bit differences use their range. floor(log2(w0 / m)) is read from the
// float's exponent bits (exact, and a few integer operations where log2 is a polynomial on a SIMD
// CPU); a ratio under the smallest normal float gives 0 after the clamp, as log2 would.
SHARED_FN uint spsmDepthScaleExponent(float w0, float m) {
    float ratio = w0 / max(m, 1e-30f);
    float e = float(int((floatBitsToUint(ratio) >> 23u) & 255u) - 127) + 8.0f;
    return uint(clamp(e, 0.0f, 31.0f));
}

// w0 2^(8 - e), exactly (ldexp scales the exponent).
SHARED_FN float spsmDepthScale(float w0, uint e) {
    return ldexp(w0, 8 - int(e));
}

SHARED_FN uvec4 spsmPack(SpsmTriangle t, float smSize) {
    uvec4 w = uvec4(0u, 0u, 0u, 0u);
    w = spsmPutBits(w, 0u, SPSM_COORD_BITS, spsmQuantizeCoord(t.a.x, smSize));
    w = spsmPutBits(w, 14u, SPSM_COORD_BITS, spsmQuantizeCoord(t.a.y, smSize));
    w = spsmPutBits(w, 28u, SPSM_COORD_BITS, spsmQuantizeCoord(t.b.x, smSize));
    w = spsmPutBits(w, 42u, SPSM_COORD_BITS, spsmQuantizeCoord(t.b.y, smSize));
    w = spsmPutBits(w, 56u, SPSM_COORD_BITS, spsmQuantizeCoord(t.c.x, smSize));
    w = spsmPutBits(w, 70u, SPSM_COORD_BITS, spsmQuantizeCoord(t.c.y, smSize));
    // w0 rounded to its top 21 bits (positive: no sign bit to keep); a positive normal float never
    // rounds to 0, so a packed triangle is never the empty marker.
    uint bits = floatBitsToUint(clamp(t.w.x, 1.2e-38f, 1e30f));
    uint w0bits = min((bits + 512u) >> 10u, 0x1FDFFFu);
    w = spsmPutBits(w, 84u, 21u, w0bits);
    float w0 = uintBitsToFloat(w0bits << 10u);  // the differences are taken from the stored w0
    float d1 = t.w.y - w0;
    float d2 = t.w.z - w0;
    uint e = spsmDepthScaleExponent(w0, max(abs(d1), abs(d2)));
    float unit = spsmDepthScale(w0, e) / 255.0f;
    w = spsmPutBits(w, 105u, 5u, e);
    w = spsmPutBits(w, 110u, 9u, uint(clamp(floor(d1 / unit + 0.5f), -255.0f, 255.0f) + 255.0f));
    w = spsmPutBits(w, 119u, 9u, uint(clamp(floor(d2 / unit + 0.5f), -255.0f, 255.0f) + 255.0f));
    return w;
}

SHARED_FN bool spsmEmpty(uvec4 w) {
    return w.x == 0u && w.y == 0u && w.z == 0u && w.w == 0u;
}

SHARED_FN SpsmTriangle spsmUnpack(uvec4 w, float smSize) {
    SpsmTriangle t;
    t.a = vec2(spsmDequantizeCoord(spsmGetBits(w, 0u, SPSM_COORD_BITS), smSize),
               spsmDequantizeCoord(spsmGetBits(w, 14u, SPSM_COORD_BITS), smSize));
    t.b = vec2(spsmDequantizeCoord(spsmGetBits(w, 28u, SPSM_COORD_BITS), smSize),
               spsmDequantizeCoord(spsmGetBits(w, 42u, SPSM_COORD_BITS), smSize));
    t.c = vec2(spsmDequantizeCoord(spsmGetBits(w, 56u, SPSM_COORD_BITS), smSize),
               spsmDequantizeCoord(spsmGetBits(w, 70u, SPSM_COORD_BITS), smSize));
    float w0 = uintBitsToFloat(spsmGetBits(w, 84u, 21u) << 10u);
    float unit = spsmDepthScale(w0, spsmGetBits(w, 105u, 5u)) / 255.0f;
    t.w = vec3(w0, w0 + (float(spsmGetBits(w, 110u, 9u)) - 255.0f) * unit,
               w0 + (float(spsmGetBits(w, 119u, 9u)) - 255.0f) * unit);
    // spsmInverseDepthError with the stored scale (not recomputed from the rounded values: once per
    // texel here, where the look-up's tests ran it for every triangle test and depth comparison).
    t.wError = 0.5f * unit + 6.2e-5f * max(t.w.x, max(t.w.y, t.w.z));
    return t;
}

// The largest error of a stored inverse depth: half a difference unit, plus w0's rounding (2^-14
// relative) which every vertex inherits. The look-up's bias adds it, per triangle (t.wError, which
// spsmUnpack computes with the stored scale; this recomputes the scale from t's values).
SHARED_FN float spsmInverseDepthError(SpsmTriangle t) {
    float m = max(abs(t.w.y - t.w.x), abs(t.w.z - t.w.x));
    float unit = spsmDepthScale(t.w.x, spsmDepthScaleExponent(t.w.x, m)) / 255.0f;
    return 0.5f * unit + 6.2e-5f * max(t.w.x, max(t.w.y, t.w.z));
}

// ---- Depth along the light's rays

// The light-view direction (z component -1) of the ray through texel coordinate x.
SHARED_FN vec3 spsmRayDirection(vec2 x, float smSize, float tanHalfFov) {
    vec2 ndc = x * (2.0f / smSize) - vec2(1.0f, 1.0f);
    return vec3(ndc.x * tanHalfFov, ndc.y * tanHalfFov, -1.0f);
}

// Twice the signed area of (a, b, p): > 0 when p is left of a -> b.
SHARED_FN float spsmEdgeFunction(vec2 a, vec2 b, vec2 p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// 1/z of the triangle's plane along the ray through x: the barycentric interpolation of the
// vertices' 1/z (exact for a plane, and an extrapolation outside the triangle); <= 0 where the
// ray misses the plane in front of the light. A degenerate triangle gives its vertices' largest.
SHARED_FN float spsmInverseDepthAt(SpsmTriangle t, vec2 x) {
    float area = spsmEdgeFunction(t.a, t.b, t.c);
    if (abs(area) < 1e-12f) return max(t.w.x, max(t.w.y, t.w.z));
    float la = spsmEdgeFunction(t.b, t.c, x) / area;
    float lb = spsmEdgeFunction(t.c, t.a, x) / area;
    return t.w.x + lb * (t.w.y - t.w.x) + (1.0f - la - lb) * (t.w.z - t.w.x);
}

SHARED_FN float spsmDepthAt(SpsmTriangle t, vec2 x) {
    float w = spsmInverseDepthAt(t, x);
    return w > 0.0f ? 1.0f / w : SPSM_FAR;
}

// The packing's depth error at x on the stored triangle t, in world units: its inverse-depth error
// at the depth there (dz = dw / w^2).
SHARED_FN float spsmPackingDepthError(SpsmTriangle t, vec2 x) {
    float w = spsmInverseDepthAt(t, x);
    return w > 1e-15f ? t.wError / (w * w) : SPSM_FAR;
}

// ---- 2D tests

// Whether x lies in the stored triangle (edges included, within 1e-4 texels so that the shared
// edge of two triangles leaves no crack), from the three edge functions of x (spsmEdgeFunction of
// the edges a->b, b->c, c->a) and twice the signed area: s E >= -1e-4 |edge| for each edge, written
// without the square roots (E s >= 0, or E^2 <= 1e-8 |edge|^2). Degenerate triangles contain nothing.
SHARED_FN bool spsmInsideEdges(SpsmTriangle t, float area, vec3 e) {
    if (abs(area) < 1e-12f) return false;
    vec3 se = area > 0.0f ? e : -e;
    vec2 ab = t.b - t.a;
    vec2 bc = t.c - t.b;
    vec2 ca = t.a - t.c;
    vec3 len2 = vec3(dot(ab, ab), dot(bc, bc), dot(ca, ca));
    vec3 tol2 = 1e-8f * len2;
    return (se.x >= 0.0f || se.x * se.x <= tol2.x) && (se.y >= 0.0f || se.y * se.y <= tol2.y) &&
           (se.z >= 0.0f || se.z * se.z <= tol2.z);
}

// The three edge functions of x: a->b, b->c, c->a.
SHARED_FN vec3 spsmEdges(SpsmTriangle t, vec2 x) {
    return vec3(spsmEdgeFunction(t.a, t.b, x), spsmEdgeFunction(t.b, t.c, x), spsmEdgeFunction(t.c, t.a, x));
}

SHARED_FN bool spsmInside(SpsmTriangle t, vec2 x) {
    return spsmInsideEdges(t, spsmEdgeFunction(t.a, t.b, t.c), spsmEdges(t, x));
}

// How the build ranks the triangles touching a texel (its depth test): 1/z of the triangle's
// plane at the texel centre, exact where the triangle covers the centre; extrapolated where it
// does not, and then made farther by SPSM_RANK_MARGIN of the depth, so that such a triangle takes
// the texel from the one covering the centre only when it is nearer there by more than 2% (a
// silhouette's steep sliver, not a smooth surface's neighbouring facet).

#define SPSM_RANK_MARGIN 0.02f
SHARED_FN float spsmRankInverseDepth(SpsmTriangle t, vec2 centre) {
    float w = spsmInverseDepthAt(t, centre);
    return spsmInside(t, centre) ? w : w * (1.0f - SPSM_RANK_MARGIN);
}

// The vertex of triangle t with index i (0, 1, 2).
SHARED_FN vec2 spsmVertex(SpsmTriangle t, int i) {
    return i == 0 ? t.a : (i == 1 ? t.b : t.c);
}

// Whether the stored triangle touches the texel square [lo, lo + 1]^2 (closed, within 1e-4
// texels): the separating-axis test of a triangle against a box, exact in 2D with five axes, the
// box's two and the triangle's three edge normals. This is what the conservative build keeps: a
// fragment of the expanded triangle whose texel fails it is dropped (Hasselgren et al. 2005 clip
// the expansion's overshoot by the triangle's bounding box, which keeps some untouched texels near
// acute corners; the edge axes drop those too).
SHARED_FN bool spsmTouchesTexel(SpsmTriangle t, vec2 lo) {
    float tol = 1e-4f;
    vec2 hi = lo + vec2(1.0f, 1.0f);
    vec2 bmin = min(t.a, min(t.b, t.c));
    vec2 bmax = max(t.a, max(t.b, t.c));
    if (bmin.x > hi.x + tol || bmin.y > hi.y + tol || bmax.x < lo.x - tol || bmax.y < lo.y - tol) return false;
    float area = spsmEdgeFunction(t.a, t.b, t.c);
    if (abs(area) < 1e-12f) return false;
    float s = area > 0.0f ? 1.0f : -1.0f;
    for (int e = 0; e < 3; ++e) {
        vec2 a = spsmVertex(t, e);
        vec2 b = spsmVertex(t, (e + 1) % 3);
        // The box corner furthest inside this edge: the largest s * edge function over the box.
        vec2 d = s * vec2(-(b.y - a.y), b.x - a.x);  // gradient of s * spsmEdgeFunction(a, b, .)
        vec2 corner = vec2(d.x >= 0.0f ? hi.x : lo.x, d.y >= 0.0f ? hi.y : lo.y);
        if (s * spsmEdgeFunction(a, b, corner) < -tol * length(b - a)) return false;
    }
    return true;
}

// What one stored triangle says about a receiver at texel coordinate x and depth z:
// 0 it does not cover x; 1 it covers x at or behind the receiver (within the bias: the receiver
// lies on it, or in front of it); 2 it covers x in front of the receiver (the ray to the light
// meets it: shadowed). The bias is the shadow map's plus the triangle's own packing error there.
// The edge functions, the barycentric 1/z and its error are computed once (spsmInside,
// spsmDepthAt and spsmPackingDepthError in one): the first draw runs this for every pixel.
SHARED_FN int spsmTriangleTest(SpsmTriangle t, vec2 x, float zReceiver, float bias) {
    float area = spsmEdgeFunction(t.a, t.b, t.c);
    vec3 e = spsmEdges(t, x);
    if (!spsmInsideEdges(t, area, e)) return 0;
    // 1/z at x: la = E(b, c, x) / area at a, lb = E(c, a, x) / area at b (spsmInverseDepthAt).
    float la = e.y / area;
    float lb = e.z / area;
    float w = t.w.x + lb * (t.w.y - t.w.x) + (1.0f - la - lb) * (t.w.z - t.w.x);
    float z = w > 0.0f ? 1.0f / w : SPSM_FAR;
    float error = w > 1e-15f ? t.wError / (w * w) : SPSM_FAR;
    return z < zReceiver - bias - error ? 2 : 1;
}

// 1/z of the stored triangle at its point nearest x: at x where the triangle covers it, else where
// the nearest of its edges passes closest (1/z is affine in texel coordinates, so linear along an
// edge). The conservative build stores triangles in texels whose centres they miss; a sliver (a
// face seen edge-on from the light: a thin plate's side) spans a long range of depths along its
// length, and its plane extrapolated to a centre beside it, even kept within its vertices' depths,
// takes the depth of its far end.
SHARED_FN float spsmInverseDepthNearest(SpsmTriangle t, vec2 x) {
    if (spsmInside(t, x)) return spsmInverseDepthAt(t, x);
    float best = SPSM_FAR;
    float w = t.w.x;
    for (int i = 0; i < 3; ++i) {
        vec2 p0 = spsmVertex(t, i);
        vec2 p1 = spsmVertex(t, (i + 1) % 3);
        float w0 = t.w[i];
        float w1 = t.w[(i + 1) % 3];
        vec2 e = p1 - p0;
        float len2 = dot(e, e);
        float s = len2 > 1e-20f ? clamp(dot(x - p0, e) / len2, 0.0f, 1.0f) : 0.0f;
        vec2 d = x - (p0 + s * e);
        float dist2 = dot(d, d);
        if (dist2 < best) {
            best = dist2;
            w = w0 + s * (w1 - w0);
        }
    }
    return w;
}

// The depth comparison of the reconstruction step for one neighbour: the neighbour triangle's depth
// nearest x (the neighbour texel's centre: the shadow map's comparison with that texel;
// spsmInverseDepthNearest). Returns true when it is in front of the receiver.
SHARED_FN bool spsmOccludesByDepth(SpsmTriangle t, vec2 x, float zReceiver, float bias) {
    float w = spsmInverseDepthNearest(t, x);
    float z = w > 0.0f ? 1.0f / w : SPSM_FAR;
    return z < zReceiver - bias - t.wError / max(w * w, 1e-30f);
}

// ---- The shadow-edge reconstruction (the paper's Fig. 1 right and Fig. 2)

// The approximate light-space normal of the shadow edge from the 3x3 depth comparisons: bit k
// (k = (dy + 1) * 3 + dx + 1) of `occluded` set when neighbour (dx, dy) is in front of the
// receiver. Each neighbour pulls the normal towards itself when it occludes and away when it does
// not, so the normal points from the lit side to the shadowed side; the tangent is its
// perpendicular. Zero when the comparisons are symmetric (all equal, or a pattern with no side).
SHARED_FN vec2 spsmEdgeNormal(uint occluded) {
    vec2 n = vec2(0.0f, 0.0f);
    for (int k = 0; k < 9; ++k) {
        if (k != 4) {
            vec2 offset = vec2(float(k % 3 - 1), float(k / 3 - 1));
            float sgn = ((occluded >> uint(k)) & 1u) != 0u ? 1.0f : -1.0f;
            n += sgn * offset;
        }
    }
    return n;
}

// The reconstruction's result, with what the spsm-texels view and the --pixel record show.
struct SpsmEdge {
    int decided;      // 1: the edge decided; 0: no tangent or no usable vertex (the caller falls back)
    float shadowed;   // 1 when x lies on the shadowed side of the reconstructed edge
    vec2 normal;      // unit edge normal (towards the shadowed side); the tangent is (-n.y, n.x)
    vec2 left;        // the linked vertices (texel coordinates): the nearest kept vertex on each
    vec2 right;       //   side of x along the tangent (equal when only one side has one)
    float dEdge;      // the edge's distance along the normal at x's tangent coordinate
    float dPoint;     // x's distance along the normal (both from the texel centre)
    int kept;         // vertices kept after the bisector and occlusion tests
};

// The distinct triangles among the occluding neighbours (bit k of `occluding` set): bit k of `mask`
// is set for the first of each (in the order of k), t[k] = tris[k] in place. Neighbouring texels
// often store the same triangle (a large caster spans many texels), and the reconstruction's work
// grows with the square of the triangles it links (every kept vertex is tested against every
// occluding edge); a duplicate adds nothing: the same vertices and the same edges. The loops below
// run over the nine places with the mask rather than over a compacted list: llvmpipe keeps a
// local array written at a varying index in memory and reads it lane by lane, which cost more than
// the skipped places (measured: techniques/spsm/README.md).
struct SpsmOccluders {
    SpsmTriangle t[9];
    uint mask;
    int count;
};

SHARED_FN bool spsmSameTriangle(SpsmTriangle p, SpsmTriangle q) {
    return p.a == q.a && p.b == q.b && p.c == q.c && p.w == q.w;
}

SHARED_FN SpsmOccluders spsmDistinctOccluders(SpsmTriangle tris[9], uint occluding) {
    SpsmOccluders o;
    o.mask = 0u;
    o.count = 0;
    for (int k = 0; k < 9; ++k) {
        o.t[k] = tris[k];
        bool fresh = ((occluding >> uint(k)) & 1u) != 0u;
        for (int j = 0; j < k; ++j) fresh = fresh && !(((o.mask >> uint(j)) & 1u) != 0u && spsmSameTriangle(tris[j], tris[k]));
        if (fresh) {
            o.mask = o.mask | (1u << uint(k));
            o.count += 1;
        }
    }
    return o;
}

SHARED_FN bool spsmOccluderUsed(SpsmOccluders o, int k) {
    return ((o.mask >> uint(k)) & 1u) != 0u;
}

// Whether a vertex v of an occluding triangle, at tangent coordinate sv and normal distance dv,
// is hidden behind an edge of an occluding triangle: an edge spanning sv (strictly) lies nearer the
// lit side (smaller d) there. Such a vertex is inside the occluders' projection, not on the edge.
SHARED_FN bool spsmVertexHidden(SpsmOccluders o, vec2 v, vec2 centre, vec2 n, vec2 tangent) {
    float sv = dot(v - centre, tangent);
    float dv = dot(v - centre, n);
    bool hidden = false;
    for (int k = 0; k < 9; ++k) {
        for (int e = 0; e < 3; ++e) {
            vec2 p = spsmVertex(o.t[k], e);
            vec2 q = spsmVertex(o.t[k], (e + 1) % 3);
            float sp = dot(p - centre, tangent);
            float sq = dot(q - centre, tangent);
            float lo = min(sp, sq);
            float hi = max(sp, sq);
            if (spsmOccluderUsed(o, k) && sv > lo + 1e-4f && sv < hi - 1e-4f) {
                float dp = dot(p - centre, n);
                float dq = dot(q - centre, n);
                float d = dp + (dq - dp) * (sv - sp) / (sq - sp);
                hidden = hidden || d < dv - 1e-3f;
            }
        }
    }
    return hidden;
}

// The edge's distance along n at tangent coordinate sx when only one linked vertex v was found:
// the occluding edges from v that head towards sx, extended (the lowest, as the envelope of the
// occluders towards the lit side). None heads there: v is a corner beyond which no stored occluder
// extends along the tangent, and x is on the lit side (SPSM_FAR).
SHARED_FN float spsmExtendFromVertex(SpsmOccluders o, vec2 v, float sx, vec2 centre, vec2 n, vec2 tangent) {
    float sv = dot(v - centre, tangent);
    float dv = dot(v - centre, n);
    float best = SPSM_FAR;
    for (int k = 0; k < 9; ++k) {
        for (int i = 0; i < 3; ++i) {
            if (spsmOccluderUsed(o, k) && length(spsmVertex(o.t[k], i) - v) < 1e-5f) {
                for (int j = 1; j < 3; ++j) {
                    vec2 w = spsmVertex(o.t[k], (i + j) % 3);
                    float sw = dot(w - centre, tangent);
                    float dw = dot(w - centre, n);
                    if ((sw - sv) * (sx - sv) > 1e-8f) best = min(best, dv + (dw - dv) * (sx - sv) / (sw - sv));
                }
            }
        }
    }
    return best;
}

// Reconstructs the shadow edge near the receiver's projection x from the 3x3 neighbourhood around
// the texel whose centre is `centre`: tris[k] are the stored triangles (k as in spsmEdgeNormal),
// `occluding` the neighbours whose depth comparison found them in front of the receiver. The edge
// links the occluders' vertices that can lie on it: those whose bisector (pointing into their
// triangle) does not face the lit side (within 60 degrees of -n: the vertex of a triangle that
// opens towards the light's side is inside the occluders, not on their edge; a sliver along the
// edge has its bisector along the tangent, and its far vertex is kept), and that no occluding edge
// hides (spsmVertexHidden). x is shadowed when it lies beyond the segment joining the nearest kept
// vertex on each side along the tangent (the paper: "comparing the projection distance d_p of p
// on the tangent with the projection distances of neighbouring vertices"); with a vertex on one
// side only, beyond the occluding edges from it extended (spsmExtendFromVertex).
SHARED_FN SpsmEdge spsmReconstructEdge(SpsmTriangle tris[9], uint occluding, vec2 x, vec2 centre) {
    SpsmEdge r;
    r.decided = 0;
    r.shadowed = 0.0f;
    r.normal = vec2(0.0f, 0.0f);
    r.left = centre;
    r.right = centre;
    r.dEdge = 0.0f;
    r.dPoint = 0.0f;
    r.kept = 0;
    vec2 m = spsmEdgeNormal(occluding);
    if (length(m) < 0.5f) return r;
    vec2 n = normalize(m);
    vec2 tangent = vec2(-n.y, n.x);
    r.normal = n;
    float sx = dot(x - centre, tangent);
    r.dPoint = dot(x - centre, n);
    // The kept vertices (three per distinct occluding triangle at most), and among them, in the
    // order of k and i, the nearest on each side of x along the tangent (the paper's linking of
    // edge vertices: the segment joining them is the edge at sx) and the nearest to sx overall
    // (for the one-sided case).
    SpsmOccluders o = spsmDistinctOccluders(tris, occluding);
    int count = 0;
    vec2 left = centre;
    vec2 right = centre;
    vec2 nearestVertex = centre;
    float bestLeft = -SPSM_FAR;
    float bestRight = SPSM_FAR;
    float nearest = SPSM_FAR;
    for (int k = 0; k < 9; ++k) {
        for (int i = 0; i < 3; ++i) {
            vec2 v = spsmVertex(o.t[k], i);
            vec2 p = spsmVertex(o.t[k], (i + 1) % 3);
            vec2 q = spsmVertex(o.t[k], (i + 2) % 3);
            vec2 bisector = normalize(p - v) + normalize(q - v);
            float facing = dot(bisector, n) / max(length(bisector), 1e-20f);
            if (spsmOccluderUsed(o, k) && facing > -0.5f && !spsmVertexHidden(o, v, centre, n, tangent)) {
                count += 1;
                float si = dot(v - centre, tangent);
                if (si <= sx && si > bestLeft) {
                    bestLeft = si;
                    left = v;
                }
                if (si >= sx && si < bestRight) {
                    bestRight = si;
                    right = v;
                }
                if (abs(si - sx) < nearest) {
                    nearest = abs(si - sx);
                    nearestVertex = v;
                }
            }
        }
    }
    r.kept = count;
    bool found = bestLeft > -SPSM_FAR && bestRight < SPSM_FAR;
    float dEdge = SPSM_FAR;
    if (found) {
        float dl = dot(left - centre, n);
        float dr = dot(right - centre, n);
        dEdge = bestRight - bestLeft > 1e-6f ? dl + (dr - dl) * (sx - bestLeft) / (bestRight - bestLeft) : min(dl, dr);
    }
    if (!found) {
        // All kept vertices on one side of x: extend from the one nearest along the tangent.
        if (count == 0) return r;
        left = nearestVertex;
        right = nearestVertex;
        dEdge = spsmExtendFromVertex(o, left, sx, centre, n, tangent);
    }
    r.decided = 1;
    r.left = left;
    r.right = right;
    r.dEdge = dEdge;
    r.shadowed = r.dPoint >= dEdge ? 1.0f : 0.0f;
    return r;
}

#endif
