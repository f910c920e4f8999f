// Hard cases for the soft-shadow techniques merged after the first suite (issue 11 item 1):
// pcss, sssm, ssm-gbp06, ssm-contour. Label `hard-case` (this file joins shadowlab_hard_cases by
// the tests/hard_cases/*.cpp glob). Small images (40 px) and a 256 shadow map keep these
// techniques (slow on llvmpipe at large light sizes) to a few seconds in all. Every render is
// checked for v in [0, 1] and no NaN/Inf in visibility, image and geometry positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "graph/renderer.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"
#include "support/hard_case_util.h"

namespace shadowlab {
namespace {

using namespace hardcase;
using namespace shared;

const char* const kSoft[] = {"pcss", "sssm", "ssm-gbp06", "ssm-contour"};
constexpr int kSize = 40;

std::string writeScene(const std::string& name, const std::string& text) {
    return hardcase::writeScene("hard-cases-soft", name, text);
}

// The four at a small shadow map (sm_size 256) unless the sets say otherwise; light size first.
Render renderSoft(const Scene& scene, const std::string& technique, std::optional<float> lightSize = {}, Sets sets = {},
                  int size = kSize) {
    if (technique != "raytraced" && technique != "reference") sets.insert(sets.begin(), {"sm_size", "256"});
    return hardcase::render(scene, technique, sets, lightSize, size);
}

// The closed form's RMSE over the floor, infinite when fewer than 200 floor pixels show (a case
// whose camera lost the floor must fail, not pass on no pixels).
double closedFormRmseSoft(const Render& r, double s, float plateHalf = 0.5f, float plateY = 2.0f, float lightWidth = 1.0f) {
    size_t n = 0;
    double rmse = hardcase::closedFormRmse(r, s, plateHalf, plateY, lightWidth, &n);
    return n > 200 ? rmse : INFINITY;
}


class HardCaseSoft : public testing::GLTest {};

// Light size exactly 0: every one of the four gives hard's visibility, bit for bit (no blocker
// search width, no penumbra, no back-projected area: each falls back to the hard test).
TEST_F(HardCaseSoft, LightSizeZeroIsExactlyHard) {
    const Scene scene = loadScene(writeScene("so", squareOccluder(1.0)));
    const Render hard = renderSoft(scene, "hard", 0.0f);
    for (const char* t : kSoft) {
        const Render r = renderSoft(scene, t, 0.0f);
        expectInvariants(r, t);
        EXPECT_EQ(r.visibility.data, hard.visibility.data) << t;
    }
}

// Light size -> 0: the mean |v - v_hard| over the floor shrinks at least linearly in w, and at the
// rate the closed form's own distance from its hard shadow shrinks: a technique that always returns
// the hard shadow (distance 0) fails, as one that stays soft does. Measured (40 px, sm_size 256;
// the test prints them), w = 0.4, 0.2, 0.1, 0.05: closed form 0.0155, 0.0069, 0.0026, 0.0009; pcss
// 0.0158, 0.0077, 0.0039, 0 (ratios to the closed form 1.02, 1.13, 1.50, then the kernel falls
// below one texel); ssm-gbp06 0.0156, 0.0087, 0.0047, 0.0015 and ssm-contour 0.0156, 0.0086,
// 0.0046, 0.0015 (ratios 1.01, 1.25, 1.81, 1.72); sssm 0.0052, 4e-5, 0, 0 (ratio 0.34 at w = 0.4:
// its screen-space kernel, 4 px there, drops below one pixel first). Asserted: each halving
// multiplies the difference by at most 0.65 (plus 1e-4 absolute for the exact zeros); at w = 0.4
// the ratio to the closed form is within [0.8, 1.25] (sssm: at least 0.25) and at w = 0.2 within
// [0.8, 1.6] for the three that filter in the map.
TEST_F(HardCaseSoft, LightSizeToZeroConvergesToHard) {
    const Scene scene = loadScene(writeScene("so", squareOccluder(1.0)));
    const Render hard = renderSoft(scene, "hard");
    for (const char* t : kSoft) {
        double previous = -1.0;
        for (float w : {0.4f, 0.2f, 0.1f, 0.05f}) {
            const Render r = renderSoft(scene, t, w);
            expectInvariants(r, t);
            const double d = floorMeanAbs(r, hard);
            double exact = 0.0;
            size_t n = 0;
            for (size_t i = 0; i < r.ids.data.size(); ++i) {
                if (r.ids.data[i] != 0.0f) continue;
                const glm::vec3 p(r.positions.data[i * 3], 0.0f, r.positions.data[i * 3 + 2]);
                exact += std::abs(squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, w) - squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 0.0f));
                ++n;
            }
            exact /= double(std::max<size_t>(n, 1));
            std::printf("%s w %.3g: floor mean |v - v_hard| %.5g, closed form's %.5g, ratio %.3f\n", t, double(w), d, exact, d / exact);
            if (previous < 0.0) EXPECT_LT(d, 0.03) << t;
            else EXPECT_LE(d, 0.65 * previous + 1e-4) << t << " w " << w << " previous " << previous;
            const bool screenSpace = std::string(t) == "sssm";
            if (w == 0.4f) {
                EXPECT_GE(d / exact, screenSpace ? 0.25 : 0.8) << t << ": no softer than hard at w = 0.4";
                if (!screenSpace) EXPECT_LE(d / exact, 1.25) << t;
            }
            if (w == 0.2f && !screenSpace) {
                EXPECT_GE(d / exact, 0.8) << t << " w 0.2";
                EXPECT_LE(d / exact, 1.6) << t << " w 0.2";
            }
            previous = d;
        }
    }
}

