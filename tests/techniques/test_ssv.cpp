// `ssv` (assarsson2004): the shared coverage math against exact areas, its hard cases, the wedge
// construction (conservative: every point of an edge's penumbra lies inside its wedge), the GPU
// against the same source as C++ on a grid, and end-to-end renders against the oracles (the
// square-occluder closed form, `raytraced`), with the per-pixel record against the image.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

#include "graph/internals.h"
#include "graph/renderer.h"
#include "hsm/hsm.h"
#include "gl/util.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "ssv/ssv.h"
#include "support/gl_fixture.h"
#include "support/mesh_scenes.h"

namespace shadowlab {
namespace {

namespace fs = std::filesystem;
using namespace shared;
using testing::Collected;
using testing::GLTest;
using testing::writeGltf;
constexpr float kPi = 3.14159265358979323846f;

// ---- the coverage math ------------------------------------------------------------------------------

// Exact occluded area (light coordinates) of the square light [-1,1]^2 by the axis-aligned
// rectangle [x0,x1] x [y0,y1].
float rectOverlap(float x0, float y0, float x1, float y1) {
    return std::max(0.0f, std::min(x1, 1.0f) - std::max(x0, -1.0f)) *
           std::max(0.0f, std::min(y1, 1.0f) - std::max(y0, -1.0f));
}

// A planar rectangle occluder parallel to the light at depth h, seen from a receiver at depth zp:
// the four oriented silhouette edges' coverages plus the light area when the centre is occluded
// equal the exact overlap of its projection with the light (the slides: a planar polygon is
// exact). Receivers and rectangles at random, including rectangles covering the whole light,
// missing it and containing the centre.
TEST(SsvMath, PlanarRectangleCoverageIsExact) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    float worst = 0.0f;
    int centreInside = 0, partial = 0;
    for (int i = 0; i < 4000; ++i) {
        const float h = 1.0f + std::abs(u(rng)), zp = h + 0.2f + 3.0f * std::abs(u(rng));
        const glm::vec3 p(2.0f * u(rng), 2.0f * u(rng), zp);
        // Rectangle in the occluder plane (light-frame units; half size 0.5 makes light coords x2).
        const float rx0 = 1.5f * u(rng), ry0 = 1.5f * u(rng);
        const float rx1 = rx0 + 0.05f + 1.5f * std::abs(u(rng)), ry1 = ry0 + 0.05f + 1.5f * std::abs(u(rng));
        const glm::vec3 c00(rx0, ry0, h), c10(rx1, ry0, h), c11(rx1, ry1, h), c01(rx0, ry1, h);
        const float half = 0.5f;
        const glm::vec3 n(0.0f, 0.0f, -1.0f);  // the receiver faces the light
        // Counter-clockwise seen from the light (x right, y up): the occluder on each edge's left.
        float sum = ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, c00, c10, half) +
                    ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, c10, c11, half) +
                    ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, c11, c01, half) +
                    ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, c01, c00, half);
        // The projection of the rectangle from p: q = (x zp - p h) / (zp - h), in light coordinates.
        auto proj = [&](float x, float px) { return (x * zp - px * h) / ((zp - h) * half); };
        const float qx0 = proj(rx0, p.x), qx1 = proj(rx1, p.x), qy0 = proj(ry0, p.y), qy1 = proj(ry1, p.y);
        const bool centre = qx0 < 0.0f && qx1 > 0.0f && qy0 < 0.0f && qy1 > 0.0f;
        const float occluded = sum + (centre ? 4.0f : 0.0f);
        const float exact = rectOverlap(qx0, qy0, qx1, qy1);
        worst = std::max(worst, std::abs(occluded - exact));
        EXPECT_NEAR(occluded, exact, 2e-5f * std::max(1.0f, std::abs(qx1 - qx0) * std::abs(qy1 - qy0))) << "case " << i;
        centreInside += centre;
        partial += exact > 0.0f && exact < 4.0f;
    }
    EXPECT_GT(centreInside, 200);
    EXPECT_GT(partial, 400);
    std::printf("planar rectangles: largest |coverage + centre - exact| %.3g\n", worst);
}

// The disk light: a half-plane occluder (a long edge) covers the circular segment beyond its line.
TEST(SsvMath, DiskCoverageOfALineIsTheCircularSegment) {
    for (float d : {-0.9f, -0.5f, -0.1f, 0.0f, 0.3f, 0.7f, 0.99f}) {
        // Edge along x at light-coordinate height d (the occluder above it, y > d): from left to
        // right the occluder is on the left. A receiver straight below at depth 2, the edge at 1,
        // so the projection doubles: the edge's light-frame y is d / 2 (radius 1).
        const glm::vec3 p(0.0f, 0.0f, 2.0f), n(0.0f, 0.0f, -1.0f);
        const glm::vec3 a(-50.0f, 0.5f * d, 1.0f), b(50.0f, 0.5f * d, 1.0f);
        const float coverage = ssvEdgeCoverage(BP_LIGHT_DISK, p, n, a, b, 1.0f);
        const float segment = std::acos(d) - d * std::sqrt(1.0f - d * d);  // area of the disk above y = d
        // The centre is occluded; on the line (d = 0) the perturbed centre of backprojection.glsl
        // decides, as it does for the contour method.
        const bool centre = d < 0.0f || (d == 0.0f && BP_PERTURBATION.y > 0.0f);
        EXPECT_NEAR(coverage + (centre ? kPi : 0.0f), segment, 2e-4f) << "d " << d;
    }
}

