// CPU tests of the back-projection math (shaders/shared/backprojection.glsl, guennebaud2007 sections
// 3-4): the contour rule table case by case at t = -1, 0, 1, contours that close and bound what
// the inside test says, radial area integration against exact polygon areas (edges on the light
// border, zero-length edges, edges and vertices on the light centre), back-projection against a
// direct ray-plane intersection, and eq. 1 against the pyramid it stands for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "shared/shared.h"

using namespace shadowlab;
using shared::BP_LIGHT_DISK;
using shared::BP_LIGHT_SQUARE;

namespace {

constexpr double kPi = std::numbers::pi;

// ---- independent oracles ---------------------------------------------------------------------------

// Exact area of polygon ∩ light by scanlines: per row, the polygon's x-intervals (even-odd)
// intersected with the light's x-range at that height, in double. Rows are placed by the midpoint
// rule between consecutive "events" (vertex heights, the light's top and bottom, heights where an
// edge crosses the light's border), so the covered length is smooth between rows' boundaries:
// exact for the square (piecewise linear), within ~1e-7 for the disk. Nothing here shares code
// with the radial integration under test.
double scanlineArea(const std::vector<glm::dvec2>& poly, int shape, int rowsPerPiece = 200) {
    std::vector<double> events = {-1.0, 1.0};
    for (size_t i = 0; i < poly.size(); ++i) {
        glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        events.push_back(a.y);
        glm::dvec2 d = b - a;
        if (shape == BP_LIGHT_SQUARE) {
            for (double x : {-1.0, 1.0})
                if (d.x != 0.0) {
                    double s = (x - a.x) / d.x;
                    if (s > 0.0 && s < 1.0) events.push_back(a.y + s * d.y);
                }
        } else {
            double qa = glm::dot(d, d), qb = glm::dot(a, d), qc = glm::dot(a, a) - 1.0;
            double disc = qb * qb - qa * qc;
            if (qa > 0.0 && disc >= 0.0)
                for (double sg : {-1.0, 1.0}) {
                    double s = (-qb + sg * std::sqrt(disc)) / qa;
                    if (s > 0.0 && s < 1.0) events.push_back(a.y + s * d.y);
                }
        }
    }
    for (double& e : events) e = std::clamp(e, -1.0, 1.0);
    std::sort(events.begin(), events.end());
    double area = 0.0;
    std::vector<double> xs;
    for (size_t k = 0; k + 1 < events.size(); ++k) {
        double y0 = events[k], y1 = events[k + 1];
        if (y1 <= y0) continue;
        // y = y0 + (y1 - y0) (1 - cos(pi u)) / 2: rows cluster at the piece's ends, where the disk's
        // sqrt(1 - y^2) has its infinite slope; the midpoint rule in u then converges fast.
        for (int r = 0; r < rowsPerPiece; ++r) {
            double u = (r + 0.5) / rowsPerPiece;
            double y = y0 + (y1 - y0) * 0.5 * (1.0 - std::cos(kPi * u));
            double h = (y1 - y0) * 0.5 * kPi * std::sin(kPi * u) / rowsPerPiece;
            double half = shape == BP_LIGHT_SQUARE ? 1.0 : std::sqrt(std::max(0.0, 1.0 - y * y));
            xs.clear();
            for (size_t i = 0; i < poly.size(); ++i) {
                glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
                if ((a.y <= y) == (b.y <= y)) continue;
                xs.push_back(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
            std::sort(xs.begin(), xs.end());
            for (size_t i = 0; i + 1 < xs.size(); i += 2)
                area += std::max(0.0, std::min(xs[i + 1], half) - std::max(xs[i], -half)) * h;
        }
    }
    return area;
}

// Even-odd point in polygon (double).
bool pointInPolygon(const std::vector<glm::dvec2>& poly, glm::dvec2 p) {
    bool inside = false;
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        glm::dvec2 a = poly[i], b = poly[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
    }
    return inside;
}

// The radial integration under test over a closed counter-clockwise polygon (occluder inside, so on
// the left of every edge): the initial area (the full light when the perturbed centre is inside)
// plus every edge's contribution.
double radialArea(const std::vector<glm::vec2>& poly, int shape) {
    glm::dvec2 perturbed = 1e-9 * glm::dvec2(shared::BP_PERTURBATION);
    std::vector<glm::dvec2> dpoly(poly.begin(), poly.end());
    double area = pointInPolygon(dpoly, perturbed) ? shared::bpLightArea(shape) : 0.0;
    for (size_t i = 0; i < poly.size(); ++i) area += shared::edgeOccludedArea(shape, poly[i], poly[(i + 1) % poly.size()]);
    return area;
}

std::vector<glm::dvec2> toDouble(const std::vector<glm::vec2>& p) { return {p.begin(), p.end()}; }

// A random simple polygon: star-shaped around `centre`, counter-clockwise.
std::vector<glm::vec2> randomStarPolygon(std::mt19937& rng, glm::vec2 centre, float maxRadius) {
    std::uniform_int_distribution<int> count(3, 9);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int n = count(rng);
    // Angles one per sector of 2 pi / n, jittered: consecutive ones less than pi apart, so the
    // polygon is simple and counter-clockwise around `centre`.
    std::vector<float> angles;
    for (int i = 0; i < n; ++i) angles.push_back((float(i) + 0.4f * unit(rng)) * 2.0f * float(kPi) / float(n));
    std::vector<glm::vec2> poly;
    for (float a : angles) {
        float r = maxRadius * (0.2f + 0.8f * unit(rng));
        poly.push_back(centre + r * glm::vec2(std::cos(a), std::sin(a)));
    }
    return poly;
}

double shoelace(const std::vector<glm::vec2>& poly) {
    double a = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        glm::dvec2 p = poly[i], q = poly[(i + 1) % poly.size()];
        a += p.x * q.y - p.y * q.x;
    }
    return 0.5 * a;
}

// The samples of a 2x2 block in the order the table uses, written out independently.
const glm::vec2 kSample[4] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};

}  // namespace

