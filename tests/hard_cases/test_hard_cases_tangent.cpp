// Hard cases of the visibility convention (DESIGN.md section 5, shaders/shared/tangent_plane.glsl):
// receivers whose own tangent plane hides part or all of the light, end to end through every
// technique. Joins shadowlab_hard_cases (tests/hard_cases/*.cpp), labelled hard-case.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "graph/renderer.h"
#include "image/metrics.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"
#include "support/hard_case_util.h"

namespace shadowlab {
namespace {

using namespace hardcase;

// A square light (width 1, centre (0, 4, 0), facing down) over a floor, and two vertical walls
// seen from +x, none casting shadows, so what a technique computes there is the convention alone:
//  - wall A in the plane x = -0.25: its tangent plane cuts the light at x = -0.25, so 3/4 of the
//    light is in front of it, whatever the point on the wall (the closed form: 0.75);
//  - wall B in the plane x = 1: the whole light is behind its plane (x < 0.5 < 1): v = 0;
//  - the floor faces the whole light: v = 1.
const char* kWalls = R"({
  "camera": {"position": [6, 1.5, 0], "target": [0, 1.2, 0], "fov_deg": 60, "near": 0.1, "far": 50},
  "lights": [{"type": "square", "position": [0, 4, 0], "direction": [0, -1, 0], "up": [0, 0, -1], "width": 1}],
  "objects": [
    {"name": "floor", "id": 0, "type": "quad", "size": [8, 8], "casts_shadows": false},
    {"name": "wall-a", "id": 1, "type": "quad", "size": [2, 1.5], "casts_shadows": false,
     "transform": {"translate": [-0.25, 1.5, -1.25], "rotate_deg": [0, 0, -90]}},
    {"name": "wall-b", "id": 2, "type": "quad", "size": [2, 1.5], "casts_shadows": false,
     "transform": {"translate": [1.0, 1.5, 1.25], "rotate_deg": [0, 0, -90]}}
  ]})";

struct Stats {
    size_t n = 0;
    double minV = 1e9, maxV = -1e9;
};
Stats statsOf(const Render& r, float id) {
    Stats s;
    for (size_t i = 0; i < r.ids.data.size(); ++i) {
        if (r.ids.data[i] != id) continue;
        ++s.n;
        s.minV = std::min<double>(s.minV, r.visibility.data[i]);
        s.maxV = std::max<double>(s.maxV, r.visibility.data[i]);
    }
    return s;
}

class HardCaseTangent : public testing::GLTest {};

// Every technique on the three receivers. The references count light samples in front of the
// plane: 1024 (or 256) stratified samples on a 32 x 32 (16 x 16) grid, whose column boundary falls
// exactly on x = -0.25, so they give 0.75, up to one sample of the boundary column whose jitter
// puts it within rounding of the plane (1/256). The
// filtering, back-projection and shadow-volume techniques multiply by the exact fraction and find no occluder:
// 0.75 to rounding. `hard` and `pcf` test the light centre (x = 0 > -0.25): 1 on wall A.
TEST_F(HardCaseTangent, TangentPlaneCutsTheLightOrHidesIt) {
    const Scene scene = loadScene(writeScene("tangent", "walls", kWalls));
    struct Expect {
        const char* technique;
        double wallA;
    };
    for (Expect e : {Expect{"reference", 0.75}, Expect{"raytraced", 0.75}, Expect{"pcss", 0.75}, Expect{"sssm", 0.75},
                     Expect{"ssm-gbp06", 0.75}, Expect{"ssm-contour", 0.75}, Expect{"ssv", 0.75}, Expect{"hard", 1.0}, Expect{"spsm", 1.0},
                     Expect{"pcf", 1.0}}) {
        SCOPED_TRACE(e.technique);
        const Render r = render(scene, e.technique, {}, {}, 64);
        expectInvariants(r, e.technique);
        const Stats a = statsOf(r, 1.0f), b = statsOf(r, 2.0f), floor = statsOf(r, 0.0f);
        ASSERT_GT(a.n, 100u);
        ASSERT_GT(b.n, 100u);
        ASSERT_GT(floor.n, 100u);
        const bool counts = e.technique == std::string("reference") || e.technique == std::string("raytraced");
        const double tol = counts ? 1.0 / 256.0 + 1e-4 : 1e-4;
        EXPECT_NEAR(a.minV, e.wallA, tol);
        EXPECT_NEAR(a.maxV, e.wallA, tol);
        EXPECT_EQ(b.maxV, 0.0);  // the whole light behind the receiver's plane
        EXPECT_EQ(floor.minV, 1.0);
    }
}