// Hard cases of the shared math (issue 21): an edge pointing at the light centre, an edge parallel
// to the light plane, collinear consecutive edges, a projected edge exactly on the light border, an
// edge behind the receiver or on its tangent plane.
TEST(SsvMath, HardCases) {
    const glm::vec3 p(0.3f, -0.2f, 3.0f), n(0.0f, 0.0f, -1.0f);
    // Pointing at the light centre: the edge lies on a ray from the origin of the light frame.
    EXPECT_EQ(ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, glm::vec3(0.2f, 0.1f, 1.0f), glm::vec3(0.4f, 0.2f, 2.0f), 0.5f),
              0.0f);
    {
        SsvLight light;
        light.centre = glm::vec3(0.0f);
        light.size = 1.0f;
        const SsvWedge w = buildWedge(light, glm::vec3(0.2f, 0.1f, 1.0f), glm::vec3(0.4f, 0.2f, 2.0f), 20.0f);
        EXPECT_EQ(w.kind, SsvWedge::Kind::None) << w.why;
    }
    // Parallel to the light plane (constant depth): the projection is a scaled copy; the coverage is
    // finite and equals the sum of its two halves (collinear consecutive edges).
    const glm::vec3 a(-0.4f, 0.1f, 1.5f), m(0.05f, 0.1f, 1.5f), b(0.6f, 0.1f, 1.5f);
    const float whole = ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, a, b, 0.5f);
    const float halves = ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, a, m, 0.5f) + ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, m, b, 0.5f);
    EXPECT_TRUE(std::isfinite(whole));
    EXPECT_NEAR(whole, halves, 1e-6f);
    EXPECT_NE(whole, 0.0f);
    // Collinear and not parallel to the light: the same.
    const glm::vec3 c(0.5f, 0.4f, 2.2f);
    const glm::vec3 mid = 0.5f * (a + c);
    EXPECT_NEAR(ssvEdgeCoverage(BP_LIGHT_DISK, p, n, a, c, 0.5f),
                ssvEdgeCoverage(BP_LIGHT_DISK, p, n, a, mid, 0.5f) + ssvEdgeCoverage(BP_LIGHT_DISK, p, n, mid, c, 0.5f), 1e-5f);
    // A projected edge exactly on the light's border (x = 1 in light coordinates) covers nothing
    // of the square; a hair inside, it covers a sliver.
    {
        const glm::vec3 q(0.0f, 0.0f, 2.0f);
        // Depth 1, so light coordinates are 2 x / 0.5 ... from q: proj = (x * 2 - 0) / (1 * 0.5) = 4 x.
        const float onBorder = ssvEdgeCoverage(BP_LIGHT_SQUARE, q, n, glm::vec3(0.25f, -1.0f, 1.0f), glm::vec3(0.25f, 1.0f, 1.0f), 0.5f);
        EXPECT_NEAR(onBorder, 0.0f, 1e-6f);
        const float inside = ssvEdgeCoverage(BP_LIGHT_SQUARE, q, n, glm::vec3(0.2499f, -1.0f, 1.0f), glm::vec3(0.2499f, 1.0f, 1.0f), 0.5f);
        EXPECT_NEAR(std::abs(inside), 2.0f * 0.0004f, 1e-5f);
    }
    // Behind the receiver (deeper than p) or behind the light plane: nothing.
    EXPECT_EQ(ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, glm::vec3(-1, 0, 3.5f), glm::vec3(1, 0, 4.0f), 0.5f), 0.0f);
    EXPECT_EQ(ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, glm::vec3(-1, 0, -0.5f), glm::vec3(1, 0, -0.1f), 0.5f), 0.0f);
    // At the receiver's own depth and in its tangent plane (an edge of its own face): nothing, and
    // never a NaN however close to the plane.
    EXPECT_EQ(ssvEdgeCoverage(BP_LIGHT_SQUARE, p, n, glm::vec3(-1, 0, 3.0f), glm::vec3(1, 0, 3.0f), 0.5f), 0.0f);
    for (float eps : {1e-3f, 1e-5f, 1e-7f}) {
        const float v = ssvEdgeCoverage(BP_LIGHT_DISK, p, glm::vec3(0.0f), glm::vec3(-1, 0, 3.0f - eps), glm::vec3(1, 0.3f, 3.0f), 0.5f);
        EXPECT_TRUE(std::isfinite(v)) << eps;
        EXPECT_LE(std::abs(v), kPi * 0.5f + 1e-4f) << eps;  // an edge covers at most half the light beyond it
    }
    // The V-buffer resolve clamps over-darkening.
    EXPECT_EQ(ssvVisibility(2.0f, 0.5f, BP_LIGHT_SQUARE), 0.0f);
    EXPECT_NEAR(ssvVisibility(0.0f, 1.0f, BP_LIGHT_SQUARE), 0.75f, 1e-7f);
    EXPECT_NEAR(ssvVisibility(1.0f, -1.0f, BP_LIGHT_SQUARE), 0.25f, 1e-7f);
    // A count one short of the wedges' (the crack on a hard shadow's boundary): a whole light back.
    EXPECT_NEAR(ssvVisibility(0.0f, -2.0f, BP_LIGHT_SQUARE), 0.5f, 1e-7f);
    EXPECT_NEAR(ssvVisibility(-1.0f, 1.0f, BP_LIGHT_SQUARE), 0.75f, 1e-7f);
    EXPECT_EQ(ssvVisibility(0.0f, -0.5f, BP_LIGHT_SQUARE), 1.0f);  // a residue near 0: lit
}

// ---- the wedge construction --------------------------------------------------------------------------

// Every point of an edge's penumbra region (l + t (x - l) for l on the light, x on the edge, t >= 1,
// up to the bottom plane) lies inside its wedge: the wedge is conservative, so culling by it loses
// nothing. And a point outside the wedge gets no coverage from the edge.
TEST(SsvWedge, EnclosesThePenumbraAndNothingOutsideIsCovered) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    int wedges = 0, everywhere = 0, samples = 0, outsideCovered = 0, outsideTested = 0, onPlaneTested = 0, inBox = 0;
    float onPlaneWorst = 0.0f;
    for (int i = 0; i < 600; ++i) {
        SsvLight light;
        light.shape = i % 2 ? LightShape::Square : LightShape::Sphere;
        light.centre = glm::vec3(0.0f, 4.0f, 0.0f);
        light.direction = glm::vec3(0, -1, 0);
        light.up = glm::vec3(0, 0, -1);
        light.right = glm::normalize(glm::cross(light.direction, light.up));
        light.size = 0.2f + 0.8f * u01(rng);
        const glm::vec3 e0(2.0f * u(rng), 1.0f + 2.0f * u01(rng), 2.0f * u(rng));
        const glm::vec3 e1 = e0 + glm::vec3(u(rng), 0.5f * u(rng), u(rng));
        const float far = 12.0f;
        const SsvWedge w = buildWedge(light, e0, e1, far);
        if (w.kind == SsvWedge::Kind::Everywhere) {
            ++everywhere;
            continue;
        }
        ASSERT_EQ(w.kind, SsvWedge::Kind::Wedge) << w.why;
        ++wedges;
        // The same wedge cut at a box of receivers (its bottom just beyond the box's farthest
        // corner along the axis): every penumbra point inside the box is still inside it.
        Bounds box;
        box.extend(glm::vec3(-4.0f, -1.0f, -4.0f));
        box.extend(glm::vec3(4.0f, 2.5f, 4.0f));
        const SsvWedge cut = buildWedge(light, e0, e1, far, &box);
        for (int k = 0; k < 40; ++k) {
            glm::vec3 l;
            if (light.shape == LightShape::Square)
                l = light.centre + light.size * ((u01(rng) - 0.5f) * light.right + (u01(rng) - 0.5f) * light.up);
            else {
                const float r = light.size * std::sqrt(u01(rng)), a = 2.0f * kPi * u01(rng);
                l = light.centre + r * (std::cos(a) * light.right + std::sin(a) * light.up);
            }
            const glm::vec3 x = glm::mix(e0, e1, u01(rng));
            const glm::vec3 q = l + (1.0f + 3.0f * u01(rng)) * (x - l);
            if (glm::length(q - light.centre) > 0.9f * far) continue;
            EXPECT_TRUE(w.contains(q, 1e-4f)) << "wedge " << i << " sample " << k;
            if (cut.kind == SsvWedge::Kind::Wedge && glm::all(glm::greaterThanEqual(q, box.lo)) &&
                glm::all(glm::lessThanEqual(q, box.hi))) {
                EXPECT_TRUE(cut.contains(q, 1e-4f)) << "cut wedge " << i << " sample " << k;
                ++inBox;
            }
            ++samples;
        }
        // Points outside the wedge (but in front of the bottom): coverage zero.
        const glm::vec3 lp = light.centre;
        // A receiver exactly on one of the wedge's front, back or side planes (a hard case: the
        // GPU's depth test and the CPU's plane test may put it on either side): its coverage is
        // continuous there and 0 from outside, so at most rounding (1e-4 of the light's area), and
        // the culling cannot change the sum whichever side it picks.
        for (int k = 0; k < 40; ++k) {
            const SsvPlane* planes[4] = {&w.front, &w.back, &w.side0, &w.side1};
            const SsvPlane& plane = *planes[k % 4];
            const glm::vec3 q0(4.0f * u(rng), 4.0f * u(rng) - 1.0f, 4.0f * u(rng));
            const glm::vec3 q = q0 - plane.distance(q0) * plane.n;
            if (!w.contains(q, 1e-4f) || glm::length(q - lp) > 0.9f * far) continue;
            auto frame = [&](const glm::vec3& v) {
                const glm::vec3 d = v - lp;
                return glm::vec3(glm::dot(d, light.right), glm::dot(d, light.up), glm::dot(d, light.direction));
            };
            const int shape = light.shape == LightShape::Square ? BP_LIGHT_SQUARE : BP_LIGHT_DISK;
            const float c = ssvEdgeCoverage(shape, frame(q), glm::vec3(0.0f), frame(e0), frame(e1), light.halfSize());
            ASSERT_TRUE(std::isfinite(c));
            EXPECT_LE(std::abs(c), 4e-4f) << "wedge " << i << " plane " << k % 4;
            onPlaneWorst = std::max(onPlaneWorst, std::abs(c));
            ++onPlaneTested;
        }
        for (int k = 0; k < 40; ++k) {
            const glm::vec3 q(4.0f * u(rng), 4.0f * u(rng) - 1.0f, 4.0f * u(rng));
            if (w.contains(q, 1e-3f) || w.bottom.distance(q) < 0.0f) continue;
            // In the light frame: x right, y up, z depth along the direction.
            auto frame = [&](const glm::vec3& v) {
                const glm::vec3 d = v - lp;
                return glm::vec3(glm::dot(d, light.right), glm::dot(d, light.up), glm::dot(d, light.direction));
            };
            const int shape = light.shape == LightShape::Square ? BP_LIGHT_SQUARE : BP_LIGHT_DISK;
            const float c = ssvEdgeCoverage(shape, frame(q), glm::vec3(0.0f), frame(e0), frame(e1), light.halfSize());
            ++outsideTested;
            if (std::abs(c) > 1e-5f) ++outsideCovered;
        }
    }
    EXPECT_GT(wedges, 400);
    EXPECT_GT(samples, 10000);
    EXPECT_GT(outsideTested, 2000);
    EXPECT_EQ(outsideCovered, 0);
    EXPECT_GT(onPlaneTested, 2000);
    EXPECT_GT(inBox, 5000);
    std::printf("receivers exactly on a wedge plane: %d, largest |coverage| %.3g (of the light's 4 or pi)\n",
                onPlaneTested, onPlaneWorst);
    std::printf("%d wedges, %d edges evaluated everywhere, %d penumbra samples inside, %d outside points uncovered\n",
                wedges, everywhere, samples, outsideTested);
}