// ==== the contour rule table (guennebaud2007 sec. 4.1, Fig. 3-4) ======================================

// t = 0: the marching-squares table, written out by hand. Each edge joins the midpoints of two
// block sides (the shared borders of occluding and background samples) with the occluder on its
// left; saddles (5, 10) join their two occluders through the block centre.
TEST(ContourRules, EveryMaskAtTZero) {
    const glm::vec2 bottom(0, -0.5f), right(0.5f, 0), top(0, 0.5f), left(-0.5f, 0);
    struct Expected {
        int count;
        glm::vec2 a0, b0, a1, b1;
    };
    const Expected table[16] = {
        {0, {}, {}, {}, {}},
        {1, bottom, left, {}, {}},    // occluder 0 (lower left)
        {1, right, bottom, {}, {}},   // occluder 1 (lower right)
        {1, right, left, {}, {}},     // occluders 0, 1: bottom row, edge pointing -x
        {1, top, right, {}, {}},      // occluder 2 (upper right)
        {2, bottom, right, top, left},  // saddle 0, 2: background corners 1 and 3 cut off
        {1, top, bottom, {}, {}},     // occluders 1, 2: right column, edge pointing -y
        {1, top, left, {}, {}},       // all but 3
        {1, left, top, {}, {}},       // occluder 3 (upper left)
        {1, bottom, top, {}, {}},     // occluders 0, 3: left column, edge pointing +y
        {2, right, top, left, bottom},  // saddle 1, 3: background corners 2 and 0 cut off
        {1, right, top, {}, {}},      // all but 2
        {1, left, right, {}, {}},     // occluders 2, 3: top row, edge pointing +x
        {1, bottom, right, {}, {}},   // all but 1
        {1, left, bottom, {}, {}},    // all but 0
        {0, {}, {}, {}, {}},
    };
    for (int mask = 0; mask < 16; ++mask) {
        SCOPED_TRACE("mask " + std::to_string(mask));
        const Expected& e = table[mask];
        ASSERT_EQ(shared::contourRule(mask).x, e.count);
        if (e.count >= 1) {
            glm::vec4 edge = shared::contourEdge(mask, 0.0f, 0);
            EXPECT_EQ(glm::vec2(edge.x, edge.y), e.a0);
            EXPECT_EQ(glm::vec2(edge.z, edge.w), e.b0);
            EXPECT_FALSE(shared::contourEdgeDegenerate(mask, 0.0f, 0));
        }
        if (e.count == 2) {
            glm::vec4 edge = shared::contourEdge(mask, 0.0f, 1);
            EXPECT_EQ(glm::vec2(edge.x, edge.y), e.a1);
            EXPECT_EQ(glm::vec2(edge.z, edge.w), e.b1);
        }
    }
}

// t = 1 joins occluder centres, t = -1 background centres (sec. 4.1). Lone occluders vanish at t = 1
// ("fewer cases generate edges"), three occluders and saddles cover the block at t = -1.
TEST(ContourRules, EveryMaskAtTPlusAndMinusOne) {
    for (int mask = 1; mask < 15; ++mask) {
        SCOPED_TRACE("mask " + std::to_string(mask));
        int occluders = __builtin_popcount(unsigned(mask));
        bool saddle = mask == 5 || mask == 10;
        for (int which = 0; which < shared::contourRule(mask).x; ++which) {
            glm::ivec2 holders = shared::contourEdgeHolders(mask, which);
            glm::vec4 plus = shared::contourEdge(mask, 1.0f, which);
            glm::vec4 minus = shared::contourEdge(mask, -1.0f, which);
            // t = 1: each extremity is its holder's centre.
            EXPECT_EQ(glm::vec2(plus.x, plus.y), kSample[holders.x]);
            EXPECT_EQ(glm::vec2(plus.z, plus.w), kSample[holders.y]);
            // t = -1: each extremity is a background sample's centre.
            for (glm::vec2 p : {glm::vec2(minus.x, minus.y), glm::vec2(minus.z, minus.w)}) {
                int k = 0;
                while (k < 4 && kSample[k] != p) ++k;
                ASSERT_LT(k, 4) << "t = -1 extremity not on a sample centre";
                EXPECT_EQ((mask >> k) & 1, 0) << "t = -1 extremity on an occluder";
            }
            EXPECT_EQ(shared::contourEdgeDegenerate(mask, 1.0f, which), occluders == 1);
            EXPECT_EQ(shared::contourEdgeDegenerate(mask, -1.0f, which), occluders == 3 || saddle);
        }
        // The two-occluder side cases at t = 1 run along the occluder centres: bottom row (3) from
        // sample 1 to sample 0, left column (9) from 0 to 3, saddle (5) a zero-area pair.
        if (mask == 3) EXPECT_EQ(shared::contourEdge(3, 1.0f, 0), glm::vec4(0.5f, -0.5f, -0.5f, -0.5f));
        if (mask == 9) EXPECT_EQ(shared::contourEdge(9, 1.0f, 0), glm::vec4(-0.5f, -0.5f, -0.5f, 0.5f));
        if (mask == 5) {
            glm::vec4 e0 = shared::contourEdge(5, 1.0f, 0), e1 = shared::contourEdge(5, 1.0f, 1);
            EXPECT_EQ(e0, glm::vec4(-0.5f, -0.5f, 0.5f, 0.5f));
            EXPECT_EQ(e1, glm::vec4(0.5f, 0.5f, -0.5f, -0.5f));
        }
    }
}

