// spsm (lecocq2014): the shared math on the CPU (the 128-bit packing at its documented precision,
// ray/triangle tests on edges and vertices, the footprint depth, the tangent estimate and the edge
// reconstruction on synthetic 3x3 neighbourhoods), the same GLSL on the GPU on a grid, the
// conservative rasterization of the build against a CPU coverage computation on random triangles,
// the CPU mirror of the look-up against the GPU, and end-to-end renders against exact hard shadows.
#include <bitset>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gl/state.h"
#include "gl/util.h"
#include "graph/renderer.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "spsm/spsm.h"
#include "support/gl_fixture.h"

namespace shadowlab::shared {
#define SHARED_FN inline
#include "tests/spsm/spsm_cases.glsl"
#undef SHARED_FN
}  // namespace shadowlab::shared

namespace shadowlab {
namespace {

using namespace shared;

// A triangle in SPSM space with 1/z at its vertices.
SpsmTriangle makeTriangle(vec2 a, vec2 b, vec2 c, vec3 w) {
    SpsmTriangle t;
    t.a = a;
    t.b = b;
    t.c = c;
    t.w = w;
    t.wError = spsmInverseDepthError(t);
    return t;
}
SpsmTriangle flat(vec2 a, vec2 b, vec2 c, float z) { return makeTriangle(a, b, c, vec3(1.0f / z)); }

// ---- packing -------------------------------------------------------------------------------------
// Documented in techniques/spsm/README.md: vertices to half a step of (N + 8) / 16383 texels; the
// inverse depths to spsmInverseDepthError (half a unit of the differences' scale, plus w0's 2^-14),
// so the depth anywhere on the triangle to spsmPackingDepthError; and that bound is not loose.
TEST(SpsmMath, PackingRoundTripHoldsItsDocumentedPrecision) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float smSize : {64.0f, 256.0f, 512.0f, 2048.0f}) {
        float step = spsmCoordStep(smSize);
        EXPECT_NEAR(step, (smSize + 8.0f) / 16383.0f, 1e-9f);
        float worstVertex = 0.0f, worstW = 0.0f, worstDepth = 0.0f;
        for (int i = 0; i < 3000; ++i) {
            auto point = [&] { return vec2(-4.0f + u(rng) * (smSize + 8.0f), -4.0f + u(rng) * (smSize + 8.0f)); };
            float z0 = std::exp(u(rng) * 8.0f - 2.0f);
            // Depth ratios across the triangle from 1 + 1e-6 (facing the light) to 20 (nearly edge-on).
            float spread = std::exp(u(rng) * 17.0f - 14.0f);
            vec3 w(1.0f / z0, 1.0f / (z0 * (1.0f + spread * u(rng))), 1.0f / (z0 * (1.0f + spread * u(rng))));
            if (i % 2) std::swap(w.x, w.y);  // the nearest vertex first, or not
            SpsmTriangle t = makeTriangle(point(), point(), point(), w);
            uvec4 code = spsmPack(t, smSize);
            ASSERT_FALSE(spsmEmpty(code));
            SpsmTriangle r = spsmUnpack(code, smSize);
            for (vec2 dv : {r.a - t.a, r.b - t.b, r.c - t.c}) worstVertex = std::max({worstVertex, std::abs(dv.x), std::abs(dv.y)});
            // The bound the look-up adds (from the stored scale), and the one recomputed from the
            // unpacked values: both hold.
            float bound = std::min(r.wError, spsmInverseDepthError(r));
            for (int k = 0; k < 3; ++k) worstW = std::max(worstW, std::abs(r.w[k] - t.w[k]) / bound);
            // Depths inside the triangle (same vertices, so only the inverse depths' error counts).
            SpsmTriangle exact = t;
            exact.a = r.a;
            exact.b = r.b;
            exact.c = r.c;
            for (int k = 0; k < 4; ++k) {
                float s1 = u(rng), q = u(rng) * (1.0f - s1);
                vec2 x = r.a + s1 * (r.b - r.a) + q * (r.c - r.a);
                float ze = spsmDepthAt(exact, x), zr = spsmDepthAt(r, x);
                if (ze >= SPSM_FAR) continue;
                worstDepth = std::max(worstDepth, std::abs(zr - ze) / spsmPackingDepthError(r, x));
            }
        }
        EXPECT_LE(worstVertex, 0.501f * step + 1e-5f) << smSize;
        EXPECT_LE(worstW, 1.0f) << smSize;
        EXPECT_GT(worstW, 0.25f) << smSize << ": the bound is tight within 4x";
        EXPECT_LE(worstDepth, 1.0f) << smSize;
        RecordProperty("worst_depth_error_of_bound_" + std::to_string(int(smSize)), std::to_string(worstDepth));
    }
    // A triangle facing the light (all vertices at one depth) stores its depth to w0's 2^-14.
    SpsmTriangle facing = flat(vec2(3.0f), vec2(40.0f, 3.0f), vec2(3.0f, 40.0f), 7.0f);
    SpsmTriangle r = spsmUnpack(spsmPack(facing, 64.0f), 64.0f);
    EXPECT_NEAR(spsmDepthAt(r, vec2(10.0f)), 7.0f, 7.0f * 1.3e-4f);
    EXPECT_NEAR(r.w.y, 1.0f / 7.0f, 1e-7f) << "the differences are taken from the stored w0, so they undo its rounding";
    EXPECT_NEAR(r.w.z, 1.0f / 7.0f, 1e-7f);
}

TEST(SpsmMath, BitFieldsCrossWordBoundaries) {
    uvec4 w(0u);
    w = spsmPutBits(w, 28u, 14u, 0x2ABCu);  // bits 28..41: crosses words 0 and 1
    w = spsmPutBits(w, 106u, 22u, 0x3FFFFFu);
    EXPECT_EQ(spsmGetBits(w, 28u, 14u), 0x2ABCu);
    EXPECT_EQ(spsmGetBits(w, 106u, 22u), 0x3FFFFFu);
    EXPECT_EQ(spsmGetBits(w, 0u, 28u), 0u);
    EXPECT_EQ(w.w >> 10u, 0x3FFFFFu);  // the top 22 bits of the last word
    EXPECT_EQ(spsmPutBits(uvec4(0u), 0u, 4u, 0xFFu).x, 0xFu) << "a value wider than its field is cut";
}

TEST(SpsmMath, AnEmptyTexelIsAllZeroAndNoTriangleIsEmpty) {
    EXPECT_TRUE(spsmEmpty(uvec4(0u)));
    // The smallest invD and the origin corner: still not the empty marker.
    SpsmTriangle t = makeTriangle(vec2(-4.0f), vec2(-4.0f), vec2(-4.0f), vec3(1e-30f));
    EXPECT_FALSE(spsmEmpty(spsmPack(t, 256.0f)));
}