// The hard shadow volume of a closed mesh is closed and wound outwards: with its points at infinity
// brought to a finite distance, its signed volume (divergence theorem) is positive.
TEST(SsvVolume, ClosedAndWoundOutwards) {
    Scene scene = loadScene("sphere-light");
    const std::vector<SsvCaster> casters = buildSsvCasters(scene);
    SsvLight light = SsvLight::from(scene.lights[0]);
    const SsvGeometry g = buildSsvGeometry(scene, casters, 0.0, light, 30.0f, 1e-4f);
    ASSERT_FALSE(g.volume.triangles.empty());
    double volume = 0.0;
    for (const glm::uvec3& t : g.volume.triangles) {
        glm::dvec3 v[3];
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 x = g.volume.vertices[t[k]];
            v[k] = x.w == 0.0f ? glm::dvec3(light.centre) + 30.0 * glm::dvec3(x) : glm::dvec3(x);
        }
        volume += glm::dot(v[0], glm::cross(v[1], v[2])) / 6.0;
    }
    EXPECT_GT(volume, 0.0);
    // One wedge per silhouette edge, all of them built as wedges for this scene.
    EXPECT_EQ(g.wedges.size(), g.edges.size());
    EXPECT_GT(g.edges.size(), 20u);
    std::printf("sphere-light: %zu silhouette edges, %zu evaluated everywhere, volume %.2f\n", g.edges.size(),
                g.wedgesEverywhere, volume);
}

// ---- GPU against CPU ----------------------------------------------------------------------------------

struct GpuCase {
    glm::vec4 receiver, normal, x0, x1, extra;
};
struct GpuResult {
    glm::vec4 edge, values, more;
};

class SsvMathGpu : public GLTest {};

TEST_F(SsvMathGpu, AgreesWithCpuOnAGrid) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<GpuCase> cases;
    for (int i = 0; i < 2048; ++i) {
        const float shape = i % 2 ? float(BP_LIGHT_SQUARE) : float(BP_LIGHT_DISK);
        const glm::vec3 p(u(rng), u(rng), 2.0f + u(rng));
        glm::vec3 n = i % 5 == 0 ? glm::vec3(0.0f) : glm::normalize(glm::vec3(0.3f * u(rng), 0.3f * u(rng), -1.0f));
        glm::vec3 x0(u(rng), u(rng), 1.0f + u(rng)), x1(u(rng), u(rng), 1.0f + u(rng));
        if (i % 7 == 0) x1.z = x0.z;                         // parallel to the light
        if (i % 11 == 0) x1 = x0 * 1.7f;                     // on a ray from the centre
        if (i % 13 == 0) x0.z = p.z;                         // at the receiver's depth
        if (i % 17 == 0) x1.z = -0.2f;                       // behind the light plane
        cases.push_back({glm::vec4(p, shape), glm::vec4(n, 0.25f + std::abs(u(rng))), glm::vec4(x0, 0), glm::vec4(x1, 0),
                         glm::vec4(u(rng), u(rng), float(i % 3) - 1.0f, 3.0f * u(rng))});
    }
    Buffer in(cases.size() * sizeof(GpuCase), cases.data());
    Buffer out(cases.size() * sizeof(GpuResult));
    const ShaderProgram& program = programCache().compute("tests/volumes/ssv_math.comp");
    program.set("count", unsigned(cases.size()));
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.dispatch(GLuint((cases.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const std::vector<GpuResult> gpu = out.read<GpuResult>();
    ASSERT_EQ(gpu.size(), cases.size());
    int covered = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
        SCOPED_TRACE("case " + std::to_string(i));
        const GpuCase& c = cases[i];
        const int shape = int(c.receiver.w);
        const float half = c.normal.w;
        const glm::vec3 p(c.receiver), n(c.normal), x0(c.x0), x1(c.x1);
        const glm::vec4 e = ssvProjectedEdge(p, n, x0, x1, half);
        // Projected points reach 2 (the pre-clip square); relative tolerance on them.
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(gpu[i].edge[k], e[k], 2e-4f);
        const float cov = ssvEdgeCoverage(shape, p, n, x0, x1, half);
        EXPECT_NEAR(gpu[i].values.x, cov, 2e-4f);
        EXPECT_NEAR(gpu[i].values.y, ssvVisibility(c.extra.z, c.extra.w, shape), 1e-6f);
        const glm::vec2 range = ssvOccludingRange(p, n, x0, x1);
        if (range.x <= range.y) {
            EXPECT_NEAR(gpu[i].values.z, range.x, 1e-5f);
            EXPECT_NEAR(gpu[i].values.w, range.y, 1e-5f);
        } else {
            EXPECT_GT(gpu[i].values.z, gpu[i].values.w - 1e-5f);
        }
        const glm::vec2 clip = ssvClipLinear(glm::vec2(0.0f, 1.0f), c.extra.x, c.extra.y);
        EXPECT_NEAR(gpu[i].more.x, clip.x, 1e-6f);
        EXPECT_NEAR(gpu[i].more.y, clip.y, 1e-6f);
        if (x0.z < p.z) {
            const glm::vec2 q = ssvProjectToLight(p, x0, half);
            EXPECT_NEAR(gpu[i].more.z, q.x, 1e-4f * std::max(1.0f, std::abs(q.x)));
            EXPECT_NEAR(gpu[i].more.w, q.y, 1e-4f * std::max(1.0f, std::abs(q.y)));
        }
        covered += cov != 0.0f;
    }
    EXPECT_GT(covered, 300);
}

// ---- renders -----------------------------------------------------------------------------------------

struct Rendered {
    Image visibility, positions, ids;
};
Rendered render(const Scene& scene, const std::string& technique, std::vector<std::pair<std::string, std::string>> sets,
                int size, std::optional<float> lightSize = {}) {
    RenderOptions options;
    options.width = options.height = size;
    options.technique = technique;
    options.sets = std::move(sets);
    options.lightSize = lightSize;
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"visibility", "gbuffer"});
    return {renderer.visibility(), renderer.positions(), renderer.ids()};
}