// For every mask and t in [-1, 1]: holders are occluders, each extremity lies on the segment between
// its holder and a background neighbour at the position t says, the second edge is the first's
// central symmetry, and occluders lie on the left of the edge, background samples on the right.
TEST(ContourRules, HoldersPositionsAndOrientationForAnyT) {
    for (float t : {-1.0f, -0.5f, 0.0f, 0.25f, 1.0f}) {
        for (int mask = 0; mask < 16; ++mask) {
            SCOPED_TRACE("mask " + std::to_string(mask) + " t " + std::to_string(t));
            int count = shared::contourRule(mask).x;
            EXPECT_EQ(count, mask == 0 || mask == 15 ? 0 : (mask == 5 || mask == 10 ? 2 : 1));
            for (int which = 0; which < count; ++which) {
                glm::vec4 e = shared::contourEdge(mask, t, which);
                glm::vec2 a(e.x, e.y), b(e.z, e.w);
                glm::ivec2 h = shared::contourEdgeHolders(mask, which);
                EXPECT_TRUE((mask >> h.x) & 1);
                EXPECT_TRUE((mask >> h.y) & 1);
                for (auto [p, holder] : {std::pair{a, h.x}, std::pair{b, h.y}}) {
                    // p = midpoint + t (holder - neighbour) / 2 for one background side neighbour.
                    bool found = false;
                    for (int nb : {(holder + 1) % 4, (holder + 3) % 4}) {
                        if ((mask >> nb) & 1) continue;
                        glm::vec2 o = kSample[holder], q = kSample[nb];
                        glm::vec2 want = 0.5f * (o + q) + 0.5f * t * (o - q);
                        if (glm::length(want - p) < 1e-6f) found = true;
                    }
                    EXPECT_TRUE(found) << p.x << "," << p.y;
                }
                if (which == 1) {
                    glm::vec4 first = shared::contourEdge(mask, t, 0);
                    EXPECT_EQ(e, -first);
                    glm::ivec2 h0 = shared::contourEdgeHolders(mask, 0);
                    EXPECT_EQ(h, glm::ivec2((h0.x + 2) % 4, (h0.y + 2) % 4));
                }
                if (glm::length(b - a) < 1e-6f) continue;
                for (int k = 0; k < 4; ++k) {
                    // A saddle's edge cuts off one background corner; the other lies beyond the
                    // second edge, on this edge's left.
                    bool saddle = count == 2;
                    if (saddle && !((mask >> k) & 1) && glm::dot(kSample[k], a + b) <= 0.0f) continue;
                    float side = shared::cross2(b - a, kSample[k] - a);
                    if ((mask >> k) & 1)
                        EXPECT_GE(side, -1e-6f) << "occluder " << k << " on the right";
                    else
                        EXPECT_LE(side, 1e-6f) << "background " << k << " on the left";
                    if (std::abs(t) < 1.0f) EXPECT_NE(side, 0.0f);
                }
            }
        }
    }
}

namespace {
// The contour of a grid of occluding samples (texel coordinates; outside the grid: background):
// every block's edges placed at its centre, in global coordinates.
struct GridContour {
    std::vector<glm::vec4> edges;
    std::vector<int> blockMask;  // (n + 1)^2 blocks, lower-left sample (bx, by) in [-1, n - 1]
};
GridContour gridContour(const std::vector<int>& occ, int n, float t) {
    auto at = [&](int x, int y) { return x >= 0 && y >= 0 && x < n && y < n ? occ[size_t(y) * n + x] : 0; };
    GridContour g;
    for (int by = -1; by < n; ++by)
        for (int bx = -1; bx < n; ++bx) {
            int mask = at(bx, by) | at(bx + 1, by) << 1 | at(bx + 1, by + 1) << 2 | at(bx, by + 1) << 3;
            g.blockMask.push_back(mask);
            glm::vec2 c(float(bx + 1), float(by + 1));
            for (int which = 0; which < shared::contourRule(mask).x; ++which) {
                glm::vec4 e = shared::contourEdge(mask, t, which);
                g.edges.push_back(glm::vec4(c.x + e.x, c.y + e.y, c.x + e.z, c.y + e.w));
            }
        }
    return g;
}
}  // namespace

