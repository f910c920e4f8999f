// Test-only, in the shared GLSL/C++ subset: the cases of the spsm shared-math grid. The fragment
// shader shaders/tests/spsm_math.frag evaluates spsmCase on the GPU, tests/techniques/test_spsm.cpp
// the same code in C++ (included like shaders/shared/shared.h does), and compares.
#ifndef SHADOWLAB_SPSM_CASES_GLSL
#define SHADOWLAB_SPSM_CASES_GLSL
#include "../../shared/spsm.glsl"

struct SpsmCaseOut {
    uvec4 code;     // spsmPack
    vec4 a;         // unpacked vertices a.xy, b.xy
    vec4 b;         // c.xy, w at a, w at c
    vec4 c;         // depth at p, 1/z at p, touches p's texel, the build's rank at another texel centre
    vec4 d;         // inside, triangle test, occludes by depth, edge function
    vec4 e;         // edge normal of the 3x3 pattern (xy), reconstruction decided, shadowed
    vec4 f;         // reconstruction d_edge, d_p, kept vertices, first-vertex hidden
    vec4 g;         // scale exponent, scale, inverse-depth error, packing depth error at p
    vec4 h;         // ray direction at p (xyz), coordinate step
    vec4 i;         // coordinate round trip, bit-field round trip, w at b, extension from a vertex
    vec4 j;         // vertex 1 of the centre neighbour (xy), packed texel empty, all-zero texel empty
    vec4 k;         // the three edge functions at p, inside from them + 2 x (same triangle as its round trip)
    vec4 l;         // spsmInverseDepthNearest at p, beside the triangle, and of the 3x3's centre triangle at p'
};

// A triangle in SPSM space around texel (8, 8) of a 64-texel map, from the grid cell (x, y).
SHARED_FN SpsmTriangle spsmCaseTriangle(int x, int y) {
    SpsmTriangle t;
    float ax = 3.0f + 0.37f * float(x);
    float ay = 2.0f + 0.29f * float(y);
    t.a = vec2(ax, ay);
    t.b = vec2(ax + 6.0f - 0.19f * float(y), ay + 0.5f + 0.07f * float(x));
    t.c = vec2(ax + 1.0f + 0.11f * float(x % 7), ay + 5.0f - 0.13f * float(y % 9));
    float w0 = 1.0f / (2.0f + 0.1f * float(x + y));
    t.w = vec3(w0, w0 * (1.0f + 0.02f * float(x % 5) - 0.03f), w0 * (1.0f - 0.01f * float(y % 7) + 0.2f * float(x % 2)));
    return t;
}