double rmse(const Image& a, const Image& b, const Image* mask = nullptr) {
    double sq = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < a.data.size(); ++i) {
        if (mask && std::isnan(mask->data[i])) continue;
        if (std::isnan(b.data[i])) continue;
        const double d = double(a.data[i]) - b.data[i];
        sq += d * d;
        ++n;
    }
    return n ? std::sqrt(sq / double(n)) : INFINITY;
}

class SsvRender : public GLTest {};

// square-occluder: a planar polygon, handled exactly by the slides' method. Against the closed form
// on the floor (DESIGN.md section 5), RMSE <= 0.01 (measured: see the printout; what is left is the
// plate's 0.001 thickness, which the closed form ignores, and rasterization of the G-buffer).
TEST_F(SsvRender, SquareOccluderMatchesTheClosedForm) {
    Scene scene = loadScene("square-occluder");
    Rendered r = render(scene, "ssv", {}, 128);
    Image oracle(r.visibility.width, r.visibility.height, 1, NAN);
    size_t penumbra = 0;
    for (int y = 0; y < oracle.height; ++y)
        for (int x = 0; x < oracle.width; ++x) {
            if (r.ids.at(x, y) != 0.0f) continue;
            glm::vec3 p(r.positions.at(x, y, 0), 0.0f, r.positions.at(x, y, 2));
            oracle.at(x, y) = squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f);
            penumbra += oracle.at(x, y) > 0.0f && oracle.at(x, y) < 1.0f;
        }
    const double e = rmse(r.visibility, oracle);
    std::printf("[ ssv      ] square-occluder vs closed form: RMSE %.5f over the floor (%zu penumbra pixels)\n", e, penumbra);
    EXPECT_LE(e, 0.01);
    EXPECT_GT(penumbra, 500u);
}

// No crack at any size (README.md, "The crack"): on a hard shadow's boundary a pixel's point can lie
// within rounding of a side quad, where the hard pass's depth test and the wedge's exact side of the
// light centre disagree; the count came out one short and the pixel lit (v = 1 where the closed form
// gives 0.5: 1024x1024, pixel 352,436). At every size from 256^2 to 2048^2 in steps of 64, 1280x720
// and 1920x1080, the largest error against the closed form over the floor region [-2, 2]^2 (which
// the camera sees past the plate, assets/scenes/README.md) is under 0.01 (measured: the printout;
// the plate's 0.001 thickness, which the closed form ignores, moves the penumbra by about 0.002).
TEST_F(SsvRender, NoCrackAtAnySize) {
    const Scene scene = loadScene("square-occluder");
    std::vector<glm::ivec2> sizes;
    for (int s = 256; s <= 2048; s += 64) sizes.push_back({s, s});
    sizes.push_back({1280, 720});
    sizes.push_back({1920, 1080});
    double worstOverall = 0.0;
    for (const glm::ivec2 size : sizes) {
        RenderOptions options;
        options.width = size.x;
        options.height = size.y;
        options.technique = "ssv";
        Renderer renderer(scene, options);
        renderer.renderFrame(0, {"visibility", "gbuffer"});
        const Image v = renderer.visibility(), positions = renderer.positions(), ids = renderer.ids();
        double worst = 0.0;
        glm::ivec2 at(-1);
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x) {
                if (ids.at(x, y) != 0.0f) continue;
                const glm::vec3 p(positions.at(x, y, 0), 0.0f, positions.at(x, y, 2));
                if (std::abs(p.x) > 2.0f || std::abs(p.z) > 2.0f) continue;
                const double e = std::abs(v.at(x, y) - squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f));
                if (e > worst) worst = e, at = {x, y};
            }
        worstOverall = std::max(worstOverall, worst);
        EXPECT_LT(worst, 0.01) << size.x << "x" << size.y << " at pixel " << at.x << "," << at.y;
    }
    std::printf("[ ssv      ] square-occluder, %zu sizes from 256^2 to 2048^2, 1280x720, 1920x1080: largest error "
                "against the closed form %.5f\n", sizes.size(), worstOverall);
}

// sphere-light against `raytraced` (its default rays): RMSE <= 0.03.
TEST_F(SsvRender, SphereLightAgainstRaytraced) {
    Scene scene = loadScene("sphere-light");
    Rendered s = render(scene, "ssv", {}, 128);
    Rendered rt = render(scene, "raytraced", {}, 128);
    const double e = rmse(s.visibility, rt.visibility);
    std::printf("[ ssv      ] sphere-light vs raytraced: RMSE %.5f\n", e);
    EXPECT_LE(e, 0.03);
}

// Light size 0: ssv is hard shadow volumes, exact hard shadows: the same as `raytraced` with one
// ray (at the light centre) on >= 99.5% of pixels (what differs is the G-buffer's rasterization
// against the rays' hits along silhouettes).
TEST_F(SsvRender, PointLightIsExactHardShadows) {
    for (const char* name : {"square-occluder", "sphere-light", "plant"}) {
        Scene scene = loadScene(name);
        Rendered s = render(scene, "ssv", {}, 128, 0.0f);
        Rendered rt = render(scene, "raytraced", {{"rays", "1"}}, 128, 0.0f);
        size_t same = 0;
        for (size_t i = 0; i < s.visibility.data.size(); ++i) same += std::abs(s.visibility.data[i] - rt.visibility.data[i]) < 1e-3f;
        const double fraction = double(same) / double(s.visibility.data.size());
        std::printf("[ ssv      ] %s, point light: %.4f of pixels equal raytraced rays=1\n", name, fraction);
        EXPECT_GE(fraction, 0.995) << name;
    }
}