// Edges of neighbouring blocks meet: over a random grid every extremity is where exactly as many
// edges start as end (closed, consistently oriented loops), and the enclosed area matches the
// closed forms of single occluders and full squares.
TEST(ContourRules, BlocksJoinIntoClosedLoops) {
    std::mt19937 rng(11);
    for (float t : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f}) {
        for (int trial = 0; trial < 20; ++trial) {
            const int n = 9;
            std::vector<int> occ(n * n);
            for (int& o : occ) o = int(rng() % 2);
            GridContour g = gridContour(occ, n, t);
            std::map<std::pair<float, float>, int> balance;
            for (const glm::vec4& e : g.edges) {
                balance[{e.x, e.y}] += 1;
                balance[{e.z, e.w}] -= 1;
            }
            for (const auto& [p, b] : balance) EXPECT_EQ(b, 0) << "at " << p.first << "," << p.second << " t " << t;
        }
    }
    // One occluder: a diamond of area 1/2 at t = 0 (the texel's corners cut), nothing at t = 1, the
    // diamond through the four neighbours' centres (area 2) at t = -1.
    std::vector<int> one(9, 0);
    one[4] = 1;
    auto area = [](const GridContour& g) {
        double a = 0.0;
        for (const glm::vec4& e : g.edges) a += 0.5 * (double(e.x) * e.w - double(e.y) * e.z);
        return a;
    };
    EXPECT_DOUBLE_EQ(area(gridContour(one, 3, 0.0f)), 0.5);
    EXPECT_DOUBLE_EQ(area(gridContour(one, 3, 1.0f)), 0.0);
    EXPECT_DOUBLE_EQ(area(gridContour(one, 3, -1.0f)), 2.0);
    // A 3x3 square of occluders: 9 texels minus four corner triangles of 1/8 at t = 0; the square
    // through its outer centres (2 x 2) at t = 1.
    std::vector<int> square(25, 0);
    for (int y = 1; y <= 3; ++y)
        for (int x = 1; x <= 3; ++x) square[size_t(y) * 5 + x] = 1;
    EXPECT_DOUBLE_EQ(area(gridContour(square, 5, 0.0f)), 8.5);
    EXPECT_DOUBLE_EQ(area(gridContour(square, 5, 1.0f)), 4.0);
}

// The inside test at a point of its block (Fig. 5b) agrees with the winding number of the whole
// contour around that point, for random grids, points and t (including t = -1, 0, 1).
TEST(ContourRules, InsideTestMatchesTheContourWindingNumber) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> coord(0.0f, 9.0f);
    int inside = 0, outside = 0;
    for (float t : {-1.0f, -0.6f, 0.0f, 0.3f, 1.0f}) {
        for (int trial = 0; trial < 30; ++trial) {
            const int n = 9;
            std::vector<int> occ(n * n);
            for (int& o : occ) o = int(rng() % 3 != 0);
            GridContour g = gridContour(occ, n, t);
            for (int k = 0; k < 20; ++k) {
                glm::vec2 p(coord(rng), coord(rng));
                double winding = 0.0;
                for (const glm::vec4& e : g.edges) {
                    glm::dvec2 a = glm::dvec2(e.x, e.y) - glm::dvec2(p), b = glm::dvec2(e.z, e.w) - glm::dvec2(p);
                    winding += std::atan2(a.x * b.y - a.y * b.x, glm::dot(a, b));
                }
                bool wound = std::lround(winding / (2.0 * kPi)) != 0;
                // p's block: the four samples around it; turns measured in the map (cross(b - a, p - a)).
                int bx = int(std::floor(p.x - 0.5f)), by = int(std::floor(p.y - 0.5f));
                int mask = g.blockMask[size_t(by + 1) * (n + 1) + size_t(bx + 1)];
                glm::vec2 c(float(bx + 1), float(by + 1));
                float turns[2] = {0.0f, 0.0f};
                for (int which = 0; which < shared::contourRule(mask).x; ++which) {
                    glm::vec4 e = shared::contourEdge(mask, t, which);
                    glm::vec2 a = c + glm::vec2(e.x, e.y), b = c + glm::vec2(e.z, e.w);
                    turns[which] = shared::cross2(b - a, p - a);
                }
                bool test = shared::contourCentreOccluded(mask, t, turns[0], turns[1]);
                EXPECT_EQ(test, wound) << "t " << t << " p " << p.x << "," << p.y << " mask " << mask;
                (test ? inside : outside) += 1;
            }
        }
    }
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 100);
}

// ==== clipping to the light ============================================================================