// ---- ray/triangle: the 2D test at p's projection plus the depth there ------------------------------
TEST(SpsmMath, RayTriangleOnEdgesAndVertices) {
    SpsmTriangle t = flat(vec2(1.0f, 1.0f), vec2(5.0f, 1.0f), vec2(1.0f, 4.0f), 4.0f);
    SpsmTriangle cw = t;  // the same triangle, clockwise
    cw.b = t.c;
    cw.c = t.b;
    for (const SpsmTriangle& tri : {t, cw}) {
        EXPECT_TRUE(spsmInside(tri, vec2(2.0f, 2.0f)));
        for (vec2 v : {t.a, t.b, t.c}) EXPECT_TRUE(spsmInside(tri, v)) << "vertices are inside";
        EXPECT_TRUE(spsmInside(tri, vec2(3.0f, 1.0f))) << "on an edge";
        EXPECT_TRUE(spsmInside(tri, vec2(3.0f, 2.5f))) << "on the hypotenuse (5,1)-(1,4)";
        EXPECT_FALSE(spsmInside(tri, vec2(3.0f, 0.999f)));
        EXPECT_FALSE(spsmInside(tri, vec2(3.0f, 2.502f)));
        EXPECT_FALSE(spsmInside(tri, vec2(5.01f, 1.0f))) << "beyond a vertex, on the edge's line";
    }
    // A shared edge leaves no crack: every point of it is inside one of the two triangles.
    SpsmTriangle other = flat(vec2(5.0f, 1.0f), vec2(5.0f, 4.0f), vec2(1.0f, 4.0f), 4.0f);
    for (int i = 0; i <= 1000; ++i) {
        vec2 x = mix(vec2(5.0f, 1.0f), vec2(1.0f, 4.0f), float(i) / 1000.0f);
        EXPECT_TRUE(spsmInside(t, x) || spsmInside(other, x)) << i;
    }
    // Degenerate triangles contain nothing.
    EXPECT_FALSE(spsmInside(flat(vec2(1.0f), vec2(2.0f), vec2(3.0f), 1.0f), vec2(2.0f)));
    // Depth: a triangle facing the light at z = 4: the ray through any x inside meets it at 4.
    SpsmTriangle plane = flat(vec2(0.0f), vec2(64.0f, 0.0f), vec2(0.0f, 64.0f), 4.0f);
    EXPECT_NEAR(spsmDepthAt(plane, vec2(10.0f, 20.0f)), 4.0f, 1e-5f);
    EXPECT_EQ(spsmTriangleTest(plane, vec2(10.0f, 20.0f), 6.0f, 0.01f), 2) << "in front of p: a hit";
    EXPECT_EQ(spsmTriangleTest(plane, vec2(10.0f, 20.0f), 4.0f, 0.01f), 1) << "p on it";
    EXPECT_EQ(spsmTriangleTest(plane, vec2(10.0f, 20.0f), 3.0f, 0.01f), 1) << "p in front of it";
    EXPECT_EQ(spsmTriangleTest(plane, vec2(10.0f, 65.0f), 6.0f, 0.01f), 0) << "outside";
    // A tilted plane: 1/z affine in x, so the depth at the midpoint is the harmonic mean.
    SpsmTriangle tilted = makeTriangle(vec2(0.0f), vec2(64.0f, 0.0f), vec2(0.0f, 64.0f), vec3(0.5f, 0.2f, 0.4f));
    float z0 = spsmDepthAt(tilted, vec2(10.0f, 8.0f)), z1 = spsmDepthAt(tilted, vec2(30.0f, 8.0f));
    EXPECT_NEAR(spsmDepthAt(tilted, vec2(20.0f, 8.0f)), 2.0f / (1.0f / z0 + 1.0f / z1), 1e-4f);
    // Where the extrapolated plane passes behind the light (1/z <= 0) it is never in front.
    SpsmTriangle steep = makeTriangle(vec2(0.0f), vec2(10.0f, 0.0f), vec2(0.0f, 10.0f), vec3(0.2f, 0.1f, 0.2f));
    EXPECT_EQ(spsmDepthAt(steep, vec2(30.0f, 0.0f)), SPSM_FAR);
    // The bias covers a receiver on a triangle stored with its packing error.
    SpsmTriangle sloped = makeTriangle(vec2(2.0f), vec2(60.0f, 2.0f), vec2(2.0f, 60.0f), vec3(0.5f, 0.1f, 0.3f));
    SpsmTriangle stored = spsmUnpack(spsmPack(sloped, 64.0f), 64.0f);
    for (vec2 x : {vec2(5.0f), vec2(30.0f, 10.0f), vec2(10.0f, 40.0f)})
        EXPECT_EQ(spsmTriangleTest(stored, x, spsmDepthAt(sloped, x), 0.0f), 1) << "p on its own stored triangle";
}

// ---- the tangent estimate and the reconstruction ---------------------------------------------------
// The reconstruction's depths (random:7100-7102): a sliver (a thin plate's side face seen edge-on
// from the light) beside a texel centre gives the depth of its nearest point, not its plane's
// extrapolation; a triangle covering the centre gives its depth there.
TEST(SpsmMath, NeighbourDepthsAreTheTrianglesNearestPoints) {
    // A sliver from (0, 0) at z = 5 to (10, 0.1) at z = 3: beside its near end, its depth is about 5.
    const SpsmTriangle sliver = makeTriangle(vec2(0.0f, 0.0f), vec2(10.0f, 0.1f), vec2(10.0f, 0.12f),
                                             vec3(1.0f / 5.0f, 1.0f / 3.0f, 1.0f / 3.0f));
    EXPECT_NEAR(1.0f / spsmInverseDepthNearest(sliver, vec2(-0.5f, 0.5f)), 5.0f, 1e-4f);
    EXPECT_NEAR(1.0f / spsmInverseDepthNearest(sliver, vec2(5.0f, 1.0f)), 1.0f / (0.5f / 5.0f + 0.5f / 3.0f), 1e-2f);
    EXPECT_FALSE(spsmOccludesByDepth(sliver, vec2(-0.5f, 0.5f), 5.05f, 0.1f)) << "the near end is beside the receiver";
    const SpsmTriangle covering = flat(vec2(0.0f), vec2(8.0f, 0.0f), vec2(0.0f, 8.0f), 2.0f);
    EXPECT_FLOAT_EQ(spsmInverseDepthNearest(covering, vec2(1.0f, 1.0f)), spsmInverseDepthAt(covering, vec2(1.0f, 1.0f)));
    EXPECT_TRUE(spsmOccludesByDepth(covering, vec2(1.0f, 1.0f), 4.0f, 0.1f));
}