// The per-pixel record recomputes the pixel on the CPU (the wedges containing the point by their
// planes, each edge's coverage by the shared math) from the GPU's hard count: its visibility is
// the image's within 1e-4, so the stencil culling marked exactly the points inside each wedge.
// Also: the coverage summed over every silhouette edge, culled by nothing, is the same (the
// wedges lose nothing).
TEST_F(SsvRender, PixelRecordsAddUpToTheImage) {
    const std::string root = std::string(SHADOWLAB_TEST_TMP) + "/ssv-records";
    int penumbraRecords = 0;
    struct Case {
        const char* scene;
        const char* split;
    };
    for (const Case c : {Case{"square-occluder", "1"}, Case{"sphere-light", "1"}, Case{"overlapping-occluders", "1"},
                         Case{"plant", "1"}, Case{"cube-popping", "2"}, Case{"plant", "2"}}) {
        const std::string name = std::string(c.scene) + "-split" + c.split;
        SCOPED_TRACE(name);
        Scene scene = loadScene(c.scene);
        RenderOptions options;
        options.width = options.height = 96;
        options.technique = "ssv";
        options.sets = {{"split", c.split}};
        Renderer renderer(scene, options);
        renderer.renderFrame(0, renderer.internalRequests(true));
        const Image v = renderer.visibility();
        std::vector<glm::ivec2> penumbra;
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x)
                if (renderer.ids().at(x, y) >= 0.0f && v.at(x, y) > 0.02f && v.at(x, y) < 0.98f) penumbra.push_back({x, y});
        ASSERT_GE(penumbra.size(), 8u);
        for (int k = 0; k < 8; ++k) {
            const glm::ivec2 p = penumbra[penumbra.size() * size_t(2 * k + 1) / 16];
            SCOPED_TRACE("pixel " + std::to_string(p.x) + "," + std::to_string(p.y));
            const std::string dir = root + "/" + name;
            fs::create_directories(dir);
            OutputSet outputs;
            InternalWriter writer(dir, outputs);
            renderer.writeInternals(writer, p);
            outputs.commit();
            std::ifstream in(dir + "/pixel.json");
            const nlohmann::json rec = nlohmann::json::parse(in)["lights"][0];
            ASSERT_FALSE(rec.contains("background"));
            const nlohmann::json& subs = rec["sub_lights"];
            ASSERT_EQ(subs.size(), std::string(c.split) == "2" ? 4u : 1u);
            std::vector<double> sums(subs.size(), 0.0);
            for (const auto& e : rec["edges"]) sums[e["sub_light"].get<size_t>()] += e["signed_area"].get<double>();
            const double area = rec["light_geometry"]["area"].get<double>();
            double fromRecord = 0.0;
            for (size_t q = 0; q < subs.size(); ++q) {
                EXPECT_NEAR(sums[q], subs[q]["coverage_sum"].get<double>(), 1e-4);
                fromRecord += std::clamp(1.0 - (subs[q]["hard_count"].get<double>() * area + sums[q]) / area, 0.0, 1.0) *
                              subs[q]["front_fraction"].get<double>() / double(subs.size());
            }
            EXPECT_NEAR(fromRecord, rec["visibility"].get<double>(), 1e-4) << rec.dump().substr(0, 1500);
            EXPECT_NEAR(rec["visibility_from_record"].get<double>(), rec["visibility"].get<double>(), 1e-4);
            EXPECT_FLOAT_EQ(rec["visibility"].get<float>(), v.at(p.x, p.y));
            if (!rec["edges"].empty()) ++penumbraRecords;
        }
        // The exported meshes: one wedge (8 triangles) per silhouette edge that has a wedge.
        std::ifstream index(root + "/" + name + "/index.json");
        ASSERT_TRUE(index.good());
    }
    EXPECT_GE(penumbraRecords, 36);
}

// The slides' first artifact: the silhouette is found from the light centre only, so where the
// silhouette seen from other points of the light differs (the turning cube of cube-popping under
// its large light, 2 wide at 1.2 above the cube's top) the penumbra is wrong, and it pops as the
// silhouette changes. The slides' remedy, 2x2 light splitting (split = 2), finds four silhouettes,
// one per quarter: against `reference` (256 samples) at three times of the cube's turn the RMSE
// falls (measured at 128x128: see the printout; bound: at least 25% less at every time), and a
// planar occluder, exact already, stays exact (square-occluder against its closed form).
TEST_F(SsvRender, LightSplittingReducesTheSingleSilhouetteError) {
    Scene scene = loadScene("cube-popping");
    for (int frame : {0, 30, 60}) {  // t = 0, 1, 2 s: the cube turned by 0, 15 and 30 degrees
        auto at = [&](const std::string& technique, std::vector<std::pair<std::string, std::string>> sets) {
            RenderOptions options;
            options.width = options.height = 128;
            options.technique = technique;
            options.sets = std::move(sets);
            Renderer renderer(scene, options);
            renderer.renderFrame(frame, {"visibility"});
            return renderer.visibility();
        };
        const Image reference = at("reference", {{"samples", "256"}});
        const double one = rmse(at("ssv", {{"split", "1"}}), reference);
        const double four = rmse(at("ssv", {{"split", "2"}}), reference);
        std::printf("[ ssv      ] cube-popping frame %d vs reference: RMSE split 1 %.5f, split 2 %.5f\n", frame, one,
                    four);
        EXPECT_LT(four, 0.75 * one) << "frame " << frame;
    }
    Scene square = loadScene("square-occluder");
    Rendered r = render(square, "ssv", {{"split", "2"}}, 96);
    double sq = 0.0;
    size_t n = 0;
    for (int y = 0; y < r.visibility.height; ++y)
        for (int x = 0; x < r.visibility.width; ++x) {
            if (r.ids.at(x, y) != 0.0f) continue;
            glm::vec3 p(r.positions.at(x, y, 0), 0.0f, r.positions.at(x, y, 2));
            const double d = r.visibility.at(x, y) - squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f);
            sq += d * d;
            ++n;
        }
    std::printf("[ ssv      ] square-occluder split 2 vs closed form: RMSE %.5f\n", std::sqrt(sq / double(n)));
    EXPECT_LE(std::sqrt(sq / double(n)), 0.01);
}

// ---- open, non-manifold and degenerate meshes in a glTF ----------------------------------------------