TEST(LightClipping, SquareAndDisk) {
    using shared::clipSegmentToDisk;
    using shared::clipSegmentToSquare;
    EXPECT_EQ(clipSegmentToSquare({-2, 0}, {2, 0}), glm::vec2(0.25f, 0.75f));
    EXPECT_EQ(clipSegmentToSquare({-0.5f, 0.5f}, {0.5f, -0.5f}), glm::vec2(0.0f, 1.0f));
    glm::vec2 out = clipSegmentToSquare({1.5f, -2}, {1.5f, 2});  // parallel, outside
    EXPECT_GT(out.x, out.y);
    EXPECT_EQ(clipSegmentToSquare({1, -2}, {1, 2}), glm::vec2(0.25f, 0.75f));  // on the border: kept
    glm::vec2 zero = clipSegmentToSquare({0.3f, 0.3f}, {0.3f, 0.3f});          // zero length inside
    EXPECT_LE(zero.x, zero.y);
    glm::vec2 zeroOut = clipSegmentToSquare({3, 0}, {3, 0});
    EXPECT_GT(zeroOut.x, zeroOut.y);
    glm::vec2 d = clipSegmentToDisk({-2, 0}, {2, 0});
    EXPECT_NEAR(d.x, 0.25f, 1e-6f);
    EXPECT_NEAR(d.y, 0.75f, 1e-6f);
    glm::vec2 miss = clipSegmentToDisk({-2, 1.5f}, {2, 1.5f});
    EXPECT_GT(miss.x, miss.y);
    glm::vec2 chord = clipSegmentToDisk({0, 0}, {0, 3});
    EXPECT_NEAR(chord.x, 0.0f, 1e-7f);
    EXPECT_NEAR(chord.y, 1.0f / 3.0f, 1e-6f);
}

// ==== radial area integration (sec. 4.2, Fig. 5a) =======================================================

// Random star-shaped polygons, in and across the light, both shapes: initial area plus the edges'
// contributions equals the exact area of polygon ∩ light. Float math on values of order 1: 1e-4.
TEST(RadialIntegration, MatchesExactPolygonAreas) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> pos(-1.6f, 1.6f), rad(0.1f, 2.0f);
    for (int shape : {BP_LIGHT_SQUARE, BP_LIGHT_DISK}) {
        int containsCentre = 0, crossesBorder = 0;
        for (int trial = 0; trial < 300; ++trial) {
            std::vector<glm::vec2> poly = randomStarPolygon(rng, {pos(rng), pos(rng)}, rad(rng));
            ASSERT_GT(shoelace(poly), 0.0);
            double exact = scanlineArea(toDouble(poly), shape);
            double radial = radialArea(poly, shape);
            EXPECT_NEAR(radial, exact, 1e-4) << "shape " << shape << " trial " << trial;
            if (pointInPolygon(toDouble(poly), {0, 0})) ++containsCentre;
            if (exact > 1e-3 && exact < std::abs(shoelace(poly)) - 1e-3) ++crossesBorder;
        }
        EXPECT_GT(containsCentre, 20);
        EXPECT_GT(crossesBorder, 50);
    }
}

// A polygon entirely inside the light, not around the centre: the contributions alone are its area.
TEST(RadialIntegration, InteriorPolygonNeedsNoInitialArea) {
    std::vector<glm::vec2> tri = {{0.2f, 0.1f}, {0.8f, 0.3f}, {0.4f, 0.7f}};
    for (int shape : {BP_LIGHT_SQUARE, BP_LIGHT_DISK}) {
        double sum = 0.0;
        for (int i = 0; i < 3; ++i) sum += shared::edgeOccludedArea(shape, tri[i], tri[(i + 1) % 3]);
        EXPECT_NEAR(sum, shoelace(tri), 1e-6);
    }
}