SHARED_FN SpsmCaseOut spsmCase(int x, int y) {
    SpsmCaseOut o;
    float smSize = 64.0f;
    float tanHalfFov = 0.6f;
    SpsmTriangle t = spsmCaseTriangle(x, y);
    o.code = spsmPack(t, smSize);
    SpsmTriangle u = spsmUnpack(o.code, smSize);
    o.a = vec4(u.a.x, u.a.y, u.b.x, u.b.y);
    o.b = vec4(u.c.x, u.c.y, u.w.x, u.w.z);
    vec2 p = vec2(4.0f + 0.21f * float(x), 3.0f + 0.23f * float(y));
    float z = 1.0f + 0.05f * float(x);
    o.c = vec4(spsmDepthAt(u, p), spsmInverseDepthAt(u, p), spsmTouchesTexel(u, floor(p)) ? 1.0f : 0.0f,
               spsmRankInverseDepth(u, floor(p) + vec2(2.5f, -0.5f)));
    o.d = vec4(spsmInside(u, p) ? 1.0f : 0.0f, float(spsmTriangleTest(u, p, z, 0.01f)),
               spsmOccludesByDepth(u, p, z, 0.01f) ? 1.0f : 0.0f, spsmEdgeFunction(u.a, u.b, p));
    // A 3x3 neighbourhood around texel (8, 8): an occluder bounded by the line through `origin`
    // with normal `n0`, split into triangles; a texel whose centre lies on its side stores one.
    float angle = 0.2f * float(x);
    vec2 n0 = vec2(cos(angle), sin(angle));
    vec2 tg = vec2(-n0.y, n0.x);
    vec2 origin = vec2(8.5f, 8.5f) + (0.1f * float(y % 9) - 0.4f) * n0;
    SpsmTriangle tris[9];
    uint occluding = 0u;
    for (int k = 0; k < 9; ++k) {
        vec2 centre = vec2(8.5f + float(k % 3 - 1), 8.5f + float(k / 3 - 1));
        float s = floor(dot(centre - origin, tg) + 0.5f);
        SpsmTriangle q;
        q.a = origin + (s - 1.0f) * tg;
        q.b = origin + (s + 1.0f) * tg;
        q.c = origin + s * tg + 3.0f * n0;
        q.w = vec3(0.5f, 0.5f, 0.45f);
        tris[k] = spsmUnpack(spsmPack(q, smSize), smSize);
        if (dot(centre - origin, n0) > 0.0f) occluding = occluding | (1u << uint(k));
    }
    vec2 m = spsmEdgeNormal(occluding);
    SpsmEdge r = spsmReconstructEdge(tris, occluding, p * 0.1f + vec2(7.6f, 7.6f), vec2(8.5f, 8.5f));
    o.e = vec4(m.x, m.y, float(r.decided), r.shadowed);
    bool hidden = spsmVertexHidden(spsmDistinctOccluders(tris, occluding), spsmVertex(tris[4], 2), vec2(8.5f, 8.5f), n0, tg);
    o.f = vec4(r.dEdge, r.dPoint, float(r.kept), hidden ? 1.0f : 0.0f);
    uint e = spsmDepthScaleExponent(u.w.x, 0.003f * float(x + 1));
    o.g = vec4(float(e), spsmDepthScale(u.w.x, e), spsmInverseDepthError(u), spsmPackingDepthError(u, p));
    o.h = vec4(spsmRayDirection(p, smSize, tanHalfFov), spsmCoordStep(smSize));
    o.i = vec4(spsmDequantizeCoord(spsmQuantizeCoord(p.x, smSize), smSize),
               float(spsmGetBits(spsmPutBits(uvec4(0u, 0u, 0u, 0u), 28u + uint(x % 8), 11u, uint(y * 37 + x)),
                                 28u + uint(x % 8), 11u)),
               u.w.y, spsmExtendFromVertex(spsmDistinctOccluders(tris, occluding), spsmVertex(tris[4], 0), 0.3f, vec2(8.5f, 8.5f), n0, tg));
    vec2 v1 = spsmVertex(tris[4], 1);
    SpsmOccluders distinct = spsmDistinctOccluders(tris, occluding);
    float used = 0.0f;  // the distinct occluders' places, weighted by place (spsmOccluderUsed)
    for (int k = 0; k < 9; ++k) used += spsmOccluderUsed(distinct, k) ? float(k + 1) : 0.0f;
    o.j = vec4(v1.x, v1.y, spsmEmpty(o.code) ? 1.0f : 0.0f,
               (spsmEmpty(uvec4(0u, 0u, 0u, 0u)) ? 1.0f : 0.0f) + 2.0f * used);
    vec3 edges = spsmEdges(u, p);
    bool insideEdges = spsmInsideEdges(u, spsmEdgeFunction(u.a, u.b, u.c), edges);
    o.k = vec4(edges, (insideEdges ? 1.0f : 0.0f) + (spsmSameTriangle(u, spsmUnpack(spsmPack(u, smSize), smSize)) ? 2.0f : 0.0f));
    o.l = vec4(spsmInverseDepthNearest(u, p), spsmInverseDepthNearest(u, p + vec2(-3.0f + 0.3f * float(x % 5), 7.0f)),
               spsmInverseDepthNearest(tris[4], p * 0.1f + vec2(7.6f, 7.6f)), 0.0f);
    return o;
}
#endif