// Bits k = (dy + 1) * 3 + dx + 1.
unsigned maskOf(std::initializer_list<int> ks) {
    unsigned m = 0;
    for (int k : ks) m |= 1u << unsigned(k);
    return m;
}

TEST(SpsmMath, EdgeNormalPointsFromTheLitToTheShadowedNeighbours) {
    vec2 top = spsmEdgeNormal(maskOf({6, 7, 8}));
    EXPECT_GT(top.y, 0.0f);
    EXPECT_EQ(top.x, 0.0f);
    vec2 left = spsmEdgeNormal(maskOf({0, 3, 6}));
    EXPECT_LT(left.x, 0.0f);
    EXPECT_EQ(left.y, 0.0f);
    vec2 corner = normalize(spsmEdgeNormal(maskOf({5, 7, 8})));  // the upper right corner
    EXPECT_NEAR(corner.x, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(corner.y, std::sqrt(0.5f), 1e-6f);
    EXPECT_EQ(length(spsmEdgeNormal(0u)), 0.0f) << "nothing occludes: no edge";
    EXPECT_EQ(length(spsmEdgeNormal(511u)), 0.0f) << "everything occludes: no edge";
    EXPECT_EQ(length(spsmEdgeNormal(maskOf({0, 8}))), 0.0f) << "opposite corners: no side";
}

// An occluder whose lower boundary is the line y = y0 (above it: occluded), tessellated coarsely:
// the 3x3 texels above the line store big triangles whose vertices lie on the line.
struct Neighbourhood {
    SpsmTriangle tris[9];
    unsigned occluding = 0;
};

Neighbourhood straightEdge(float y0, float slope) {
    Neighbourhood n;
    auto line = [&](float x) { return y0 + slope * (x - 8.5f); };
    for (int k = 0; k < 9; ++k) {
        vec2 centre(8.5f + float(k % 3 - 1), 8.5f + float(k / 3 - 1));
        float x0 = std::floor(centre.x) - 1.0f, x1 = x0 + 3.0f;  // a triangle 3 texels wide per column
        n.tris[k] = flat(vec2(x0, line(x0)), vec2(x1, line(x1)), vec2(0.5f * (x0 + x1), line(0.5f * (x0 + x1)) + 6.0f), 2.0f);
        if (centre.y > line(centre.x)) n.occluding |= 1u << unsigned(k);
    }
    return n;
}

TEST(SpsmMath, ReconstructedEdgeSeparatesBothSidesOfAStraightEdge) {
    for (float slope : {0.0f, 0.3f, -0.4f}) {
        Neighbourhood n = straightEdge(8.2f, slope);
        for (float dy : {-0.3f, -0.05f, 0.05f, 0.3f}) {
            vec2 x(8.6f, 8.2f + slope * (8.6f - 8.5f) + dy);
            SpsmEdge e = spsmReconstructEdge(n.tris, n.occluding, x, vec2(8.5f, 8.5f));
            ASSERT_EQ(e.decided, 1) << slope << " " << dy;
            EXPECT_EQ(e.shadowed, dy > 0.0f ? 1.0f : 0.0f) << "slope " << slope << " dy " << dy;
            EXPECT_GT(e.normal.y, 0.5f) << "the normal points into the occluder";
            EXPECT_GE(e.kept, 2);
        }
    }
}

TEST(SpsmMath, VerticesHiddenBehindAnEdgeAreDiscarded) {
    // A big triangle whose lower edge is y = 8 and, inside it, a small one whose lowest vertex
    // (8.5, 9.5) points towards the lit side: that vertex is behind the big triangle's edge.
    Neighbourhood n;
    SpsmTriangle big = flat(vec2(4.0f, 8.0f), vec2(13.0f, 8.0f), vec2(8.5f, 16.0f), 2.0f);
    SpsmTriangle small = flat(vec2(8.5f, 9.5f), vec2(9.5f, 10.5f), vec2(7.5f, 10.5f), 2.0f);
    for (int k = 0; k < 9; ++k) n.tris[k] = k == 7 ? small : big;
    n.occluding = maskOf({6, 7, 8});
    vec2 normal(0.0f, 1.0f), tangent(-1.0f, 0.0f);
    EXPECT_TRUE(spsmVertexHidden(spsmDistinctOccluders(n.tris, n.occluding), small.a, vec2(8.5f), normal, tangent));
    EXPECT_FALSE(spsmVertexHidden(spsmDistinctOccluders(n.tris, n.occluding), big.a, vec2(8.5f), normal, tangent));
    // The edge is the big triangle's: a point between y = 8 and the small vertex is shadowed...
    SpsmEdge e = spsmReconstructEdge(n.tris, n.occluding, vec2(8.5f, 8.6f), vec2(8.5f, 8.5f));
    ASSERT_EQ(e.decided, 1);
    EXPECT_EQ(e.shadowed, 1.0f);
    EXPECT_NEAR(e.dEdge, -0.5f, 1e-5f);
    // ... and one below it lit.
    EXPECT_EQ(spsmReconstructEdge(n.tris, n.occluding, vec2(8.5f, 7.9f), vec2(8.5f, 8.5f)).shadowed, 0.0f);
}

// The reconstruction links the distinct occluding triangles only: neighbouring texels storing the
// same triangle add no vertex and no edge. The mask marks the first of each, in place.
TEST(SpsmMath, DistinctOccludersKeepEachOccludingTriangleOnce) {
    Neighbourhood n = straightEdge(8.2f, 0.3f);  // one triangle per column, repeated in its rows
    SpsmOccluders o = spsmDistinctOccluders(n.tris, n.occluding);
    int expected = 0;
    for (int k = 0; k < 9; ++k) {
        bool first = ((n.occluding >> unsigned(k)) & 1u) != 0u;
        for (int j = 0; j < k; ++j) first = first && !(((n.occluding >> unsigned(j)) & 1u) && spsmSameTriangle(n.tris[j], n.tris[k]));
        expected += first;
    }
    EXPECT_EQ(o.count, expected);
    EXPECT_LE(o.count, 3) << "three columns";
    for (int i = 0; i < 9; ++i) {
        EXPECT_TRUE(spsmSameTriangle(o.t[i], n.tris[i])) << "in place";
        EXPECT_TRUE(!spsmOccluderUsed(o, i) || ((n.occluding >> unsigned(i)) & 1u)) << "only occluders";
        for (int j = 0; j < i; ++j)
            if (spsmOccluderUsed(o, i) && spsmOccluderUsed(o, j)) EXPECT_FALSE(spsmSameTriangle(o.t[i], o.t[j]));
    }
    EXPECT_EQ(std::bitset<9>(o.mask).count(), size_t(o.count));
    Neighbourhood one;
    for (int k = 0; k < 9; ++k) one.tris[k] = flat(vec2(4.0f, 8.0f), vec2(13.0f, 8.0f), vec2(8.5f, 16.0f), 2.0f);
    EXPECT_EQ(spsmDistinctOccluders(one.tris, maskOf({5, 6, 7, 8})).count, 1);
    EXPECT_EQ(spsmDistinctOccluders(one.tris, 0u).count, 0);
}

// The build's rank: a triangle covering the texel centre keeps its depth there; one that does not
// is ranked by its plane extrapolated there, made SPSM_RANK_MARGIN farther.
TEST(SpsmMath, RankFavoursTheTriangleCoveringTheCentreWithinTheMargin) {
    SpsmTriangle covering = flat(vec2(0.0f), vec2(4.0f, 0.0f), vec2(0.0f, 4.0f), 5.0f);
    SpsmTriangle beside = flat(vec2(1.6f, 1.6f), vec2(6.0f, 1.6f), vec2(1.6f, 6.0f), 5.0f * 0.99f);  // 1% nearer
    vec2 centre(1.5f, 1.5f);
    EXPECT_FLOAT_EQ(spsmRankInverseDepth(covering, centre), 0.2f);
    EXPECT_LT(spsmRankInverseDepth(beside, centre), spsmRankInverseDepth(covering, centre)) << "1% nearer: not enough";
    SpsmTriangle steep = makeTriangle(vec2(1.6f, 1.6f), vec2(6.0f, 1.6f), vec2(1.6f, 6.0f), vec3(0.3f, 0.2f, 0.2f));
    EXPECT_GT(spsmRankInverseDepth(steep, centre), spsmRankInverseDepth(covering, centre))
        << "a plane rising steeply towards the light takes the texel";
}

TEST(SpsmMath, NoTangentOrNoVertexLeavesTheDecisionToTheFallback) {
    Neighbourhood n = straightEdge(8.2f, 0.0f);
    EXPECT_EQ(spsmReconstructEdge(n.tris, 0u, vec2(8.5f), vec2(8.5f)).decided, 0);
    EXPECT_EQ(spsmReconstructEdge(n.tris, 511u, vec2(8.5f), vec2(8.5f)).decided, 0);
    EXPECT_EQ(spsmReconstructEdge(n.tris, maskOf({0, 8}), vec2(8.5f), vec2(8.5f)).decided, 0);
}

// ---- the same GLSL on the GPU ----------------------------------------------------------------------
class SpsmGpu : public testing::GLTest {};

TEST_F(SpsmGpu, SharedMathMatchesCpuOnAGrid) {
    constexpr int n = 32;
    Texture packed(n, n, GL_RGBA32UI);
    std::vector<std::unique_ptr<Texture>> outs;
    std::vector<const Texture*> attachments{&packed};
    for (int i = 0; i < 7; ++i) {
        outs.push_back(std::make_unique<Texture>(n, n, GL_RGBA32F));
        attachments.push_back(outs.back().get());
    }
    Framebuffer fbo(attachments, nullptr);
    ShaderProgram program("common/fullscreen.vert", "tests/spsm/spsm_math.frag");
    program.use();
    fbo.bind(n, n);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    auto read = [&](const Texture& t) {
        std::vector<float> v(size_t(n) * n * 4);
        glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(v.size() * 4), v.data());
        return v;
    };
    program.set("variant", 0);
    drawFullscreenTriangle();
    std::vector<uint32_t> words(size_t(n) * n * 4);
    glGetTextureImage(packed.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(words.size() * 4), words.data());
    std::vector<std::vector<float>> first;
    for (auto& t : outs) first.push_back(read(*t));
    program.set("variant", 1);
    drawFullscreenTriangle();
    std::vector<std::vector<float>> second;
    for (int i = 0; i < 5; ++i) second.push_back(read(*outs[size_t(i)]));
    // Same operations; the GPU may fuse multiply-adds and round divisions its own way. 1e-4
    // relative catches any change of formula; the packed words and decisions must agree exactly
    // except where a value sits within rounding of a threshold (allowed in 1% of the cells).
    auto near = [](float gpu, float cpu) { return gpu == cpu || std::abs(gpu - cpu) <= 1e-4f * std::max(1.0f, std::abs(cpu)); };
    int badCells = 0, packedDiffer = 0;
    std::string first10;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            size_t i = size_t(y) * n + x;
            SpsmCaseOut o = spsmCase(x, y);
            bool differ = false;
            for (int c = 0; c < 4; ++c) differ = differ || words[i * 4 + size_t(c)] != o.code[c];
            packedDiffer += differ;
            bool bad = false;
            vec4 cpu[12] = {o.a, o.b, o.c, o.d, o.e, o.f, o.g, o.h, o.i, o.j, o.k, o.l};
            for (int k = 0; k < 12; ++k)
                for (int c = 0; c < 4; ++c) {
                    float gpu = k < 7 ? first[size_t(k)][i * 4 + size_t(c)] : second[size_t(k - 7)][i * 4 + size_t(c)];
                    if (!near(gpu, cpu[k][c])) {
                        if (!bad && badCells < 10)
                            first10 += "\n  output " + std::to_string(k) + "." + std::to_string(c) + " at " + std::to_string(x) +
                                       "," + std::to_string(y) + ": gpu " + std::to_string(gpu) + " cpu " + std::to_string(cpu[k][c]);
                        bad = true;
                    }
                }
            badCells += bad;
        }
    EXPECT_LE(badCells, n * n / 100) << first10;
    EXPECT_LE(packedDiffer, n * n / 100);
    RecordProperty("cells_differing", badCells);
}