// An open mesh (a square of two triangles at y = 2, zero thickness: square-occluder's plate as a
// surface), the same with two fins on one edge (that edge has four faces: not a manifold), and
// the same with degenerate triangles (a repeated index, three collinear points). The documented
// behaviour (README.md, "Silhouettes"): the open square's boundary edges are its silhouettes, and
// a planar polygon is exact (closed form, RMSE <= 0.01); the non-manifold mesh is named on stderr
// once and treated as an open surface (no crash, v in [0, 1], never lighter than `raytraced` by more
// than its rays' noise); degenerate triangles change nothing (the same image as the open square).
TEST_F(SsvRender, OpenNonManifoldAndDegenerateMeshesInAGltf) {
    const std::vector<glm::vec3> square = {{-0.5f, 2, -0.5f}, {0.5f, 2, -0.5f}, {0.5f, 2, 0.5f}, {-0.5f, 2, 0.5f}};
    const std::vector<uint32_t> two = {0, 2, 1, 0, 3, 2};
    auto closedFormRmse = [](const Rendered& r) {
        double sq = 0.0;
        size_t n = 0;
        for (int y = 0; y < r.visibility.height; ++y)
            for (int x = 0; x < r.visibility.width; ++x) {
                if (r.ids.at(x, y) != 0.0f) continue;
                glm::vec3 p(r.positions.at(x, y, 0), 0.0f, r.positions.at(x, y, 2));
                const double d = r.visibility.at(x, y) - squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f);
                sq += d * d;
                ++n;
            }
        return n > 1000 ? std::sqrt(sq / double(n)) : INFINITY;
    };
    // Open.
    const Rendered open = render(loadScene(writeGltf("open-square", square, two)), "ssv", {}, 96);
    const double e = closedFormRmse(open);
    std::printf("[ ssv      ] open square (2 triangles) vs closed form: RMSE %.5f\n", e);
    EXPECT_LE(e, 0.01);
    // Degenerate triangles added: the same picture.
    std::vector<glm::vec3> withPoint = square;
    withPoint.push_back({0.0f, 2.0f, -0.5f});  // the middle of edge 0-1
    std::vector<uint32_t> degenerate = two;
    degenerate.insert(degenerate.end(), {0, 0, 1, 0, 1, 4, 2, 2, 2});
    const Rendered same = render(loadScene(writeGltf("degenerate-square", withPoint, degenerate)), "ssv", {}, 96);
    double worst = 0.0;
    for (size_t i = 0; i < same.visibility.data.size(); ++i)
        worst = std::max(worst, double(std::abs(same.visibility.data[i] - open.visibility.data[i])));
    EXPECT_LE(worst, 1e-5) << "degenerate triangles changed the shadow";
    // Non-manifold: edge 0-1 shared by the square's triangle and two fins (one down, one up).
    std::vector<glm::vec3> finned = square;
    finned.push_back({0.0f, 1.6f, -0.5f});
    finned.push_back({0.0f, 2.4f, -0.5f});
    std::vector<uint32_t> fins = two;
    fins.insert(fins.end(), {0, 1, 4, 1, 0, 5});
    const Scene nm = loadScene(writeGltf("finned-square", finned, fins));
    ::testing::internal::CaptureStderr();
    const Rendered f = render(nm, "ssv", {}, 96);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("ssv: object 'finned-square' is not a manifold"), std::string::npos) << err;
    const Rendered rt = render(nm, "raytraced", {}, 96);
    size_t lighter = 0;
    for (size_t i = 0; i < f.visibility.data.size(); ++i) {
        const float v = f.visibility.data[i];
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << i;
        lighter += v > rt.visibility.data[i] + 0.1f;
    }
    std::printf("[ ssv      ] finned square: RMSE vs raytraced %.5f, %zu pixels lighter by > 0.1\n",
                rmse(f.visibility, rt.visibility), lighter);
    EXPECT_LE(lighter, f.visibility.data.size() / 1000);
}

// The hostile meshes of the open-mesh rules (README.md, "Open and imperfect meshes"), each against
// `raytraced` and against the same shape made well: a closed box (0.8 wide, floating at height 1.6)
// with one face wound the wrong way (the shadow vanished: RMSE 0.237 before the topology turned
// it round), the box with every triangle twice (a black streak across the floor), three triangles
// on one edge (the shadow disappeared), and a finely tessellated sphere with two 3-edge holes (the
// whole mesh was treated as a sheet: twice as dark). Bounds: the well-made shape's RMSE against
// `raytraced` plus 0.01, or within 1e-5 of its image where the rule makes the same volume.
std::vector<glm::vec3> liftedBox(const Mesh& box) {
    std::vector<glm::vec3> p = box.positions;
    for (glm::vec3& q : p) q = q * 0.8f + glm::vec3(0.2f, 1.6f, -0.1f);
    return p;
}

double maxDifference(const Image& a, const Image& b) {
    double worst = 0.0;
    for (size_t i = 0; i < a.data.size(); ++i) worst = std::max(worst, double(std::abs(a.data[i] - b.data[i])));
    return worst;
}

TEST_F(SsvRender, WrongWindingDuplicatesAndNonManifoldEdgesKeepTheShadow) {
    const Mesh box = makeBox(glm::vec3(1.0f));
    const std::vector<glm::vec3> p = liftedBox(box);
    const Scene good = loadScene(writeGltf("ssv-box", p, box.indices));
    const Rendered well = render(good, "ssv", {}, 96);
    const Rendered rt = render(good, "raytraced", {{"rays", "256"}}, 96);
    const double base = rmse(well.visibility, rt.visibility);
    std::printf("[ ssv      ] box vs raytraced: RMSE %.5f\n", base);
    EXPECT_LE(base, 0.03);
    for (const char* technique : {"ssv", "pvm", "pvmf"}) {
        SCOPED_TRACE(technique);
        const Image reference = technique == std::string("ssv") ? well.visibility : render(good, technique, {}, 96).visibility;
        // One face (two triangles) wound the wrong way: turned round by the topology, the same image.
        std::vector<uint32_t> flipped = box.indices;
        std::swap(flipped[1], flipped[2]);
        std::swap(flipped[4], flipped[5]);
        ::testing::internal::CaptureStderr();
        const Rendered f = render(loadScene(writeGltf("ssv-box-flipped-face", p, flipped)), technique, {}, 96);
        const std::string said = ::testing::internal::GetCapturedStderr();
        EXPECT_LE(maxDifference(f.visibility, reference), 1e-5) << "one face wound the wrong way";
        if (technique == std::string("ssv"))
            EXPECT_NE(said.find("ssv: object 'ssv-box-flipped-face': 2 triangles wound against their neighbours were "
                                "turned round"), std::string::npos) << said;
        // Every triangle twice, the second time reversed: the duplicates are left out, the same image.
        std::vector<uint32_t> twice = box.indices;
        for (size_t i = 0; i < box.indices.size(); i += 3)
            twice.insert(twice.end(), {box.indices[i], box.indices[i + 2], box.indices[i + 1]});
        ::testing::internal::CaptureStderr();
        const Rendered d = render(loadScene(writeGltf("ssv-box-twice", p, twice)), technique, {}, 96);
        const std::string saidTwice = ::testing::internal::GetCapturedStderr();
        EXPECT_LE(maxDifference(d.visibility, reference), 1e-5) << "every triangle twice";
        if (technique == std::string("ssv"))
            EXPECT_NE(saidTwice.find("ssv: object 'ssv-box-twice': 12 duplicate triangles"), std::string::npos) << saidTwice;
    }
    // Three triangles on one edge (a square plate with a fin on one side): against `raytraced`.
    const std::vector<glm::vec3> square = {{-0.5f, 2, -0.5f}, {0.5f, 2, -0.5f}, {0.5f, 2, 0.5f}, {-0.5f, 2, 0.5f},
                                           {0.0f, 2.3f, -0.5f}};
    const Scene fin = loadScene(writeGltf("ssv-three-on-an-edge", square, {0, 2, 1, 0, 3, 2, 0, 1, 4}));
    ::testing::internal::CaptureStderr();
    const Rendered f = render(fin, "ssv", {}, 96);
    ::testing::internal::GetCapturedStderr();
    const Rendered finRt = render(fin, "raytraced", {{"rays", "256"}}, 96);
    const double finError = rmse(f.visibility, finRt.visibility);
    size_t lostUmbra = 0;
    for (size_t i = 0; i < f.visibility.data.size(); ++i) lostUmbra += finRt.visibility.data[i] < 0.05f && f.visibility.data[i] > 0.5f;
    std::printf("[ ssv      ] three triangles on an edge vs raytraced: RMSE %.5f, %zu umbra pixels lit\n", finError, lostUmbra);
    EXPECT_LE(finError, 0.03);
    EXPECT_EQ(lostUmbra, 0u);
}