// Edges lying exactly on the light's border contribute nothing, so polygons sharing the border
// (the light itself, its right half, a corner cell, a polygon covering it) come out exact.
TEST(RadialIntegration, EdgesOnTheLightBorder) {
    auto rect = [](float x0, float y0, float x1, float y1) {
        return std::vector<glm::vec2>{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    };
    EXPECT_NEAR(radialArea(rect(-1, -1, 1, 1), BP_LIGHT_SQUARE), 4.0, 1e-6);
    EXPECT_NEAR(radialArea(rect(0.25f, -1, 1, 1), BP_LIGHT_SQUARE), 1.5, 1e-6);
    EXPECT_NEAR(radialArea(rect(0.5f, 0, 1, 1), BP_LIGHT_SQUARE), 0.5, 1e-6);
    EXPECT_NEAR(radialArea(rect(-3, -3, 3, 3), BP_LIGHT_SQUARE), 4.0, 1e-6);
    EXPECT_NEAR(radialArea(rect(-1, -1, -0.5f, 1), BP_LIGHT_SQUARE), 1.0, 1e-6);
    // One edge along the border, from corner to corner: zero.
    EXPECT_NEAR(shared::edgeOccludedArea(BP_LIGHT_SQUARE, {1, -1}, {1, 1}), 0.0, 1e-7);
    EXPECT_NEAR(shared::edgeOccludedArea(BP_LIGHT_SQUARE, {-1, 1}, {-1, -1}), 0.0, 1e-7);
    EXPECT_NEAR(shared::edgeOccludedArea(BP_LIGHT_SQUARE, {1, 1}, {-1, 1}), 0.0, 1e-7);
    // Disk: a chord-free polygon hugging the circle from outside covers it all; a tangent edge is zero.
    EXPECT_NEAR(radialArea(rect(-1, -1, 1, 1), BP_LIGHT_DISK), kPi, 1e-5);
    EXPECT_NEAR(shared::edgeOccludedArea(BP_LIGHT_DISK, {1, -1}, {1, 1}), 0.0, 1e-6);
    EXPECT_NEAR(radialArea(rect(0, -1, 1, 1), BP_LIGHT_DISK), kPi / 2, 1e-5);
}

// Zero-length edges contribute nothing wherever they are (inside, outside, on the border, on the
// centre), and repeated vertices leave a polygon's area unchanged.
TEST(RadialIntegration, ZeroLengthEdges) {
    for (int shape : {BP_LIGHT_SQUARE, BP_LIGHT_DISK})
        for (glm::vec2 p : {glm::vec2(0.3f, -0.2f), glm::vec2(2, 2), glm::vec2(1, 0.5f), glm::vec2(0, 0), glm::vec2(-1, -1)}) {
            float a = shared::edgeOccludedArea(shape, p, p);
            EXPECT_EQ(a, 0.0f) << p.x << "," << p.y;
        }
    std::vector<glm::vec2> poly = {{-0.5f, -0.2f}, {0.6f, -0.2f}, {0.6f, -0.2f}, {0.6f, 0.9f}, {-0.5f, 0.9f}, {-0.5f, 0.9f}};
    for (int shape : {BP_LIGHT_SQUARE, BP_LIGHT_DISK})
        EXPECT_NEAR(radialArea(poly, shape), scanlineArea(toDouble(poly), shape), 1e-4);
}

// Edges through the light centre (their line meets it: the radial method's singular case) and
// vertices on it: the perturbed centre decides the side consistently, so polygons come out exact.
TEST(RadialIntegration, EdgesAndVerticesThroughTheCentre) {
    std::vector<std::vector<glm::vec2>> polys = {
        {{-0.5f, 0}, {0.5f, 0}, {0.5f, 0.7f}, {-0.5f, 0.7f}},    // bottom edge through the centre
        {{-0.5f, -0.7f}, {0.5f, -0.7f}, {0.5f, 0}, {-0.5f, 0}},  // top edge through the centre
        {{0, -2}, {2, -2}, {2, 2}, {0, 2}},                      // half plane x > 0, edge along the y axis
        {{-2, -2}, {0, -2}, {0, 2}, {-2, 2}},                    // half plane x < 0
        {{-1, -1}, {1, 1}, {-1, 1}},                             // diagonal through the centre
        {{0, 0}, {1, 0}, {1, 1}, {0, 1}},                        // a vertex on the centre (quadrant)
        {{0, 0}, {0.5f, -0.8f}, {0.9f, 0.9f}},                   // another vertex on the centre
        {{-0.3f, -0.3f}, {0.3f, 0.3f}, {0.3f, 0.3f}, {-0.6f, 0.5f}},  // an edge with the centre inside it
    };
    for (int shape : {BP_LIGHT_SQUARE, BP_LIGHT_DISK})
        for (size_t i = 0; i < polys.size(); ++i)
            EXPECT_NEAR(radialArea(polys[i], shape), scanlineArea(toDouble(polys[i]), shape), 1e-4)
                << "shape " << shape << " polygon " << i;
    // One edge through the centre contributes half the light, with the side the perturbation picks.
    float half = shared::edgeOccludedArea(BP_LIGHT_SQUARE, {1, 0}, {-1, 0});
    EXPECT_NEAR(std::abs(half), 2.0f, 1e-6f);
}

// GBP06 quads: rectangles against the square (interval overlap) and the disk (radial edges).
TEST(RadialIntegration, RectanglesOnBothLights) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.8f, 1.8f);
    for (int trial = 0; trial < 300; ++trial) {
        float x0 = u(rng), x1 = u(rng), y0 = u(rng), y1 = u(rng);
        if (x0 > x1) std::swap(x0, x1);
        if (y0 > y1) std::swap(y0, y1);
        if (trial % 10 == 0) (x1 > 0.0f ? x0 : x1) = 0.0f;  // an edge through the centre
        if (trial % 15 == 0) y1 = 1.0f;  // an edge on the border
        std::vector<glm::dvec2> poly = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
        for (int shape : {BP_LIGHT_SQUARE, BP_LIGHT_DISK})
            EXPECT_NEAR(shared::rectOccludedArea(shape, glm::vec4(x0, y0, x1, y1)), scanlineArea(poly, shape), 1e-4)
                << "shape " << shape << " trial " << trial;
    }
    EXPECT_EQ(shared::rectOccludedArea(BP_LIGHT_SQUARE, glm::vec4(0.5f, 0.5f, 0.5f, 0.9f)), 0.0f);
    EXPECT_EQ(shared::rectOccludedArea(BP_LIGHT_DISK, glm::vec4(0.5f, 0.5f, 0.4f, 0.9f)), 0.0f);
}