// ---- conservative rasterization: every texel a triangle touches gets a fragment ----------------------
// Area of the unit square at lo clipped by triangle abc, in double precision (independent of the
// shader's single-precision clip).
double touchedArea(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 lo) {
    std::vector<glm::dvec2> poly{lo, lo + glm::dvec2(1, 0), lo + glm::dvec2(1, 1), lo + glm::dvec2(0, 1)};
    double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (area < 0) std::swap(b, c);
    glm::dvec2 v[3] = {a, b, c};
    for (int e = 0; e < 3 && !poly.empty(); ++e) {
        glm::dvec2 p0 = v[e], p1 = v[(e + 1) % 3];
        auto f = [&](glm::dvec2 p) { return (p1.x - p0.x) * (p.y - p0.y) - (p1.y - p0.y) * (p.x - p0.x); };
        std::vector<glm::dvec2> out;
        for (size_t i = 0; i < poly.size(); ++i) {
            glm::dvec2 p = poly[i], q = poly[(i + 1) % poly.size()];
            double fp = f(p), fq = f(q);
            if (fp >= 0) out.push_back(p);
            if ((fp >= 0) != (fq >= 0)) out.push_back(p + (fp / (fp - fq)) * (q - p));
        }
        poly = out;
    }
    double twice = 0;
    for (size_t i = 0; i < poly.size(); ++i) twice += poly[i].x * poly[(i + 1) % poly.size()].y - poly[i].y * poly[(i + 1) % poly.size()].x;
    return std::abs(twice) * 0.5;
}