// An occluder touching the receiver (the plate 1e-3 above the floor): the penumbra is
// w * gap / (4 - gap) = 2.5e-4 wide, so the closed form is the plate's footprint; every
// technique matches it (measured RMSE 0 for all four, printed; asserted < 0.01, a few edge pixels).
TEST_F(HardCaseSoft, OccluderTouchingTheReceiver) {
    const Scene scene = loadScene(writeScene("touch", squareOccluder(1.0, 0.5, 1e-3)));
    for (const char* t : kSoft) {
        const Render r = renderSoft(scene, t);
        expectInvariants(r, t);
        const double e = closedFormRmseSoft(r, 1.0, 0.5f, 1e-3f);
        std::printf("%s touching: RMSE to the closed form %.4f\n", t, e);
        EXPECT_LT(e, 0.01) << t;
    }
}

// An occluder almost at the light (the plate 0.01 below it): the blocker search and the filter or
// back-projection kernels are widest here and must be clamped (pcss/sssm: 2 sm_size - 1 texels and
// m; the ssm's: max_kernel), so a render at the default light size still finishes in bounded time
// with sm_size 1024 (asserted < 20 s per render; measured at most 0.17 s at 40 px), and the
// floor matches the closed form (almost all dark): measured RMSE 0.0070 for all four at both map
// sizes (the test prints them), asserted < 0.02 at both.
TEST_F(HardCaseSoft, OccluderAlmostAtTheLight) {
    const Scene scene = loadScene(writeScene("near-light", squareOccluder(1.0, 0.5, 3.99)));
    for (const char* t : kSoft) {
        for (const char* sm : {"256", "1024"}) {
            const Render r = renderSoft(scene, t, {}, {{"sm_size", sm}});
            expectInvariants(r, t);
            const double e = closedFormRmseSoft(r, 1.0, 0.5f, 3.99f);
            std::printf("%s near the light, sm_size %s: RMSE to the closed form %.4f, render %.3f s\n", t, sm, e, r.seconds);
            EXPECT_LT(e, 0.02) << t << " sm_size " << sm;
            EXPECT_LT(r.seconds, 20.0) << t << " sm_size " << sm;
        }
    }
}

// Grazing receivers (the `grazing` scene: ramps at shallow angles): at its own light size every
// technique keeps the invariants; at light size 0 each equals hard on >= 99% of geometry pixels.
TEST_F(HardCaseSoft, GrazingReceivers) {
    const Scene scene = loadScene("grazing");
    const Render hard = renderSoft(scene, "hard", 0.0f);
    for (const char* t : kSoft) {
        expectInvariants(renderSoft(scene, t), t);
        const Render r = renderSoft(scene, t, 0.0f);
        expectInvariants(r, t);
        size_t same = 0, n = 0;
        for (size_t i = 0; i < r.ids.data.size(); ++i) {
            if (r.ids.data[i] < 0.0f) continue;
            ++n;
            same += r.visibility.data[i] == hard.visibility.data[i];
        }
        EXPECT_GT(n, 300u) << t;
        EXPECT_GE(double(same) / double(n), 0.99) << t;
    }
}