TEST_F(SsvRender, ASolidWithTwoSmallHolesIsNotASheet) {
    const Mesh sphere = makeSphere(0.6f, 96);
    std::vector<glm::vec3> p = sphere.positions;
    for (glm::vec3& q : p) q += glm::vec3(0.0f, 1.6f, 0.0f);
    const Scene closed = loadScene(writeGltf("ssv-sphere", p, sphere.indices));
    // Two triangles away, one on each side: two 3-edge holes.
    std::vector<uint32_t> holed = sphere.indices;
    const size_t n = holed.size() / 3;
    holed.erase(holed.begin() + std::ptrdiff_t(3 * (2 * n / 3)), holed.begin() + std::ptrdiff_t(3 * (2 * n / 3) + 3));
    holed.erase(holed.begin() + std::ptrdiff_t(3 * (n / 3)), holed.begin() + std::ptrdiff_t(3 * (n / 3) + 3));
    const Scene open = loadScene(writeGltf("ssv-sphere-two-holes", p, holed));
    const MeshTopology t = buildTopology(open.objects.back().mesh);
    EXPECT_EQ(t.boundaryEdges(), 6u);
    ASSERT_EQ(t.components.size(), 1u);
    EXPECT_TRUE(t.components[0].solid());
    EXPECT_EQ(t.fillCentres.size(), 2u);
    const Rendered a = render(closed, "ssv", {}, 96), b = render(open, "ssv", {}, 96);
    const Rendered rt = render(open, "raytraced", {{"rays", "256"}}, 96);
    const double closedError = rmse(a.visibility, rt.visibility), holedError = rmse(b.visibility, rt.visibility);
    std::printf("[ ssv      ] sphere (%zu triangles) vs raytraced: RMSE %.5f closed, %.5f with two 3-edge holes\n",
                sphere.triangleCount(), closedError, holedError);
    EXPECT_LE(holedError, closedError + 0.005);
}

// ---- the exported wedges, re-rasterized on the CPU ---------------------------------------------------


// The wedges the technique exports (`--internals`: the mesh it drew) decide, on the CPU, which
// pixels each wedge's coverage reaches: a pixel's point is inside a wedge when it lies on the inner
// side of the planes of the wedge's exported triangles (wound outwards). The sum of the edges'
// coverages (the shared math) over the wedges containing each pixel's point equals the GPU's
// stencil-culled V-buffer (the `wedge_coverage` internal) at every pixel of the image, within 1e-3
// on all but 0.1% of the pixels (room for points within rounding of a wedge's plane, where the
// coverage is near 0 anyway). Measured at 80x80: no pixel off; the largest difference 1.2e-7 on
// square-occluder and overlapping-occluders, 2.8e-5 on plant (1268 wedges: float sums).
// The stencil marked exactly the points inside each drawn wedge, and the export is what was drawn.
TEST_F(SsvRender, ExportedWedgesReRasterizedGiveTheGpuCoverage) {
    for (const char* name : {"square-occluder", "overlapping-occluders", "plant"}) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(name);
        RenderOptions options;
        options.width = options.height = 80;
        options.technique = "ssv";
        Renderer renderer(scene, options);
        renderer.renderFrame(0, renderer.internalRequests(false));
        Collected c;
        renderer.writeInternals(c, std::nullopt);
        ASSERT_TRUE(c.meshes.count("wedges") && c.meshes.count("silhouettes") && c.images.count("wedge_coverage"));
        const MeshData& wedges = c.meshes["wedges"];
        const MeshData& edges = c.meshes["silhouettes"];
        const Image& gpu = c.images["wedge_coverage"];
        const std::vector<float>& edgeOf = wedges.primitiveAttributes[0].second;
        const std::vector<float>& weight = edges.primitiveAttributes[0].second;
        const std::vector<float>& kind = edges.primitiveAttributes[2].second;
        // Each wedge's planes from its exported triangles (8 per wedge, consecutive).
        struct Planes {
            int edge;
            std::vector<glm::vec4> planes;  // n, d: inside is dot(n, x) <= d
        };
        std::vector<Planes> hulls;
        for (size_t t = 0; t < wedges.primitiveCount(); ++t) {
            if (t % 8 == 0) hulls.push_back({int(edgeOf[t]), {}});
            const glm::vec3 a = wedges.positions[wedges.indices[3 * t]], b = wedges.positions[wedges.indices[3 * t + 1]],
                            cc = wedges.positions[wedges.indices[3 * t + 2]];
            glm::vec3 n = glm::cross(b - a, cc - a);
            if (glm::length(n) == 0.0f) continue;
            n = glm::normalize(n);
            hulls.back().planes.push_back(glm::vec4(n, glm::dot(n, a)));
        }
        EXPECT_EQ(hulls.size() * 8, wedges.primitiveCount());
        // One wedge per silhouette edge whose wedge could be built, in edge order.
        size_t withWedge = 0;
        for (float k : kind) withWedge += k == float(int(SsvWedge::Kind::Wedge));
        EXPECT_EQ(hulls.size(), withWedge);
        for (size_t h = 1; h < hulls.size(); ++h) EXPECT_LT(hulls[h - 1].edge, hulls[h].edge);
        if (std::string(name) == "square-occluder") {
            EXPECT_EQ(edges.primitiveCount(), 4u);  // the plate's top face's four edges
            EXPECT_EQ(hulls.size(), 4u);
        }
        const LightState& light = *renderer.lights()[0];
        const glm::mat4 view = light.view.viewFromWorld;
        auto toLight = [&](glm::vec3 x) {
            const glm::vec4 v = view * glm::vec4(x, 1.0f);
            return glm::vec3(v.x, v.y, -v.z);
        };
        const int shape = bpLightShape(light.light);
        const float half = bpLightHalfSize(light.light);
        const Image positions = renderer.positions(), normals = renderer.normals();
        size_t off = 0, covered = 0, pixels = 0;
        double worst = 0.0;
        for (int y = 0; y < gpu.height; ++y)
            for (int x = 0; x < gpu.width; ++x) {
                const glm::vec3 w(positions.at(x, y, 0), positions.at(x, y, 1), positions.at(x, y, 2));
                if (!std::isfinite(w.x)) continue;
                ++pixels;
                const glm::vec3 nw(normals.at(x, y, 0), normals.at(x, y, 1), normals.at(x, y, 2));
                const glm::vec3 nv = glm::mat3(view) * nw;
                const glm::vec3 p = toLight(w), n(nv.x, nv.y, -nv.z);
                double sum = 0.0;
                for (const Planes& h : hulls) {
                    bool inside = true;
                    for (const glm::vec4& q : h.planes) inside = inside && glm::dot(glm::vec3(q), w) <= q.w;
                    if (!inside) continue;
                    const size_t e = size_t(h.edge);
                    sum += weight[e] * ssvEdgeCoverage(shape, p, n, toLight(edges.positions[edges.indices[2 * e]]),
                                                       toLight(edges.positions[edges.indices[2 * e + 1]]), half);
                }
                for (size_t e = 0; e < edges.primitiveCount(); ++e)  // edges without a wedge: everywhere
                    if (kind[e] == float(int(SsvWedge::Kind::Everywhere)))
                        sum += weight[e] * ssvEdgeCoverage(shape, p, n, toLight(edges.positions[edges.indices[2 * e]]),
                                                           toLight(edges.positions[edges.indices[2 * e + 1]]), half);
                const double d = std::abs(sum - gpu.at(x, y));
                worst = std::max(worst, d);
                off += d > 1e-3;
                covered += std::abs(gpu.at(x, y)) > 1e-3;
            }
        std::printf("[ ssv      ] %s: %zu wedges re-rasterized from the export, %zu of %zu pixels covered, %zu off by "
                    "> 1e-3 (largest %.2g)\n",
                    name, hulls.size(), covered, pixels, off, worst);
        EXPECT_GT(covered, 100u);
        EXPECT_LE(off, pixels / 1000);
    }
}