TEST(RadialIntegration, VisibilityIsClampedToTheUnitRange) {
    EXPECT_EQ(shared::bpVisibility(5.0f, BP_LIGHT_SQUARE), 0.0f);
    EXPECT_EQ(shared::bpVisibility(-0.1f, BP_LIGHT_SQUARE), 1.0f);
    EXPECT_FLOAT_EQ(shared::bpVisibility(1.0f, BP_LIGHT_SQUARE), 0.75f);
    EXPECT_FLOAT_EQ(shared::bpVisibility(float(kPi) / 2, BP_LIGHT_DISK), 0.5f);
}

// ==== back-projection and the kernel (sec. 3, eq. 1) ======================================================

// backprojectToLight equals intersecting the ray from p through the 3D sample with the light plane
// (in double, from the sample's 3D position rebuilt independently).
TEST(Backprojection, MatchesRayPlaneIntersection) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int trial = 0; trial < 1000; ++trial) {
        float size = 512.0f, tanHalf = 0.3f + u(rng), half = 0.2f + u(rng);
        glm::vec3 p((u(rng) - 0.5f) * 4.0f, (u(rng) - 0.5f) * 4.0f, 2.0f + 3.0f * u(rng));
        glm::vec2 texel(u(rng) * size, u(rng) * size);
        float depth = p.z * (0.05f + 0.9f * u(rng));
        glm::vec2 got = shared::backprojectToLight(p, texel, depth, size, tanHalf, half);
        glm::dvec2 ndc = glm::dvec2(texel) / double(size) * 2.0 - 1.0;
        glm::dvec3 q(ndc.x * tanHalf * depth, ndc.y * tanHalf * depth, depth);
        glm::dvec3 dp(p);
        double s = dp.z / (dp.z - q.z);  // p + s (q - p) has z = 0
        glm::dvec2 hit = glm::dvec2(dp) + s * (glm::dvec2(q) - glm::dvec2(dp));
        EXPECT_NEAR(got.x, hit.x / half, 2e-4 * std::max(1.0, std::abs(hit.x / half)));
        EXPECT_NEAR(got.y, hit.y / half, 2e-4 * std::max(1.0, std::abs(hit.y / half)));
    }
}

// DESIGN.md section 5: seen from floor point p, the square-occluder's plate back-projects onto
// [-1 - p.x, 1 - p.x] in world units; the light (w_l = 1) is [-0.5, 0.5], so light coordinates
// double that. Light frame: x = world x, depth 4 - world y.
TEST(Backprojection, SquareOccluderCornersLandWhereDesignSays) {
    const float size = 256.0f, tanHalf = 1.0f;
    for (float px : {-1.3f, 0.0f, 0.7f}) {
        glm::vec3 p(px, 0.2f, 4.0f);
        // The plate's edge x = 0.5 at depth 2 is at ndc 0.5 / (2 tan) -> texel (ndc + 1) / 2 * size.
        float texelX = (0.5f / (2.0f * tanHalf) + 1.0f) * 0.5f * size;
        glm::vec2 l = shared::backprojectToLight(p, {texelX, size / 2}, 2.0f, size, tanHalf, 0.5f);
        EXPECT_NEAR(l.x, (1.0f - px) / 0.5f, 1e-4f);
    }
}

// Eq. 1 is the width, in texels, of the pyramid (p, light) cut at depth z_min and projected from
// the light centre onto the map: rebuilt here from the two rays p -> light border.
TEST(Kernel, EquationOneIsThePyramidCrossSection) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int trial = 0; trial < 200; ++trial) {
        float lightWidth = 0.1f + 2.0f * u(rng), size = 1024.0f, tanHalf = 0.2f + u(rng);
        float zp = 1.0f + 5.0f * u(rng), zmin = zp * (0.05f + 0.9f * u(rng));
        float px = (u(rng) - 0.5f) * zp * tanHalf;
        double x[2];
        for (int side = 0; side < 2; ++side) {
            double lx = (side ? 0.5 : -0.5) * lightWidth;
            double s = (zp - zmin) / zp;  // from p (depth zp) toward the light point (depth 0)
            double wx = px + s * (lx - px);
            x[side] = (wx / (zmin * tanHalf) + 1.0) * 0.5 * size;
        }
        EXPECT_NEAR(shared::hsmKernelTexels(lightWidth, size, tanHalf, zmin, zp), x[1] - x[0], 1e-3 * (x[1] - x[0]) + 1e-3);
    }
}