// The separating-axis test the build keeps fragments by, against the double-precision overlap
// area: every texel with overlap is touched; a texel more than 1e-3 texels away is not.
TEST(SpsmMath, TouchesTexelMatchesTheExactOverlap) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int touched = 0, checked = 0;
    for (int i = 0; i < 400; ++i) {
        float scale = i % 3 == 0 ? 6.0f : (i % 3 == 1 ? 1.0f : 0.1f);
        vec2 a(4.0f + u(rng) * 8.0f, 4.0f + u(rng) * 8.0f);
        vec2 b = a + (vec2(u(rng), u(rng)) - 0.5f) * 2.0f * scale, c = a + (vec2(u(rng), u(rng)) - 0.5f) * 2.0f * scale;
        if (i % 7 == 0) c = mix(a, b, u(rng)) + vec2(0.003f, -0.002f);  // a needle
        SpsmTriangle t = flat(a, b, c, 3.0f);
        if (std::abs(spsmEdgeFunction(a, b, c)) < 1e-6f) continue;
        for (int ty = 0; ty < 20; ++ty)
            for (int tx = 0; tx < 20; ++tx) {
                glm::dvec2 lo(tx, ty);
                double area = touchedArea(a, b, c, lo);
                double near = touchedArea(a, b, c, lo - 1e-3) + touchedArea(a, b, c, lo + 1e-3);
                bool test = spsmTouchesTexel(t, vec2(tx, ty));
                ++checked;
                touched += test;
                if (area > 1e-9) EXPECT_TRUE(test) << i << " texel " << tx << "," << ty << " area " << area;
                if (near <= 0.0) EXPECT_FALSE(test) << i << " texel " << tx << "," << ty;
            }
    }
    EXPECT_GT(touched, 2000);
    EXPECT_GT(checked, 100000);
    // Degenerate triangles touch nothing.
    EXPECT_FALSE(spsmTouchesTexel(flat(vec2(1.0f), vec2(2.0f), vec2(3.0f), 1.0f), vec2(1.0f)));
}

struct BuildRig {
    static constexpr int size = 64;
    static constexpr float tanHalfFov = 0.5f;
    Texture map{size, size, GL_RGBA32UI};
    Texture depth{size, size, GL_DEPTH_COMPONENT32F};
    Framebuffer fbo{{&map}, &depth};
    GLuint vao = 0, vbo = 0;
    BuildRig() {
        glCreateVertexArrays(1, &vao);
        glCreateBuffers(1, &vbo);
        glVertexArrayVertexBuffer(vao, 0, vbo, 0, sizeof(glm::vec3));
        glEnableVertexArrayAttrib(vao, 0);
        glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, 0, 0);
    }
    ~BuildRig() {
        glDeleteBuffers(1, &vbo);
        glDeleteVertexArrays(1, &vao);
    }
    // The light-view point whose projection is texel coordinate x, at depth z.
    static glm::vec3 at(glm::vec2 x, float z) { return spsmRayDirection(x, float(size), tanHalfFov) * z; }
    // Renders the triangles (light-view space) and returns the stored words.
    std::vector<uint32_t> render(const std::vector<glm::vec3>& vertices, bool conservative) {
        glNamedBufferData(vbo, GLsizeiptr(vertices.size() * sizeof(glm::vec3)), vertices.data(), GL_STATIC_DRAW);
        std::vector<std::string> defines;
        if (conservative) defines.push_back("CONSERVATIVE");
        const ShaderProgram& program = programCache().get("spsm/build.vert", "spsm/build.frag", defines, "spsm/build.geom");
        program.use();
        program.set("worldFromObject", glm::mat4(1.0f));
        program.set("lightViewFromWorld", glm::mat4(1.0f));
        program.set("smSize", float(size));
        program.set("tanHalfFov", tanHalfFov);
        program.set("nearZ", 0.1f);
        PipelineState::depthGreaterReversed().apply();
        fbo.bind(size, size);
        const GLuint none[4] = {0, 0, 0, 0};
        const float zero = 0.0f;
        glClearNamedFramebufferuiv(fbo.id(), GL_COLOR, 0, none);
        glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &zero);
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
        glBindVertexArray(0);
        PipelineState::fullscreen().apply();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        std::vector<uint32_t> words(size_t(size) * size * 4);
        resetPackState();
        glGetTextureImage(map.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(words.size() * 4), words.data());
        return words;
    }
};