// A sphere under the light: past its terminator every technique gives 0, and on the band where
// the tangent plane cuts the light the two references agree. The tangent plane is the facet's
// (the G-buffer's geometric normal, shaders/common/gbuffer.frag): the 48-segment mesh is what is
// drawn and traced, so "past the terminator" is where the whole light is behind the facet's plane,
// and the facet normals are checked to be the sphere's within half a facet's angle (3.75 degrees
// along each of the two directions: at most 5.3). Band: mean |difference| measured 0.0072 (it was
// 0.015 with the interpolated normal as the plane), bound 0.02: 256 samples' stratified count of a
// fraction cut by a line.
TEST_F(HardCaseTangent, SphereTerminator) {
    const char* text = R"({
      "camera": {"position": [0, 1.2, 4], "target": [0, 1, 0], "fov_deg": 35, "near": 0.1, "far": 50},
      "lights": [{"type": "square", "position": [0, 4, 0], "direction": [0, -1, 0], "up": [0, 0, -1], "width": 1.5}],
      "objects": [
        {"name": "floor", "id": 0, "type": "quad", "size": [8, 8], "casts_shadows": false},
        {"name": "ball", "id": 1, "type": "sphere", "radius": 0.8, "segments": 48, "transform": {"translate": [0, 1, 0]}}
      ]})";
    const Scene scene = loadScene(writeScene("tangent", "sphere", text));
    const glm::vec3 centre(0.0f, 1.0f, 0.0f), light(0.0f, 4.0f, 0.0f);
    const float width = 1.5f;
    // The fraction of the light in front of the analytic tangent plane at p.
    // The fraction of the light in front of the facet's plane at pixel i.
    auto front = [&](const Render& r, size_t i) {
        glm::vec3 p(r.positions.data[i * 3], r.positions.data[i * 3 + 1], r.positions.data[i * 3 + 2]);
        glm::vec3 n(r.normals.data[i * 3], r.normals.data[i * 3 + 1], r.normals.data[i * 3 + 2]);
        return shared::lightFractionInFront(shared::LIGHT_SHAPE_SQUARE, light, glm::vec3(1, 0, 0), glm::vec3(0, 0, -1),
                                            width, p, n);
    };
    const Render ref = render(scene, "reference", {{"samples", "256"}}, {}, 64);
    const Render ray = render(scene, "raytraced", {{"rays", "256"}}, {}, 64);
    double bandDiff = 0.0;
    size_t band = 0, beyond = 0;
    float worstCos = 1.0f;
    for (size_t i = 0; i < ref.ids.data.size(); ++i) {
        if (ref.ids.data[i] != 1.0f) continue;
        glm::vec3 p(ref.positions.data[i * 3], ref.positions.data[i * 3 + 1], ref.positions.data[i * 3 + 2]);
        glm::vec3 n(ref.normals.data[i * 3], ref.normals.data[i * 3 + 1], ref.normals.data[i * 3 + 2]);
        worstCos = std::min(worstCos, glm::dot(n, glm::normalize(p - centre)));
        const float f = front(ref, i);
        if (f == 0.0f) ++beyond;
        if (f > 0.1f && f < 0.9f) {
            bandDiff += std::abs(ref.visibility.data[i] - ray.visibility.data[i]);
            ++band;
        }
    }
    ASSERT_GT(band, 20u);
    ASSERT_GT(beyond, 20u);
    std::printf("sphere terminator: mean |reference - raytraced| on the band %.4f over %zu pixels\n",
                bandDiff / double(band), band);
    EXPECT_LT(bandDiff / double(band), 0.02);
    EXPECT_GT(worstCos, std::cos(glm::radians(5.4f))) << "a facet normal further from the sphere's than half a facet";
    for (const char* t : {"hard", "pcf", "pcss", "sssm", "ssm-gbp06", "ssm-contour", "ssv", "spsm", "reference", "raytraced"}) {
        SCOPED_TRACE(t);
        const Render r = std::string(t) == "reference" ? ref : std::string(t) == "raytraced" ? ray : render(scene, t, {}, {}, 64);
        expectInvariants(r, t);
        size_t lit = 0;
        for (size_t i = 0; i < r.ids.data.size(); ++i)
            if (r.ids.data[i] == 1.0f && front(r, i) == 0.0f) lit += r.visibility.data[i] != 0.0f;
        EXPECT_EQ(lit, 0u) << "pixels past the terminator with light";
    }
}

// The two references agree once both follow the convention (issue 17): `reference` with 256 light
// samples against `raytraced` with 256 rays, RMSE over all pixels at 128 x 128 (the issue's table
// is at 256 x 256, scripts/compare-references.sh). Measured at 128 x 128: square-occluder 0.0030,
// overlapping-occluders 0.0050, plant 0.0089, contact 0.0019, grazing 0.0026, complex 0.0094 (the
// test prints each with its bound's ratio to it); each bound is at most about 3x its measurement
// (square-occluder 3.05x, grazing 3.01x, contact 2.96x, the others 1.3-2.4x) and at most 0.012 (the
// issue's 0.01 at twice the pixel size).
// Contact was 0.0153 while the tangent plane was the interpolated normal's: along the sphere's and
// the torus's terminators a faceted mesh hides light behind its facets' planes, which the ray
// tracer found and the shadow map's depth test did not (shaders/common/gbuffer.frag).
TEST_F(HardCaseTangent, ReferencesAgreeOnTheTestScenes) {
    struct Bound {
        const char* scene;
        double rmse;
    };
    for (Bound b : {Bound{"square-occluder", 0.009}, Bound{"overlapping-occluders", 0.012}, Bound{"plant", 0.012},
                    Bound{"contact", 0.0057}, Bound{"grazing", 0.0078}, Bound{"complex", 0.012}}) {
        SCOPED_TRACE(b.scene);
        const Scene scene = loadScene(b.scene);
        const Render ref = render(scene, "reference", {{"samples", "256"}}, {}, 128);
        const Render ray = render(scene, "raytraced", {{"rays", "256"}}, {}, 128);
        const Metrics m = computeMetrics(ref.visibility, ray.visibility);
        std::printf("references on %s: RMSE %.4f (bound %.4f, %.2fx)\n", b.scene, m.rmse, b.rmse, b.rmse / m.rmse);
        EXPECT_LT(m.rmse, b.rmse);
    }
}

}  // namespace
}  // namespace shadowlab