TEST(Kernel, RefinementLevelAndTexelRanges) {
    EXPECT_EQ(shared::hsmRefinementLevel(0.3f, 10), 0);
    EXPECT_EQ(shared::hsmRefinementLevel(1.99f, 10), 0);
    EXPECT_EQ(shared::hsmRefinementLevel(2.0f, 10), 1);
    EXPECT_EQ(shared::hsmRefinementLevel(3.99f, 10), 1);
    EXPECT_EQ(shared::hsmRefinementLevel(4.0f, 10), 2);
    EXPECT_EQ(shared::hsmRefinementLevel(5000.0f, 10), 10);
    EXPECT_EQ(shared::kernelTexelRange({10.5f, 20.25f}, 3.0f, 64), glm::ivec4(9, 18, 12, 21));
    EXPECT_EQ(shared::kernelTexelRange({1.0f, 62.0f}, 9.0f, 64), glm::ivec4(0, 57, 5, 63));
    EXPECT_EQ(shared::kernelTexelRange({5.5f, 5.5f}, 0.0f, 64), glm::ivec4(5, 5, 5, 5));
    // At the level floor(log2 w), a kernel of w texels touches at most 3 x 3 texels.
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int trial = 0; trial < 2000; ++trial) {
        int size = 37 + int(u(rng) * 300);
        int top = int(std::floor(std::log2(float(size))));
        float w = 1.0f + u(rng) * float(size) * 0.5f;
        glm::vec2 c(u(rng) * size, u(rng) * size);
        int level = shared::hsmRefinementLevel(w, top);
        glm::ivec4 r0 = shared::kernelTexelRange(c, w, size);
        glm::ivec4 rl = shared::levelTexelRange(r0, level, std::max(1, size >> level));
        EXPECT_LE(rl.z - rl.x, 2);
        EXPECT_LE(rl.w - rl.y, 2);
        // Every level-0 texel of the range is covered by a level texel of the range (odd sizes: the
        // last texel of a level covers the left-over texels).
        int levelSize = std::max(1, size >> level);
        for (int x : {r0.x, r0.z}) {
            int covering = std::min(x >> level, levelSize - 1);
            EXPECT_GE(covering, rl.x);
            EXPECT_LE(covering, rl.z);
        }
    }
}

// ==== which samples occlude ==============================================================================

TEST(Occlusion, ReceiverPlaneDepthAndTheTest) {
    const float size = 128.0f, tanHalf = 0.8f;
    // A receiver plane facing the light along its axis: the plane depth is z_p on every ray.
    glm::vec3 p(0.3f, -0.2f, 3.0f);
    glm::vec3 n = shared::receiverNormalTowardLight(glm::vec3(0, 0, 1), p);
    EXPECT_EQ(n, glm::vec3(0, 0, -1));
    for (glm::vec2 texel : {glm::vec2(3, 7), glm::vec2(64, 64), glm::vec2(120, 5)})
        EXPECT_NEAR(shared::receiverPlaneDepth(n, p, texel, size, tanHalf), 3.0f, 1e-5f);
    // A tilted plane: the depth where the ray meets it, and the receiver's own ray gives z_p.
    glm::vec3 tilted = shared::receiverNormalTowardLight(glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f)), p);
    glm::vec2 own((p.x / (p.z * tanHalf) + 1.0f) * 0.5f * size, (p.y / (p.z * tanHalf) + 1.0f) * 0.5f * size);
    EXPECT_NEAR(shared::receiverPlaneDepth(tilted, p, own, size, tanHalf), p.z, 1e-4f);
    glm::vec2 texel(90, 40);
    float z = shared::receiverPlaneDepth(tilted, p, texel, size, tanHalf);
    glm::vec3 hit = shared::texelRay(texel, size, tanHalf) * z;
    EXPECT_NEAR(glm::dot(tilted, hit - p), 0.0f, 1e-4f);
    // The plane x = 1, parallel to the light's axis: rays toward +x meet it, rays toward -x never do.
    glm::vec3 steep = shared::receiverNormalTowardLight(glm::vec3(1, 0, 0), glm::vec3(1, 0, 3));
    EXPECT_EQ(steep, glm::vec3(-1, 0, 0));
    float ndc = 127.0f / 128.0f * 2.0f - 1.0f;
    EXPECT_NEAR(shared::receiverPlaneDepth(steep, glm::vec3(1, 0, 3), glm::vec2(127, 64), size, tanHalf), 1.0f / (ndc * tanHalf), 1e-5f);
    EXPECT_EQ(shared::receiverPlaneDepth(steep, glm::vec3(1, 0, 3), glm::vec2(10, 64), size, tanHalf), shared::BP_FAR);
    // The test: nearer than the receiver by the bias, and not on the receiver's own plane.
    EXPECT_TRUE(shared::sampleOccludes(1.0f, 3.0f, 5.0f, 0.1f));
    EXPECT_FALSE(shared::sampleOccludes(2.95f, 3.0f, 5.0f, 0.1f));  // within the bias of p
    EXPECT_FALSE(shared::sampleOccludes(2.0f, 3.0f, 2.05f, 0.1f));  // on the tangent plane
    EXPECT_FALSE(shared::sampleOccludes(2.0f, 3.0f, 1.95f, 0.1f));
    EXPECT_TRUE(shared::sampleOccludes(2.0f, 3.0f, 1.5f, 0.1f));    // behind the plane: a closed object's far side
    EXPECT_TRUE(shared::sampleOccludes(2.0f, 3.0f, shared::BP_FAR, 0.1f));
    EXPECT_FALSE(shared::sampleOccludes(3.4e38f, 3.0f, shared::BP_FAR, 0.1f));  // no caster
}