TEST_F(SpsmGpu, ConservativeBuildGivesEveryTouchedTexelAFragment) {
    BuildRig rig;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int missed = 0, extra = 0, conservativeTexels = 0, centreTexels = 0, triangles = 0;
    for (int i = 0; i < 240; ++i) {
        // Big, small, tiny (under a texel), thin (a needle) and sliver (one vertex near the opposite edge).
        float scale = i % 4 == 0 ? 20.0f : (i % 4 == 1 ? 3.0f : (i % 4 == 2 ? 0.3f : 0.05f));
        glm::vec2 a(8.0f + u(rng) * 40.0f, 8.0f + u(rng) * 40.0f);
        glm::vec2 b = a + glm::vec2(u(rng) - 0.5f, u(rng) - 0.5f) * 2.0f * scale;
        glm::vec2 c = a + glm::vec2(u(rng) - 0.5f, u(rng) - 0.5f) * 2.0f * scale;
        if (i % 5 == 3) c = glm::mix(a, b, u(rng)) + glm::vec2(0.02f, -0.01f) * u(rng);  // a needle
        if (std::abs(spsmEdgeFunction(a, b, c)) < 1e-5f) continue;
        // A triangle whose quantised vertices collapse (under a coordinate step across) stores nothing.
        SpsmTriangle q = spsmUnpack(spsmPack(flat(a, b, c, 3.0f), float(BuildRig::size)), float(BuildRig::size));
        if (std::abs(spsmEdgeFunction(q.a, q.b, q.c)) < 1e-6f) continue;
        ++triangles;
        float za = 3.0f + u(rng), zb = 3.0f + u(rng), zc = 3.0f + u(rng);
        std::vector<glm::vec3> tri{BuildRig::at(a, za), BuildRig::at(b, zb), BuildRig::at(c, zc)};
        std::vector<uint32_t> words = rig.render(tri, true);
        std::vector<uint32_t> centre = rig.render(tri, false);
        // The triangle as stored (quantised): what the look-up tests and what must be covered.
        SpsmTriangle stored{};
        bool found = false;
        for (size_t k = 0; k < words.size() && !found; k += 4)
            if (words[k] | words[k + 1] | words[k + 2] | words[k + 3]) {
                stored = spsmUnpack(uvec4(words[k], words[k + 1], words[k + 2], words[k + 3]), float(BuildRig::size));
                found = true;
            }
        ASSERT_TRUE(found) << "triangle " << i << " stored nowhere";
        for (int ty = 0; ty < BuildRig::size; ++ty)
            for (int tx = 0; tx < BuildRig::size; ++tx) {
                size_t k = (size_t(ty) * BuildRig::size + size_t(tx)) * 4;
                bool has = words[k] | words[k + 1] | words[k + 2] | words[k + 3];
                bool hasCentre = centre[k] | centre[k + 1] | centre[k + 2] | centre[k + 3];
                double area = touchedArea(stored.a, stored.b, stored.c, glm::dvec2(tx, ty));
                // Within 1e-3 texels of the square counts as touching (the shader's clip tolerance).
                double near = touchedArea(stored.a, stored.b, stored.c, glm::dvec2(tx, ty) - 1e-3) +
                              touchedArea(stored.a, stored.b, stored.c, glm::dvec2(tx, ty) + 1e-3);
                if (area > 1e-9 && !has && missed++ < 10)
                    ADD_FAILURE() << "triangle " << i << " (" << stored.a.x << "," << stored.a.y << " " << stored.b.x << ","
                                  << stored.b.y << " " << stored.c.x << "," << stored.c.y << ") touches texel " << tx << ","
                                  << ty << " (area " << area << ", spsmTouchesTexel " << spsmTouchesTexel(stored, vec2(tx, ty))
                                  << ") but got no fragment";
                if (has && area <= 0.0 && near <= 0.0 && extra++ < 10)
                    ADD_FAILURE() << "triangle " << i << " got texel " << tx << "," << ty << " it does not touch";
                conservativeTexels += has;
                centreTexels += hasCentre;
                if (hasCentre && !has)
                    ADD_FAILURE() << "triangle " << i << ": texel " << tx << "," << ty << " has a centre sample but no "
                                  << "conservative fragment (area " << area << ", near " << near << ")";
            }
    }
    EXPECT_GT(triangles, 200);
    EXPECT_EQ(missed, 0);
    EXPECT_EQ(extra, 0);
    // Centre sampling misses the edge texels: the lesson's claim, measured.
    EXPECT_LT(double(centreTexels), 0.8 * double(conservativeTexels));
    RecordProperty("texels_conservative", conservativeTexels);
    RecordProperty("texels_centre_sampled", centreTexels);
}

TEST_F(SpsmGpu, EachTexelKeepsTheTriangleWhosePlaneIsNearestAtItsCentre) {
    BuildRig rig;
    // A floor at depth 6 over the whole map and a plate at depth 3 covering the left part of texel
    // column 20 (x < 20.3): the plate wins column 20 although it misses that texel's centre (its
    // plane there is at 3).
    auto quad = [](glm::vec2 lo, glm::vec2 hi, float z) {
        return std::vector<glm::vec3>{BuildRig::at(lo, z), BuildRig::at({hi.x, lo.y}, z), BuildRig::at(hi, z),
                                      BuildRig::at(lo, z), BuildRig::at(hi, z), BuildRig::at({lo.x, hi.y}, z)};
    };
    std::vector<glm::vec3> v = quad({-2.0f, -2.0f}, {66.0f, 66.0f}, 6.0f);
    std::vector<glm::vec3> plate = quad({10.0f, 10.0f}, {20.3f, 30.0f}, 3.0f);
    v.insert(v.end(), plate.begin(), plate.end());
    std::vector<uint32_t> words = rig.render(v, true);
    auto depthAt = [&](int tx, int ty) {
        size_t k = (size_t(ty) * BuildRig::size + size_t(tx)) * 4;
        SpsmTriangle t = spsmUnpack(uvec4(words[k], words[k + 1], words[k + 2], words[k + 3]), float(BuildRig::size));
        return spsmDepthAt(t, vec2(float(tx) + 0.5f, float(ty) + 0.5f));
    };
    EXPECT_NEAR(depthAt(20, 15), 3.0f, 0.01f) << "the plate, though it misses the centre";
    EXPECT_NEAR(depthAt(21, 15), 6.0f, 0.02f);
    EXPECT_NEAR(depthAt(15, 15), 3.0f, 0.01f);
    EXPECT_NEAR(depthAt(40, 40), 6.0f, 0.02f);
}

// ---- the look-up: the CPU mirror agrees with the GPU, and spsm against exact hard shadows ----------
struct SpsmFrame {
    Image visibility, branches, positions, normals;
    std::vector<uint32_t> words;
    int smSize = 0;
    LightView view;
    Light light;
};

SpsmFrame renderSpsm(const std::string& sceneName, int size, std::vector<std::pair<std::string, std::string>> sets) {
    Scene scene = loadScene(sceneName);
    RenderOptions o;
    o.width = o.height = size;
    o.technique = "spsm";
    o.lightSize = 0.0f;
    o.sets = std::move(sets);
    Renderer renderer(scene, o);
    renderer.renderFrame(0, {"visibility", "gbuffer", "L0/spsm", "L0/spsm_branch"});
    SpsmFrame f;
    f.visibility = renderer.visibility();
    f.positions = renderer.positions();
    f.normals = renderer.normals();
    const Resource* map = renderer.pool().find("L0/spsm");
    const Resource* branch = renderer.pool().find("L0/spsm_branch");
    EXPECT_TRUE(map && branch);
    if (map && branch) {
        f.words = readTextureUint(map->texture);
        f.smSize = map->texture.width();
        f.branches = readTexture(branch->texture, 1);
    }
    const LightState* light = renderer.lights().at(0);
    f.light = light->light;
    f.view = light->view;
    return f;
}