// Scene scale 1e-3 and 1e4: the RMSE against the closed form is the scale-1 RMSE within 0.003
// (biases are in texels, near/far scale with the scene). Measured RMSE (printed), equal to 4 digits
// at all three scales: pcss 0.0113, sssm 0.0348, ssm-gbp06 0.0088, ssm-contour 0.0087.
TEST_F(HardCaseSoft, SquareOccluderClosedFormAtEveryScale) {
    for (const char* t : kSoft) {
        const Render r1 = renderSoft(loadScene(writeScene("s1", squareOccluder(1.0))), t);
        expectInvariants(r1, t);
        const double e1 = closedFormRmseSoft(r1, 1.0);
        std::printf("%s scale 1: RMSE to the closed form %.4f\n", t, e1);
        EXPECT_LT(e1, std::string(t) == "sssm" ? 0.05 : 0.02) << t;
        for (double s : {1e-3, 1e4}) {
            const Render r = renderSoft(loadScene(writeScene("ss", squareOccluder(s))), t);
            expectInvariants(r, t);
            const double e = closedFormRmseSoft(r, s);
            std::printf("%s scale %g: RMSE to the closed form %.4f\n", t, s, e);
            EXPECT_NEAR(e, e1, 0.003) << t << " scale " << s;
        }
    }
}