// The slides' load balancing: the V-buffer at 1/k of the frame's resolution (vbuffer_divisor),
// upsampled bilinearly. k = 1 is the frame itself. At k = 2 and 3 the image differs from k = 1
// (> 1e-4: the reduced buffer's error is real); a smooth shadow on a plane stays close
// (square-occluder's floor: RMSE <= 0.01), while wherever the geometry changes within k pixels the
// bilinear taps mix a surface with what lies behind it (plant: its leaves, a few pixels wide at
// 128x128, and the floor seen between them; bound 0.12 over the image): the "rendering errors" of
// the slides' load balancing, measured in the printout. The window's refinement (the volumes and
// wedges whole, the visibility in bands of rows) gives the frame run whole.
TEST_F(SsvRender, ReducedVBufferIsCloseAndRefinesInBands) {
    for (const char* name : {"square-occluder", "plant"}) {
        Scene scene = loadScene(name);
        const Rendered full = render(scene, "ssv", {}, 128);
        for (const char* k : {"2", "3"}) {
            SCOPED_TRACE(std::string(name) + " k=" + k);
            const Rendered reduced = render(scene, "ssv", {{"vbuffer_divisor", k}}, 128);
            const double e = rmse(reduced.visibility, full.visibility);
            double sq = 0.0;
            size_t n = 0;
            for (size_t i = 0; i < full.ids.data.size(); ++i)
                if (full.ids.data[i] == 0.0f) {
                    const double d = double(reduced.visibility.data[i]) - full.visibility.data[i];
                    sq += d * d;
                    ++n;
                }
            const double floor = std::sqrt(sq / double(std::max<size_t>(n, 1)));
            std::printf("[ ssv      ] %s vbuffer_divisor %s: RMSE %.5f against the full V-buffer, %.5f over the floor\n",
                        name, k, e, floor);
            EXPECT_GT(e, 1e-4);
            if (std::string(name) == "square-occluder") EXPECT_LE(floor, 0.01);
            EXPECT_LE(e, 0.12);
        }
    }
    Scene scene = loadScene("plant");
    for (const char* k : {"2", "3"}) {
        SCOPED_TRACE(std::string("refined, k=") + k);
        RenderOptions options;
        options.width = 96;
        options.height = 72;
        options.technique = "ssv";
        options.sets = {{"vbuffer_divisor", k}};
        Renderer whole(scene, options), refined(scene, options);
        whole.renderFrame(0, {"visibility"});
        double progress = 0.0;
        for (int calls = 0; progress < 1.0 && calls < 4000; ++calls) progress = refined.refineFrame(0, {"visibility"}, 0.001);
        ASSERT_EQ(progress, 1.0);
        const Image a = whole.visibility(), b = refined.visibility();
        double worst = 0.0;
        for (size_t i = 0; i < a.data.size(); ++i) worst = std::max(worst, double(std::abs(a.data[i] - b.data[i])));
        EXPECT_LE(worst, 1e-5);
    }
}

// The reactive rule (load_balance_ms): a target no frame can meet (0.01 ms) raises the divisor one
// step a frame to its largest, 4; a target every frame meets (10 s) brings it back one step a frame
// to 1; 0 leaves it alone. Each change re-runs what depends on it, so the frames differ (the
// flicker the slides warn of).
TEST_F(SsvRender, LoadBalancingReactsToTheFrameCost) {
    Scene scene = loadScene("plant");
    RenderOptions options;
    options.width = options.height = 64;
    options.technique = "ssv";
    options.sets = {{"load_balance_ms", "0.01"}};
    Renderer renderer(scene, options);
    auto divisor = [&] { return int(renderer.lights()[0]->params.get("vbuffer_divisor")); };
    std::vector<int> up;
    std::vector<Image> frames;
    for (int f = 0; f < 5; ++f) {
        renderer.renderFrame(f, {"visibility"});
        frames.push_back(renderer.visibility());
        up.push_back(divisor());
    }
    EXPECT_EQ(up, (std::vector<int>{2, 3, 4, 4, 4}));
    EXPECT_NE(frames[0].data, frames[1].data);  // k = 1, then k = 2: another picture
    EXPECT_EQ(frames[3].data, frames[4].data);  // settled at 4: nothing re-runs
    renderer.setParam("load_balance_ms", "10000");
    std::vector<int> down;
    for (int f = 5; f < 9; ++f) {
        renderer.renderFrame(f, {"visibility"});
        down.push_back(divisor());
    }
    EXPECT_EQ(down, (std::vector<int>{3, 2, 1, 1}));
    renderer.setParam("load_balance_ms", "0");
    renderer.setParam("vbuffer_divisor", "3");
    for (int f = 9; f < 12; ++f) renderer.renderFrame(f, {"visibility"});
    EXPECT_EQ(divisor(), 3);
    // The window's progressive frames: one step per completed frame, none while a finished frame is
    // only reused.
    Renderer window(scene, options);
    std::vector<int> steps;
    for (int call = 0; call < 5; ++call) {
        ASSERT_EQ(window.refineFrame(0, {"visibility"}, 1e9), 1.0);
        steps.push_back(int(window.lights()[0]->params.get("vbuffer_divisor")));
    }
    EXPECT_EQ(steps, (std::vector<int>{2, 3, 4, 4, 4}));
}

// The slides' second artifact: "overlapping geometry is handled incorrectly". Where the penumbrae
// of the two plates of overlapping-occluders overlap, each edge's coverage is added as if it alone
// hid the light, so the hidden parts are counted twice and v falls below the truth: the pixels
// darker than `raytraced` by more than 0.02 far outnumber those lighter by as much.
TEST_F(SsvRender, OverlappingOccludersOverDarken) {
    Scene scene = loadScene("overlapping-occluders");
    Rendered s = render(scene, "ssv", {}, 128);
    Rendered rt = render(scene, "raytraced", {}, 128);
    size_t darker = 0, lighter = 0;
    double worst = 0.0;
    for (size_t i = 0; i < s.visibility.data.size(); ++i) {
        const double d = double(s.visibility.data[i]) - rt.visibility.data[i];
        darker += d < -0.02;
        lighter += d > 0.02;
        worst = std::min(worst, d);
    }
    std::printf("[ ssv      ] overlapping-occluders vs raytraced: %zu pixels darker by > 0.02, %zu lighter; most "
                "darker by %.3f\n",
                darker, lighter, -worst);
    EXPECT_GT(darker, 100u);
    EXPECT_GT(darker, 4 * lighter);
    EXPECT_LT(worst, -0.1);
}

}  // namespace
}  // namespace shadowlab