// At the defaults, and with neighbourhood 1 (the texel's own triangle alone: without reconstruction
// the first step decides every pixel and nothing is listed; with it, the 3x3 depth comparisons
// still run and the neighbours' triangles are not intersected).
TEST_F(SpsmGpu, CpuLookUpAgreesWithTheGpuOnEveryPixel) {
    struct Setting {
        int neighbourhood;
        bool reconstruction;
    };
    for (Setting setting : {Setting{3, true}, Setting{1, false}, Setting{1, true}})
    for (const char* sceneName : {"square-occluder", "contact", "overlapping-occluders"}) {
        SCOPED_TRACE("neighbourhood " + std::to_string(setting.neighbourhood) + ", reconstruction " +
                     std::to_string(setting.reconstruction));
        SpsmFrame f = renderSpsm(sceneName, 160,
                                 {{"sm_size", "128"},
                                  {"neighbourhood", std::to_string(setting.neighbourhood)},
                                  {"reconstruction", setting.reconstruction ? "true" : "false"}});
        ASSERT_FALSE(f.words.empty());
        const TechniqueDesc& d = spsmTechnique();
        float biasConst = float(d.findParam("bias_const")->defaultValue), biasSlope = float(d.findParam("bias_slope")->defaultValue);
        int pixels = 0, differ = 0;
        std::array<int, 9> seen{};
        for (int y = 0; y < f.visibility.height; ++y)
            for (int x = 0; x < f.visibility.width; ++x) {
                glm::vec3 p(f.positions.at(x, y, 0), f.positions.at(x, y, 1), f.positions.at(x, y, 2));
                glm::vec3 n(f.normals.at(x, y, 0), f.normals.at(x, y, 1), f.normals.at(x, y, 2));
                if (std::isnan(p.x)) continue;
                ++pixels;
                int gpuBranch = int(std::lround(f.branches.at(x, y)));
                seen[size_t(gpuBranch)]++;
                if (!inFrontOfTangentPlane(p, n, f.light.position)) continue;
                glm::vec4 coord = shadowMapCoord(f.view.viewFromWorld, f.view.clipFromView, p);
                if (coord.w == 0.0f) continue;
                float texelWorld = shadowTexelWorldSize(coord.z, f.view.tanHalfFov, float(f.smSize));
                float cosTheta = std::abs(dot(n, normalize(f.light.position - p)));
                float bias = shadowDepthBias(texelWorld, biasConst, biasSlope, cosTheta);
                SpsmLookup l = spsmLookup(f.words, f.smSize, glm::vec2(coord) * float(f.smSize), coord.z, bias,
                                          setting.neighbourhood, setting.reconstruction);
                if (l.branch != gpuBranch || l.visibility != f.visibility.at(x, y)) ++differ;
            }
        EXPECT_GT(pixels, 10000) << sceneName;
        // Single-precision rounding differs between the two (fused multiply-adds): a handful of
        // pixels exactly on a threshold may go the other way.
        EXPECT_LE(differ, pixels / 500) << sceneName;
        EXPECT_GT(seen[1] + seen[2] + seen[7], pixels / 2) << sceneName << ": most pixels end at their own texel";
        if (setting.neighbourhood == 1) EXPECT_EQ(seen[3] + seen[4], 0) << sceneName << ": no neighbour is intersected";
        if (!setting.reconstruction) EXPECT_EQ(seen[5], 0) << sceneName << ": no edge is reconstructed";
        if (setting.neighbourhood == 3 && setting.reconstruction)
            RecordProperty(std::string(sceneName) + "_differ", differ);
    }
}

}  // namespace
}  // namespace shadowlab