// A silhouette edge whose back-projection passes exactly through the light centre (DESIGN.md
// section 9): seen from a floor point at x = 1, the plate's edge x = 0.5 projects onto the light
// through its centre (the hard shadow's border), and at (1, 1) the plate's corner does (two edges
// and their shared vertex through the centre). The camera looks straight down at (1, 0, 0) with an
// odd image size, so the centre column of pixels lies on x = 1 and the centre row on z = 0 (to
// float rounding). There the closed form is v = 0.5 (edge, |z| < 0.5) and v = 0.75 at the corner,
// and v is linear in x across the edge (slope 1 per world unit, 0.107 per pixel here), so besides
// the closed form each technique must show no spike on the degenerate column: its value within
// `spike` of the mean of its two neighbours. Measured (41 px, sm_size 256; the test prints them),
// column maxima of |v - exact| and |v - neighbours|, edge / corner:
//   pcss 0.041 / 0.057 and 0.032; sssm 0.139 / 0.159 and 0.008; ssm-gbp06 0.030 / 0.029 and 0;
//   ssm-contour 0.030 / 0.029 and 0; reference (256 samples) 0.010 / 0.009 and 0.012 / 0.010;
//   raytraced (256 rays) 0.008 / 0.007 and 0.010. At the centre pixel itself the references give
//   0.5000 and 0.7500.
// Asserted 1.3x (the reference's spike, 0.015 over 0.012) to 2x (sssm's spike, raytraced's closed
// form) those, most about 1.5x; the ssm's spike bound 0.01 is a margin over their 0. The
// shadow-map techniques' 0.02-0.03 is the plate edge's position quantised to the 256 map, the same
// off the degenerate column; sssm's 0.16 is its separable filter darkening where the two edges'
// penumbrae cross near the corner, a property of the paper's separable approximation, not of the
// degenerate edge (it shows no spike: 0.008).
// The column is exactly degenerate for the closed form, `reference` and `raytraced`; for the
// shadow-map techniques the edge is the plate's edge quantised to a texel border, so their exactly
// degenerate line runs within a third of a pixel of the column. Edges and vertices exactly through
// the centre in the shared back-projection math are tested on the CPU
// (RadialIntegration.EdgesAndVerticesThroughTheCentre) and on the GPU grid (test_hard_cases_gpu.cpp).
TEST_F(HardCaseSoft, SilhouetteEdgeThroughTheLightCentre) {
    constexpr int kOdd = 41;
    for (const float cz : {0.0f, 1.0f}) {  // the edge's middle, then the corner
        char text[2048];
        std::snprintf(text, sizeof text, R"({
          "camera": {"position": [1, 6, %.9g], "target": [1, 0, %.9g], "up": [0, 0, -1], "fov_deg": 40, "near": 0.1, "far": 50},
          "lights": [{"type": "square", "position": [0, 4, 0], "direction": [0, -1, 0], "up": [0, 0, -1], "width": 1}],
          "objects": [
            {"name": "floor", "id": 0, "type": "quad", "size": [8, 8], "casts_shadows": false},
            {"name": "plate", "id": 1, "type": "box", "size": [1, 0.001, 1], "transform": {"translate": [0, 2, 0]}}
          ]})", double(cz), double(cz));
        const Scene scene = loadScene(writeScene(cz == 0.0f ? "edge-centre" : "corner-centre", text));
        struct Tolerance {
            const char* technique;
            double closedForm, spike;
        };
        const Tolerance techniques[] = {{"pcss", 0.085, 0.05},       {"sssm", 0.24, 0.015},       {"ssm-gbp06", 0.045, 0.01},
                                        {"ssm-contour", 0.045, 0.01}, {"reference", 0.015, 0.015}, {"raytraced", 0.015, 0.015}};
        for (const auto& [t, tol, spike] : techniques) {
            SCOPED_TRACE(std::string(t) + (cz == 0.0f ? " edge" : " corner"));
            const Sets sets = std::string(t) == "reference" ? Sets{{"samples", "256"}}
                              : std::string(t) == "raytraced" ? Sets{{"rays", "256"}} : Sets{};
            const Render r = renderSoft(scene, t, {}, sets, kOdd);
            expectInvariants(r, t);
            const int c = kOdd / 2;
            auto at = [&](int x, int y) { return size_t(y) * size_t(kOdd) + size_t(x); };
            // The centre pixel is on the degenerate point itself.
            const size_t centre = at(c, c);
            ASSERT_EQ(r.ids.data[centre], 0.0f);
            EXPECT_NEAR(r.positions.data[centre * 3], 1.0f, 1e-4f);
            EXPECT_NEAR(r.positions.data[centre * 3 + 2], cz, 1e-4f);
            const glm::vec3 p(r.positions.data[centre * 3], 0.0f, r.positions.data[centre * 3 + 2]);
            EXPECT_NEAR(squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f), cz == 0.0f ? 0.5f : 0.75f, 1e-3f);
            // Along the centre column (x = 1): the closed form, and no spike against the neighbours.
            int checked = 0;
            double maxError = 0.0, maxSpike = 0.0;
            for (int y = 1; y + 1 < kOdd; ++y) {
                const size_t i = at(c, y);
                if (r.ids.data[i] != 0.0f || r.ids.data[at(c - 1, y)] != 0.0f || r.ids.data[at(c + 1, y)] != 0.0f) continue;
                const glm::vec3 q(r.positions.data[i * 3], 0.0f, r.positions.data[i * 3 + 2]);
                const float exact = squareOccluderVisibility(q, 0.5f, 2.0f, 4.0f, 1.0f);
                const float v = r.visibility.data[i];
                EXPECT_NEAR(v, exact, tol) << "pixel " << c << "," << y << " at z " << q.z;
                const float neighbours = 0.5f * (r.visibility.data[at(c - 1, y)] + r.visibility.data[at(c + 1, y)]);
                EXPECT_NEAR(v, neighbours, spike) << "spike at pixel " << c << "," << y << " at z " << q.z;
                maxError = std::max(maxError, double(std::abs(v - exact)));
                maxSpike = std::max(maxSpike, double(std::abs(v - neighbours)));
                ++checked;
            }
            std::printf("%s %s: centre v %.4f (exact %.2f), column max |v - exact| %.4f, max |v - neighbours| %.4f\n", t,
                        cz == 0.0f ? "edge" : "corner", double(r.visibility.data[centre]), cz == 0.0f ? 0.5 : 0.75, maxError,
                        maxSpike);
            EXPECT_GT(checked, 30) << "floor pixels on the centre column";
        }
    }
}

// Monotone as the occluder grows: a larger plate never lights a floor pixel more (0.01 slack for
// the soft techniques' filtering of a moved edge; the hard test alone is exact).
TEST_F(HardCaseSoft, MonotoneAsTheOccluderGrows) {
    for (const char* t : kSoft) {
        Render previous;
        for (double half : {0.3, 0.5, 0.7}) {
            const Render r = renderSoft(loadScene(writeScene("grow", squareOccluder(1.0, half))), t);
            expectInvariants(r, t);
            if (!previous.visibility.data.empty()) {
                size_t brighter = 0;
                for (size_t i = 0; i < r.ids.data.size(); ++i)
                    if (r.ids.data[i] == 0.0f) brighter += r.visibility.data[i] > previous.visibility.data[i] + 0.01f;
                EXPECT_EQ(brighter, 0u) << t << " half " << half;
            }
            previous = r;
        }
    }
}

}  // namespace
}  // namespace shadowlab