namespace shadowlab {
namespace {

// ---- end to end against exact hard shadows (issue 23's "must hold", as far as it holds) ------------
size_t misclassified(const Image& test, const Image& reference) {
    size_t bad = 0;
    for (size_t i = 0; i < test.data.size(); ++i)
        if (std::isfinite(test.data[i]) && std::isfinite(reference.data[i])) bad += (test.data[i] > 0.5f) != (reference.data[i] > 0.5f);
    return bad;
}

Image renderVisibility(const Scene& scene, const std::string& technique, std::vector<std::pair<std::string, std::string>> sets,
                       float lightSize, int size = 512) {
    RenderOptions o;
    o.width = o.height = size;
    o.technique = technique;
    o.sets = std::move(sets);
    o.lightSize = lightSize;
    Renderer r(scene, o);
    r.renderFrame(0, {"visibility"});
    return r.visibility();
}

class SpsmRender : public testing::GLTest {};

// Point light, sm_size 256, 512x512, against raytraced rays = 1 (the exact hard shadow). The issue
// asks for a tenth of hard's misclassified pixels: measured 4/544 on square-occluder, 29/1828 on
// overlapping-occluders and 62/776 on contact, whose curved meshes come closest to the bound
// (techniques/spsm/README.md).
TEST_F(SpsmRender, MisclassifiesFarFewerPixelsThanHardAtTheSameMapSize) {
    struct Case {
        const char* scene;
        double bound;
    };
    for (Case c : {Case{"square-occluder", 0.1}, Case{"overlapping-occluders", 0.1}, Case{"contact", 0.1}}) {
        SCOPED_TRACE(c.scene);
        Scene scene = loadScene(c.scene);
        Image exact = renderVisibility(scene, "raytraced", {{"rays", "1"}}, 0.0f);
        size_t hard = misclassified(renderVisibility(scene, "hard", {{"sm_size", "256"}}, 0.0f), exact);
        size_t spsm = misclassified(renderVisibility(scene, "spsm", {{"sm_size", "256"}}, 0.0f), exact);
        RecordProperty(std::string(c.scene) + "_hard", int(hard));
        RecordProperty(std::string(c.scene) + "_spsm", int(spsm));
        EXPECT_GT(hard, 300u) << "hard at 256^2 aliases";
        EXPECT_LE(double(spsm), c.bound * double(hard));
    }
}

// Generated scenes (casters the scenes do not have: cylinders and spheres lit near their
// terminators, thin plates lying on the floor, seen from lights almost above their corners): the
// same measure. Before the reconstruction took each neighbour's depth at the stored triangle's
// point nearest the texel centre (spsmInverseDepthNearest) rather than its plane extrapolated there,
// spsm misclassified more pixels than `hard` on four of these six (random:7100: 197 against 0, on
// a cylinder's lit side; 7102: 233 against 121, beside a plate on the floor).
TEST_F(SpsmRender, MisclassifiesNoMoreThanHardOnGeneratedScenes) {
    size_t hardTotal = 0, spsmTotal = 0;
    for (int seed = 7100; seed <= 7105; ++seed) {
        const std::string name = "random:" + std::to_string(seed);
        SCOPED_TRACE(name);
        const Scene scene = loadScene(name);
        const Image exact = renderVisibility(scene, "raytraced", {{"rays", "1"}}, 0.0f);
        const size_t hard = misclassified(renderVisibility(scene, "hard", {{"sm_size", "256"}}, 0.0f), exact);
        const size_t spsm = misclassified(renderVisibility(scene, "spsm", {{"sm_size", "256"}}, 0.0f), exact);
        std::printf("[ spsm     ] %s: hard %zu, spsm %zu misclassified\n", name.c_str(), hard, spsm);
        // Both light the thin side faces that the reference shadows (7102, 7103); 7100 keeps 8 pixels
        // on the cylinder's terminator (197 before), where `hard` has none.
        EXPECT_LE(spsm, hard + 10);
        hardTotal += hard;
        spsmTotal += spsm;
    }
    EXPECT_LE(10 * spsmTotal, 3 * hardTotal);  // measured 413 against 1627
}

// Conservative rasterization is what the texel's triangle test rests on: without it (centre
// samples) the edge texels lose their triangles and the errors multiply.
TEST_F(SpsmRender, ConservativeRasterizationMatters) {
    Scene scene = loadScene("overlapping-occluders");
    Image exact = renderVisibility(scene, "raytraced", {{"rays", "1"}}, 0.0f, 256);
    size_t on = misclassified(renderVisibility(scene, "spsm", {{"sm_size", "128"}}, 0.0f, 256), exact);
    size_t off = misclassified(renderVisibility(scene, "spsm", {{"sm_size", "128"}, {"conservative", "false"}}, 0.0f, 256), exact);
    EXPECT_LT(3 * on, off);
}

// A hard-shadow technique: an area light is taken at its centre, so the light's size changes nothing.
TEST_F(SpsmRender, AnAreaLightIsTakenAtItsCentre) {
    Scene scene = loadScene("square-occluder");
    Image point = renderVisibility(scene, "spsm", {{"sm_size", "256"}}, 0.0f, 128);
    Image wide = renderVisibility(scene, "spsm", {{"sm_size", "256"}}, 2.0f, 128);
    EXPECT_EQ(misclassified(point, wide), 0u);
    for (size_t i = 0; i < wide.data.size(); ++i) ASSERT_TRUE(wide.data[i] == 0.0f || wide.data[i] == 1.0f) << "hard: 0 or 1";
}

// The SPSM's memory in --stats: 16 bytes a texel (the paper: 4 MB at 512^2), and how the build
// rasterized conservatively on this driver.
// The look-up's later steps run over lists of the pixels the step before left undecided
// (lookup.comp): the neighbourhood step over every pixel whose own texel did not decide it, the
// reconstruction over those whose 3x3 depth comparisons disagree. Counted against the branches
// each pixel ends in, on a scene with many small triangles (plant) and point light, sm 256: the
// lists hold no more and no fewer pixels than the steps need.
TEST_F(SpsmRender, EachStepRunsOnlyOnThePixelsTheStepBeforeLeftUndecided) {
    Scene scene = loadScene("plant");
    for (int reconstruction : {1, 0}) {
        SCOPED_TRACE(reconstruction);
        RenderOptions o;
        o.width = o.height = 256;
        o.technique = "spsm";
        o.lightSize = 0.0f;
        o.sets = {{"sm_size", "256"}, {"reconstruction", std::to_string(reconstruction)}};
        Renderer r(scene, o);
        r.renderFrame(0, {"visibility"});
        nlohmann::json stats = r.stats({}, 1, 1);
        const nlohmann::json& c = stats["lights"][0]["counters"]["spsm"];
        auto pixels = [&](const char* branch) { return c["pixels"][branch].get<size_t>(); };
        const nlohmann::json& steps = c["step_pixels"];
        EXPECT_EQ(steps["texel"].get<size_t>(), 256u * 256u);
        size_t neighbourhood = steps["neighbourhood"].get<size_t>();
        size_t rebuilt = steps["reconstruction"].get<size_t>();
        EXPECT_EQ(neighbourhood, pixels("neighbour_hit") + pixels("neighbour_cover") + pixels("reconstructed_edge") +
                                     pixels("fallback"));
        EXPECT_GT(neighbourhood, 256u * 256u / 100) << "plant's leaves leave many pixels to the neighbourhood";
        EXPECT_LT(neighbourhood, 256u * 256u / 4) << "most pixels are decided by their own texel";
        if (reconstruction == 1) {
            EXPECT_GE(rebuilt, pixels("reconstructed_edge"));
            EXPECT_LE(rebuilt, pixels("reconstructed_edge") + pixels("fallback"));
            EXPECT_GT(rebuilt, 0u);
        } else {
            EXPECT_EQ(rebuilt, 0u);
            EXPECT_EQ(pixels("reconstructed_edge"), 0u);
        }
    }
    // Neighbourhood 1 without reconstruction (the bench's floor): the first step decides every
    // pixel, those its texel's triangle leaves undecided lit (fallback), and nothing is listed.
    RenderOptions o;
    o.width = o.height = 256;
    o.technique = "spsm";
    o.lightSize = 0.0f;
    o.sets = {{"sm_size", "256"}, {"neighbourhood", "1"}, {"reconstruction", "false"}};
    Renderer r(scene, o);
    r.renderFrame(0, {"visibility"});
    nlohmann::json stats = r.stats({}, 1, 1);
    const nlohmann::json& c = stats["lights"][0]["counters"]["spsm"];
    EXPECT_EQ(c["step_pixels"]["neighbourhood"].get<size_t>(), 0u);
    EXPECT_EQ(c["step_pixels"]["reconstruction"].get<size_t>(), 0u);
    EXPECT_GT(c["pixels"]["fallback"].get<size_t>(), 256u * 256u / 100) << "what the neighbourhood step gets otherwise";
    EXPECT_EQ(c["pixels"]["neighbour_hit"].get<size_t>() + c["pixels"]["neighbour_cover"].get<size_t>() +
                  c["pixels"]["reconstructed_edge"].get<size_t>(),
              0u);
}

TEST_F(SpsmRender, StatsReportMemoryAndTheRasterization) {
    Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 64;
    o.technique = "spsm";
    Renderer r(scene, o);
    r.renderFrame(0, {"visibility"});
    nlohmann::json stats = r.stats({}, 1, 1);
    const nlohmann::json& c = stats["lights"][0]["counters"]["spsm"];
    EXPECT_EQ(c["memory_bytes"].get<size_t>(), 512u * 512u * 16u);
    EXPECT_EQ(c["memory_bytes"].get<size_t>(), 4u * 1024u * 1024u);
    EXPECT_EQ(c["rasterization"].get<std::string>(), spsmConservativeMethod());
    size_t counted = 0;
    for (const auto& [name, n] : c["pixels"].items()) counted += n.get<size_t>();
    EXPECT_GT(counted, 64u * 64u / 2);
    bool listed = false;
    for (const auto& res : stats["resources"])
        if (res["name"] == "L0/spsm") listed = res["bytes"].get<size_t>() == 512u * 512u * 16u;
    EXPECT_TRUE(listed) << "the pool lists the SPSM with its bytes";
}

}  // namespace
}  // namespace shadowlab
