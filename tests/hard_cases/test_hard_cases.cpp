// The hard-case suite (DESIGN.md section 9, issue 11), ctest label `hard-case`: the shared GLSL/C++
// math and the existing techniques (hard, pcf, reference, raytraced) end to end, on inputs where
// numbers go wrong. Every case asserts numbers, and every render is checked for the invariants:
// v in [0, 1], no NaN or Inf in the visibility, the image, or the positions of geometry pixels.
// Images are small (32..64 px) so the whole suite stays a few seconds on llvmpipe.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "gl/util.h"
#include "graph/renderer.h"
#include "image/metrics.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"
#include "support/shadow_map_settings.h"
#include "support/hard_case_util.h"
#include "support/real_meshes.h"

namespace shadowlab {
namespace {

using namespace hardcase;
using namespace shared;

// ---- helpers ----------------------------------------------------------------------------------------

// Few samples or rays, for cases that check invariants and coarse numbers.
Sets quick(const std::string& technique, const char* count = "16") {
    if (technique == "raytraced") return {{"rays", count}};
    if (technique == "reference") return {{"samples", count}};
    return {};
}

std::string writeScene(const std::string& name, const std::string& text) {
    return hardcase::writeScene("hard-cases", name, text);
}


// ======== 1. the shared math on the CPU ==============================================================

// Mean |v_w - v_0| of the closed form along the line z = 0.3, x in [-2, 2] (8,000 cell centres:
// none on the hard edge |x| = 1, where the inclusive hard shadow and every soft one differ).
double closedFormDistanceToHard(float w) {
    double sum = 0.0;
    const int n = 8000;
    for (int i = 0; i < n; ++i) {
        const glm::vec3 p(-2.0f + 4.0f * (float(i) + 0.5f) / float(n), 0.0f, 0.3f);
        sum += std::abs(squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, w) - squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 0.0f));
    }
    return sum / n;
}

// Light size -> 0: the closed form converges to the hard shadow linearly in w (the penumbra is a
// band of width w * (occluder-receiver)/(light-occluder) = w around each hard edge, with the same
// profile at every w, so the mean difference over a fixed region is proportional to w: w / 8
// here, two edges of 4 units): halving w halves it within 5%, down to w = 0.0125 (25 cells).
TEST(HardCaseMath, LightSizeToZeroConvergesLinearly) {
    double previous = closedFormDistanceToHard(0.8f);
    EXPECT_NEAR(previous, 0.8 / 8.0, 0.005);
    for (float w : {0.4f, 0.2f, 0.1f, 0.05f, 0.025f, 0.0125f}) {
        const double d = closedFormDistanceToHard(w);
        EXPECT_NEAR(d / previous, 0.5, 0.025) << "w " << w;
        previous = d;
    }
    EXPECT_LT(closedFormDistanceToHard(1e-6f), 1e-6);
}

// The closed form is scale-free: v(s p; s a, s y_o, s y_l, s w) = v(p) for s = 1e-3 and 1e4.
TEST(HardCaseMath, ClosedFormIsScaleInvariant) {
    for (float s : {1e-3f, 1e4f}) {
        float worst = 0.0f;
        for (int y = 0; y <= 60; ++y)
            for (int x = 0; x <= 60; ++x) {
                const glm::vec3 p(-3.0f + 0.1f * float(x), 0.0f, -3.0f + 0.1f * float(y));
                const float v1 = squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f);
                const float vs = squareOccluderVisibility(s * p, 0.5f * s, 2.0f * s, 4.0f * s, 1.0f * s);
                worst = std::max(worst, std::abs(v1 - vs));
            }
        // Float rounding of the scaled interval ends, relative to w: a few ulps of values ~1.
        EXPECT_LT(worst, 2e-5f) << "scale " << s;
    }
}

// An occluder touching the receiver (y_o -> p.y): s = (y_l - p.y)/(y_o - p.y) -> infinity, and at
// y_o = p.y exactly the point is not below the occluder. v stays in [0, 1], 0 under the plate,
// 1 outside, and never NaN.
TEST(HardCaseMath, OccluderTouchingReceiver) {
    for (float gap : {1e-2f, 1e-4f, 1e-7f, 1e-30f, 0.0f}) {
        for (float x : {-2.0f, -0.5001f, -0.4999f, 0.0f, 0.3f, 0.4999f, 0.5001f, 3.0f}) {
            const float v = squareOccluderVisibility(glm::vec3(x, 0.0f, 0.0f), 0.5f, gap, 4.0f, 1.0f);
            ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << gap << " " << x;
            if (gap > 0.0f && gap <= 1e-4f) EXPECT_EQ(v, std::abs(x) < 0.5f ? 0.0f : 1.0f) << gap << " " << x;
        }
    }
    EXPECT_EQ(squareOccluderVisibility(glm::vec3(0.0f), 0.5f, 0.0f, 4.0f, 1.0f), 1.0f);  // p.y == y_o: not below
}

// An occluder almost at the light (y_o -> y_l): s -> 1 and the plate covers the light plane as
// itself; the 1 x 1 plate covers the whole 1 x 1 light from every floor point below it.
TEST(HardCaseMath, OccluderAlmostAtTheLight) {
    for (float gap : {1e-2f, 1e-4f, 1e-6f}) {
        for (float x : {-0.4f, 0.0f, 0.4f}) {
            const float v = squareOccluderVisibility(glm::vec3(x, 0.0f, 0.2f), 0.5f, 4.0f - gap, 4.0f, 1.0f);
            EXPECT_NEAR(v, 0.0f, 4.0f * gap) << gap << " " << x;
        }
        // A plate smaller than the light leaves the rest of the light visible: 1 - (0.5)^2.
        // (The plate back-projects scaled by s = 4 / (4 - gap): covered (0.5 s)^2, so within gap / 4.)
        EXPECT_NEAR(squareOccluderVisibility(glm::vec3(0.0f), 0.25f, 4.0f - gap, 4.0f, 1.0f), 0.75f, 0.2f * gap + 1e-6f);
    }
}

// Visibility never increases as the occluder grows (closed form, exact comparisons).
TEST(HardCaseMath, MonotoneAsTheOccluderGrows) {
    size_t violations = 0;
    for (int y = 0; y <= 40; ++y)
        for (int x = 0; x <= 40; ++x) {
            const glm::vec3 p(-2.0f + 0.1f * float(x), 0.0f, -2.0f + 0.1f * float(y));
            for (float w : {0.0f, 0.3f, 1.0f, 3.0f}) {
                float previous = 1.0f;
                for (float a = 0.0f; a <= 2.0f; a += 0.05f) {
                    const float v = squareOccluderVisibility(p, a, 2.0f, 4.0f, w);
                    violations += v > previous;
                    previous = v;
                }
            }
        }
    EXPECT_EQ(violations, 0u);
}

// Grazing receivers: cos(theta) -> 0 (and below: a back-facing normal) must not blow up the bias.
// The slope term is clamped at tan = 10, so the bias stays within texel * (const + 10 slope).
TEST(HardCaseMath, GrazingReceiverBiasIsBounded) {
    const float texel = 0.01f;
    for (float c : {1.0f, 0.5f, 0.1f, 1e-3f, 1e-6f, 0.0f, -0.5f, -1.0f}) {
        const float bias = shadowDepthBias(texel, 1.0f, 2.0f, c);
        ASSERT_TRUE(std::isfinite(bias)) << c;
        EXPECT_GE(bias, texel * 1.0f) << c;
        EXPECT_LE(bias, texel * (1.0f + 2.0f * 10.0f) * (1.0f + 1e-6f)) << c;
        const float rpb = receiverPlaneBias(texel, c, 3.0f);
        ASSERT_TRUE(std::isfinite(rpb)) << c;
        EXPECT_LE(rpb, texel * 10.0f * 3.0f * (1.0f + 1e-6f)) << c;
    }
    EXPECT_EQ(shadowDepthBias(texel, 1.0f, 2.0f, 1.0f), texel);  // facing the light: no slope term
}

// Near/far 1e5 in the light's projection: a point's light-view depth comes back exactly as the
// distance along the axis (it is not taken from the non-linear clip depth), and uv stays in [0, 1]
// for points inside the frustum.
TEST(HardCaseMath, NearFarRatio1e5Projection) {
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 4, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
    for (float nearPlane : {1e-4f, 1e-3f, 0.1f}) {
        const glm::mat4 clip = glm::perspective(glm::radians(90.0f), 1.0f, nearPlane, nearPlane * 1e5f);
        for (float depth : {2.0f * nearPlane, 1.0f, 3.9f, 100.0f}) {
            if (depth >= nearPlane * 1e5f) continue;
            const glm::vec3 p(0.3f * depth, 4.0f - depth, -0.2f * depth);
            const glm::vec4 c = shadowMapCoord(view, clip, p);
            // The point's y = 4 - depth is rounded to a float: its depth is exact only to ulp(4)
            // = 4.8e-7 absolute, so uv = 0.5 + 0.5 x / z to 0.5 * 0.3 * ulp(4) / depth relative.
            const float ulp4 = 4.8e-7f;
            EXPECT_NEAR(c.z, depth, 2.0f * ulp4 + 1e-6f * depth) << nearPlane << " " << depth;
            EXPECT_EQ(c.w, 1.0f);
            EXPECT_NEAR(c.x, 0.5f + 0.5f * 0.3f, 1e-5f + 0.5f * ulp4 / depth) << depth;
            EXPECT_NEAR(c.y, 0.5f + 0.5f * 0.2f, 1e-5f + 0.5f * ulp4 / depth) << depth;  // -z in view is up in the map
        }
        // Behind the light: outside (w <= 0), treated as lit by the callers.
        EXPECT_EQ(shadowMapCoord(view, clip, glm::vec3(0, 5, 0)).w, 0.0f);
    }
}

// Stratified samples at the extremes: n = 1 (one cell), n = 65536 (the largest), non-square n;
// every sample inside [0, 1)^2, weights summing to 1.
TEST(HardCaseMath, StratifiedSamplesAtTheExtremes) {
    for (uint n : {1u, 2u, 3u, 17u, 1000u, 65536u}) {
        double weights = 0.0;
        for (uint i = 0; i < n; ++i) {
            const glm::vec3 s = stratifiedSample(i, n, 12345u);
            ASSERT_TRUE(s.x >= 0.0f && s.x < 1.0f && s.y >= 0.0f && s.y < 1.0f) << n << " " << i;
            weights += s.z;
        }
        EXPECT_NEAR(weights, 1.0, 1e-4) << n;
    }
    // The disk map: the centre maps to 0, and nothing leaves the unit disk.
    EXPECT_EQ(concentricSquareToDisk(glm::vec2(0.5f)), glm::vec2(0.0f));
    for (float u : {0.0f, 1e-7f, 0.5f, 0.9999999f, 1.0f})
        for (float v : {0.0f, 0.5f, 1.0f}) EXPECT_LE(glm::length(concentricSquareToDisk(glm::vec2(u, v))), 1.0f + 1e-6f);
}

// ======== 2. GPU/CPU agreement of the shared math, hard inputs included ==============================

struct GpuCase {
    glm::vec4 a, b, c;
    glm::uvec4 d;
};
struct GpuResult {
    glm::vec4 closedForm, coord, sampleUvw, disk;
    glm::uvec4 hash;
};

class HardCaseGpu : public testing::GLTest {};

// The cases: receivers on a grid including the hard-shadow edges (|x| = 1), occluders touching the
// receiver and almost at the light, light widths 0 .. 2.5, cos(theta) from 1 to 0 and negative,
// sample counts 1 .. 65536.
std::vector<GpuCase> gpuCases() {
    std::vector<GpuCase> cases;
    const float xs[] = {-3.0f, -1.0f, -0.999f, -0.5f, 0.0f, 0.25f, 0.5f, 1.0f, 1.001f, 2.5f};
    const float occluderYs[] = {1e-6f, 0.5f, 2.0f, 3.9999f};
    const float widths[] = {0.0f, 1e-4f, 1.0f, 2.5f};
    const float cosines[] = {1.0f, 0.3f, 1e-5f, 0.0f, -0.7f};
    const uint ns[] = {1u, 2u, 7u, 256u, 65536u};
    uint k = 0;
    for (float x : xs)
        for (float z : xs)
            for (float oy : occluderYs)
                for (float w : widths) {
                    GpuCase c;
                    c.a = glm::vec4(x, 0.0f, z, 0.5f);
                    c.b = glm::vec4(oy, 4.0f, w, cosines[k % 5]);
                    c.c = glm::vec4(0.01f + 0.001f * float(k % 7), 1.0f, 2.0f, float(k % 5));
                    const uint n = ns[k % 5];
                    c.d = glm::uvec4((k * 2654435761u) % n, n, k, k * 97u);
                    cases.push_back(c);
                    ++k;
                }
    return cases;
}

TEST_F(HardCaseGpu, SharedMathAgreesWithCpu) {
    const std::vector<GpuCase> cases = gpuCases();
    Buffer input(cases.size() * sizeof(GpuCase), cases.data());
    Buffer output(cases.size() * sizeof(GpuResult));
    const glm::mat4 view = glm::lookAt(glm::vec3(0.1f, 4.0f, 0.2f), glm::vec3(0.1f, 0.0f, 0.2f), glm::vec3(0, 0, -1));
    const glm::mat4 clip = glm::perspective(glm::radians(100.0f), 1.0f, 1e-3f, 1e2f);  // near/far 1e5
    const ShaderProgram& program = programCache().compute("tests/hard_cases.comp");
    program.set("lightViewFromWorld", view);
    program.set("lightClipFromView", clip);
    program.set("count", unsigned(cases.size()));
    input.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    output.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.dispatch(GLuint((cases.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const std::vector<GpuResult> gpu = output.read<GpuResult>();
    ASSERT_EQ(gpu.size(), cases.size());

    // Tolerances. Visibility and the sample positions are values of order 1 built from a few
    // float operations; the GPU may fuse multiply-adds and round division differently: 4e-5
    // absolute (a few hundred ulps at 1, far below a visible difference). The hard shadow (w = 0)
    // is a comparison and must agree exactly except within 1e-5 of its edge. Biases are products:
    // 1e-5 relative. Projections: 1e-4 relative (a 4x4 matrix product and a division). Hashes and
    // strata rows are integer arithmetic: exact.
    size_t checked = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
        const GpuCase& c = cases[i];
        const GpuResult& g = gpu[i];
        const glm::vec3 p(c.a);
        const float cpuV = squareOccluderVisibility(p, c.a.w, c.b.x, c.b.y, c.b.z);
        if (c.b.z == 0.0f) {
            const bool nearEdge = std::abs(std::abs(p.x) - 1.0f) < 1e-3f || std::abs(std::abs(p.z) - 1.0f) < 1e-3f ||
                                  c.b.x < 1e-3f;
            if (!nearEdge) EXPECT_EQ(g.closedForm.x, cpuV) << i;
        } else {
            EXPECT_NEAR(g.closedForm.x, cpuV, 4e-5f) << i;
        }
        ASSERT_TRUE(g.closedForm.x >= 0.0f && g.closedForm.x <= 1.0f) << i;
        const float bias = shadowDepthBias(c.c.x, c.c.y, c.c.z, c.b.w);
        EXPECT_NEAR(g.closedForm.y, bias, 1e-5f * bias) << i;
        const float rpb = receiverPlaneBias(c.c.x, c.b.w, c.c.w);
        EXPECT_NEAR(g.closedForm.z, rpb, 1e-5f * std::max(rpb, 1e-3f)) << i;
        EXPECT_EQ(g.closedForm.w, intervalOverlap(c.a.x, c.a.y, -0.5f * c.b.z, 0.5f * c.b.z)) << i;
        const glm::vec4 coord = shadowMapCoord(view, clip, p);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.coord[k], coord[k], 1e-4f * std::max(1.0f, std::abs(coord[k]))) << i;
        EXPECT_EQ(g.coord.w, coord.w) << i;
        const glm::vec3 s = stratifiedSample(c.d.x, c.d.y, c.d.z);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.sampleUvw[k], s[k], 4e-5f) << i;
        EXPECT_NEAR(g.sampleUvw.w, shadowTexelWorldSize(p.y, c.c.x, 1024.0f), 1e-6f) << i;
        const glm::vec2 disk = concentricSquareToDisk(glm::vec2(s));
        EXPECT_NEAR(g.disk.x, disk.x, 1e-4f) << i;
        EXPECT_NEAR(g.disk.y, disk.y, 1e-4f) << i;
        EXPECT_EQ(g.hash.x, pcgHash(c.d.w)) << i;
        EXPECT_EQ(g.hash.y, strataRows(c.d.y)) << i;
        ++checked;
    }
    EXPECT_EQ(checked, 1600u);
}

// ======== 3. end to end through the renderer ==========================================================

class HardCase : public testing::GLTest {};

// Light size -> 0: `reference` converges to `hard` linearly in w, like the closed form (halving
// w halves the mean difference within 30%: the map's texel quantisation adds a floor of about one
// texel row of pixels); `pcf` softens by its kernel, not the light, so its hard limit is kernel 1,
// which equals `hard` exactly.
TEST_F(HardCase, LightSizeToZeroConvergesToHard) {
    const Scene scene = loadScene(writeScene("so", squareOccluder(1.0)));
    const Render hard = render(scene, "hard");
    expectInvariants(hard, "hard");
    double previous = 0.0;
    for (float w : {0.8f, 0.4f, 0.2f}) {
        const Render soft = render(scene, "reference", {{"samples", "64"}}, w);
        expectInvariants(soft, "reference");
        const double d = floorMeanAbs(soft, hard);
        if (previous > 0.0) EXPECT_NEAR(d / previous, 0.5, 0.15) << "w " << w;
        previous = d;
    }
    const Render pcf1 = render(scene, "pcf", {{"pcf_kernel", "1"}});
    expectInvariants(pcf1, "pcf");
    EXPECT_EQ(pcf1.visibility.data, hard.visibility.data);
}

// At light size exactly 0 every technique gives the point-light result: hard's, and raytraced's
// exact hard shadow agrees with it off the edges.
TEST_F(HardCase, LightSizeZeroEveryTechniqueIsHard) {
    const Scene scene = loadScene(writeScene("so", squareOccluder(1.0)));
    const Render hard = render(scene, "hard", {}, 0.0f);
    for (const char* t : {"pcf", "reference"}) {
        // The `hard` that replaces t keeps t's shadow-map settings (the reference's are its own).
        const Render same = render(scene, "hard", testing::shadowMapSettingsOf(t), 0.0f);
        EXPECT_EQ(render(scene, t, {}, 0.0f).visibility.data, same.visibility.data) << t;
    }
    const Render ray = render(scene, "raytraced", {{"rays", "1"}}, 0.0f);
    expectInvariants(ray, "raytraced");
    EXPECT_GE(floorAgreement(ray, hard, 0.0f), 0.97);
}

// Scene scale 1e-3 and 1e4 vs scale 1, on the closed form: the same visibility within the same
// tolerance at every scale (biases are in texels, near/far scale with the scene).
TEST_F(HardCase, SceneScale1eMinus3MatchesClosedForm) {
    for (const char* t : {"reference", "raytraced"}) {
        const Scene scene = loadScene(writeScene("s-small", squareOccluder(1e-3)));
        const Render r = render(scene, t, {{t == std::string("reference") ? "samples" : "rays", "256"}});
        expectInvariants(r, t);
        EXPECT_LT(closedFormRmse(r, 1e-3), 0.03) << t;
    }
}

TEST_F(HardCase, SceneScale1e4MatchesClosedForm) {
    for (const char* t : {"reference", "raytraced"}) {
        const Scene scene = loadScene(writeScene("s-large", squareOccluder(1e4)));
        const Render r = render(scene, t, {{t == std::string("reference") ? "samples" : "rays", "256"}});
        expectInvariants(r, t);
        EXPECT_LT(closedFormRmse(r, 1e4), 0.03) << t;
    }
}

TEST_F(HardCase, ScalesAgreeWithEachOther) {
    const Render r1 = render(loadScene(writeScene("s1", squareOccluder(1.0))), "raytraced", {{"rays", "64"}});
    for (double s : {1e-3, 1e4}) {
        const Render rs = render(loadScene(writeScene("ss", squareOccluder(s))), "raytraced", {{"rays", "64"}});
        // Same camera framing, same pixels: the same visibility up to float rounding of the ray
        // origins (a pixel on an edge may flip one ray of 64): 99% within 1/32.
        EXPECT_GE(floorAgreement(r1, rs, 1.0f / 32.0f), 0.99) << "scale " << s;
    }
}

// The closed form at scale 1 for the shadow-map reference and the ray tracer.
TEST_F(HardCase, SquareOccluderClosedFormAtScale1) {
    const Scene scene = loadScene(writeScene("so", squareOccluder(1.0)));
    const Render ref = render(scene, "reference", {{"samples", "256"}});
    const Render ray = render(scene, "raytraced", {{"rays", "256"}});
    size_t n = 0;
    EXPECT_LT(closedFormRmse(ref, 1.0, 0.5f, 2.0f, 1.0f, &n), 0.03);
    EXPECT_GT(n, 1000u);
    EXPECT_LT(closedFormRmse(ray, 1.0), 0.03);
}

// An occluder touching the receiver: a plate lying 1e-4 above the floor. The floor under it is
// dark and the floor 0.3 beyond its edge is lit (the penumbra there is w * gap / (4 - gap), 1e-5).
TEST_F(HardCase, OccluderTouchingTheReceiver) {
    const Scene scene = loadScene(writeScene("touch", squareOccluder(1.0, 0.5, 1e-3)));
    for (const char* t : {"hard", "pcf", "raytraced"}) {
        const Render r = render(scene, t, t == std::string("raytraced") ? Sets{{"rays", "16"}} : Sets{}, {}, 64);
        expectInvariants(r, t);
        size_t farLit = 0, far = 0;
        for (size_t i = 0; i < r.ids.data.size(); ++i) {
            if (r.ids.data[i] != 0.0f) continue;
            const float x = r.positions.data[i * 3], z = r.positions.data[i * 3 + 2];
            if (std::max(std::abs(x), std::abs(z)) > 0.8f) {
                ++far;
                farLit += r.visibility.data[i] > 0.99f;
            }
        }
        EXPECT_GT(far, 500u);
        EXPECT_GE(double(farLit) / double(far), 0.995) << t;
    }
}

// An occluder almost at the light: the plate 0.01 below the light covers all of it from the floor
// (closed form v <= 0.005 on [-1.5, 1.5]^2). The shadow map's near plane must not clip it away.
// 64 samples/rays: one unoccluded sample is 1/64, two (the uncovered sliver is 0.0025 wide) 0.03.
TEST_F(HardCase, OccluderAlmostAtTheLight) {
    const Scene scene = loadScene(writeScene("near-light", squareOccluder(1.0, 0.5, 3.99)));
    for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
        const Render r = render(scene, t, quick(t, "64"));
        expectInvariants(r, t);
        size_t inside = 0, dark = 0;
        for (size_t i = 0; i < r.ids.data.size(); ++i) {
            if (r.ids.data[i] != 0.0f) continue;
            const float x = r.positions.data[i * 3], z = r.positions.data[i * 3 + 2];
            if (std::max(std::abs(x), std::abs(z)) > 1.5f) continue;
            ++inside;
            dark += r.visibility.data[i] < 0.05f;  // closed form <= 0.005 plus two samples
        }
        EXPECT_GT(inside, 300u);
        EXPECT_EQ(dark, inside) << t;
    }
}

// Grazing receivers (the `grazing` scene: ramps at shallow angles, a large depth range): every
// technique keeps the invariants, and hard agrees with the ray-traced point light on >= 95% of
// geometry pixels (the rest: acne/peter-panning within the bias on the steepest ramp).
TEST_F(HardCase, GrazingReceivers) {
    const Scene scene = loadScene("grazing");
    const Render hard = render(scene, "hard", {}, 0.0f);
    const Render ray = render(scene, "raytraced", {{"rays", "1"}}, 0.0f);
    expectInvariants(hard, "hard");
    expectInvariants(ray, "raytraced");
    size_t same = 0, n = 0;
    for (size_t i = 0; i < hard.ids.data.size(); ++i) {
        if (hard.ids.data[i] < 0.0f) continue;
        ++n;
        same += hard.visibility.data[i] == ray.visibility.data[i];
    }
    EXPECT_GT(n, 500u);
    EXPECT_GE(double(same) / double(n), 0.95);
    for (const char* t : {"pcf", "reference"}) expectInvariants(render(scene, t, quick(t)), t);
}

// Near/far ratio 1e5 for the camera: near 1e-4, far 10 (square-occluder's depth range is 10), the
// same hard shadow as with near 0.1 on >= 99% of floor pixels.
TEST_F(HardCase, CameraNearFar1e5) {
    const Render normal = render(loadScene(writeScene("nf1", squareOccluder(1.0))), "hard");
    const Render extreme = render(loadScene(writeScene("nf2", squareOccluder(1.0, 0.5, 2.0, 1.0, 1e-4, 10.0))), "hard");
    expectInvariants(extreme, "hard near 1e-4");
    EXPECT_GE(floorAgreement(normal, extreme, 0.0f), 0.99);
    const Render far = render(loadScene(writeScene("nf3", squareOccluder(1.0, 0.5, 2.0, 1.0, 0.1, 1e4))), "pcf");
    expectInvariants(far, "pcf far 1e4");
    EXPECT_GE(floorAgreement(render(loadScene(writeScene("nf1", squareOccluder(1.0))), "pcf"), far, 0.02f), 0.99);
}

// A 1x1 shadow map stores one depth (the nearest occluder over the whole frustum): visibility is
// 0 or 1 everywhere and stays in range with every filter.
TEST_F(HardCase, ShadowMap1x1) {
    const Scene scene = loadScene(writeScene("so", squareOccluder(1.0)));
    for (const char* t : {"hard", "pcf"}) {
        const Render r = render(scene, t, {{"sm_size", "1"}}, {}, 32);
        expectInvariants(r, t);
        if (t == std::string("hard"))
            for (float v : r.visibility.data) ASSERT_TRUE(v == 0.0f || v == 1.0f) << v;
    }
}

// The largest shadow map the driver allows (and the parameter's range: 8192): the hard shadow is
// exact against the closed form off its edges.
TEST_F(HardCase, ShadowMapLargest) {
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    ASSERT_GE(maxSize, 1024);
    const int size = std::min(maxSize, 8192);
    const Scene scene = loadScene(writeScene("so", squareOccluder(1.0, 0.5, 2.0, 0.0)));
    const Render r = render(scene, "hard", {{"sm_size", std::to_string(size)}}, {}, 32);
    expectInvariants(r, "hard");
    size_t wrong = 0, n = 0;
    for (size_t i = 0; i < r.ids.data.size(); ++i) {
        if (r.ids.data[i] != 0.0f) continue;
        const float x = r.positions.data[i * 3], z = r.positions.data[i * 3 + 2];
        if (std::abs(std::abs(x) - 1.0f) < 0.02f || std::abs(std::abs(z) - 1.0f) < 0.02f) continue;
        ++n;
        wrong += r.visibility.data[i] != squareOccluderVisibility(glm::vec3(x, 0, z), 0.5f, 2.0f, 4.0f, 0.0f);
    }
    EXPECT_GT(n, 300u);
    EXPECT_EQ(wrong, 0u) << "sm_size " << size;
}

// No objects: every technique gives v = 1 and background everywhere, the image finite.
TEST_F(HardCase, EmptyScene) {
    const Scene scene = loadScene(writeScene("empty", R"({"camera": {"position": [0, 5, 5], "target": [0, 0, 0]},
        "lights": [{"type": "square", "position": [0, 4, 0], "width": 1}], "objects": []})"));
    for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
        const Render r = render(scene, t, quick(t), {}, 16);
        expectInvariants(r, t);
        for (size_t i = 0; i < r.visibility.data.size(); ++i) {
            ASSERT_EQ(r.visibility.data[i], 1.0f) << t;
            ASSERT_EQ(r.ids.data[i], -1.0f) << t;
        }
    }
}

// The camera inside a closed box: every pixel sees the box's inside (id 1), nothing is NaN.
TEST_F(HardCase, CameraInsideGeometry) {
    const Scene scene = loadScene(writeScene("camera-inside", R"({
        "camera": {"position": [0, 1, 0], "target": [0, 1, -1], "near": 0.01, "far": 20},
        "lights": [{"type": "square", "position": [0, 4, 0], "width": 1}],
        "objects": [{"name": "floor", "id": 0, "type": "quad", "size": [8, 8]},
                    {"name": "box", "id": 1, "type": "box", "size": [2, 2, 2], "transform": {"translate": [0, 1, 0]}}]})"));
    for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
        const Render r = render(scene, t, quick(t), {}, 24);
        expectInvariants(r, t);
        size_t box = 0;
        for (float id : r.ids.data) box += id == 1.0f;
        EXPECT_EQ(box, r.ids.data.size()) << t;
        // The light is outside the closed box: its inside is in shadow (faces pointing away from
        // the light are 0 by the depth test or by the ray tracer; allow the bias band at corners).
        size_t dark = 0;
        for (float v : r.visibility.data) dark += v < 0.5f;
        EXPECT_GE(double(dark) / double(r.visibility.data.size()), 0.9) << t;
    }
}

// The light inside a closed box: the floor outside is in shadow for every technique.
TEST_F(HardCase, LightInsideGeometry) {
    const Scene scene = loadScene(writeScene("light-inside", R"({"camera": {"position": [0, 5, 6], "target": [0, 0, 0]},
        "lights": [{"type": "square", "position": [0, 1, 0], "width": 0.2}],
        "objects": [{"name": "floor", "id": 0, "type": "quad", "size": [8, 8]},
                    {"name": "box", "id": 1, "type": "box", "size": [1, 1, 1], "transform": {"translate": [0, 1, 0]}}]})"));
    for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
        const Render r = render(scene, t, quick(t), {}, 32);
        expectInvariants(r, t);
        size_t floor = 0, lit = 0;
        for (size_t i = 0; i < r.ids.data.size(); ++i) {
            if (r.ids.data[i] != 0.0f) continue;
            ++floor;
            lit += r.visibility.data[i] > 0.5f;
        }
        EXPECT_GT(floor, 100u);
        EXPECT_LE(double(lit) / double(floor), 0.02) << t;
    }
}

// Back-facing and double-sided geometry: a single quad (one-sided, no thickness) as the occluder,
// facing the light or facing away, casts the same shadow in every technique (shadow maps must
// not cull back faces; rays hit both sides). 98% of floor pixels agree between the two.
TEST_F(HardCase, BackfacingOccluderCastsTheSameShadow) {
    const auto quadScene = [](const char* name, const char* rotate) {
        return loadScene(writeScene(name, std::string(R"({"camera": {"position": [0, 5.5, 6.5], "target": [0, 0, 0.3], "fov_deg": 40},
          "lights": [{"type": "square", "position": [0, 4, 0], "width": 1}],
          "objects": [{"name": "floor", "id": 0, "type": "quad", "size": [8, 8], "casts_shadows": false},
                      {"name": "sheet", "id": 1, "type": "quad", "size": [1, 1], "transform": {"translate": [0, 2, 0], "rotate_deg": )") +
                                        rotate + "}}]}"));
    };
    const Scene up = quadScene("sheet-up", "[0, 0, 0]");
    const Scene down = quadScene("sheet-down", "[180, 0, 0]");
    for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
        const Sets sets = t == std::string("raytraced") ? Sets{{"rays", "64"}} : t == std::string("reference") ? Sets{{"samples", "64"}} : Sets{};
        const Render a = render(up, t, sets), b = render(down, t, sets);
        expectInvariants(a, t);
        expectInvariants(b, t);
        EXPECT_GE(floorAgreement(a, b, 0.05f), 0.98) << t;
        // And it is a shadow: the closed form of a (zero-thickness) plate.
        EXPECT_LT(closedFormRmse(b, 1.0), t == std::string("hard") || t == std::string("pcf") ? 0.2 : 0.04) << t;
    }
}

// Monotone as the occluder grows: plates of half size 0.3, 0.5, 0.7; per pixel, visibility does not
// increase (hard: exactly, off a one-pixel edge band; reference: within its sampling noise 0.03).
TEST_F(HardCase, MonotoneAsTheOccluderGrows) {
    for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
        std::vector<Render> renders;
        for (double half : {0.3, 0.5, 0.7})
            renders.push_back(render(loadScene(writeScene("grow", squareOccluder(1.0, half))), t, quick(t, "64")));
        for (size_t k = 1; k < renders.size(); ++k) {
            expectInvariants(renders[k], t);
            size_t up = 0, n = 0;
            for (size_t i = 0; i < renders[k].ids.data.size(); ++i) {
                if (renders[k].ids.data[i] != 0.0f || renders[k - 1].ids.data[i] != 0.0f) continue;
                ++n;
                up += renders[k].visibility.data[i] > renders[k - 1].visibility.data[i] + 0.03f;
            }
            EXPECT_LE(double(up) / double(n), 0.002) << t << " step " << k;
        }
    }
}

// Every technique on every shipped scene, at 24x24: the invariants hold (a broad net for NaN).
TEST_F(HardCase, EveryShippedSceneKeepsTheInvariants) {
    for (const std::string& name : testing::loadableScenes()) {
        const Scene scene = loadScene(name);
        for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
            const Render r = render(scene, t, t == std::string("raytraced") ? Sets{{"rays", "4"}} : t == std::string("reference") ? Sets{{"samples", "4"}} : Sets{}, {}, 24);
            expectInvariants(r, name + " " + t);
        }
    }
}

// Huge light (width 100, much wider than the scene): the whole floor sees most of the light;
// closed form and references agree.
TEST_F(HardCase, HugeLight) {
    const Scene scene = loadScene(writeScene("huge-light", squareOccluder(1.0, 0.5, 2.0, 100.0)));
    const Render ray = render(scene, "raytraced", {{"rays", "256"}});
    expectInvariants(ray, "raytraced");
    EXPECT_LT(closedFormRmse(ray, 1.0, 0.5f, 2.0f, 100.0f), 0.03);
    const Render ref = render(scene, "reference", {{"samples", "256"}});
    expectInvariants(ref, "reference");
    EXPECT_LT(closedFormRmse(ref, 1.0, 0.5f, 2.0f, 100.0f), 0.05);
}

// The plate's edge exactly under the light's edge (x = 0.5 both): the closed form's breakpoints
// coincide; the references still agree with it.
TEST_F(HardCase, EdgesAlignedWithTheLightBorder) {
    const Scene scene = loadScene(writeScene("aligned", squareOccluder(1.0, 0.5, 2.0, 1.0)));
    const Render ray = render(scene, "raytraced", {{"rays", "256"}}, {}, 64);
    expectInvariants(ray, "raytraced");
    EXPECT_LT(closedFormRmse(ray, 1.0), 0.03);
    // On the CPU: points whose back-projection puts an interval end exactly on +-0.5.
    EXPECT_EQ(squareOccluderVisibility(glm::vec3(1.5f, 0.0f, 0.0f), 0.5f, 2.0f, 4.0f, 1.0f), 1.0f);
    EXPECT_EQ(squareOccluderVisibility(glm::vec3(0.5f, 0.0f, 0.0f), 0.5f, 2.0f, 4.0f, 1.0f), 0.0f);
    EXPECT_FLOAT_EQ(squareOccluderVisibility(glm::vec3(1.0f, 0.0f, 0.0f), 0.5f, 2.0f, 4.0f, 1.0f), 0.5f);
}

// Degenerate geometry: a zero-area (collinear) triangle occluder from a glTF file casts nothing and
// produces no NaN normals in the G-buffer.
TEST_F(HardCase, DegenerateTrianglesCastNothing) {
    const std::string scene = writeScene("degenerate", R"({"camera": {"position": [0, 5.5, 6.5], "target": [0, 0, 0.3], "fov_deg": 40},
        "lights": [{"type": "square", "position": [0, 4, 0], "width": 1}],
        "objects": [{"name": "floor", "id": 0, "type": "quad", "size": [8, 8], "casts_shadows": false},
                    {"name": "line", "id": 1, "type": "box", "size": [1, 1e-30, 1e-30], "transform": {"translate": [0, 2, 0]}}]})");
    const Scene s = loadScene(scene);
    for (const char* t : {"hard", "pcf", "reference", "raytraced"}) {
        const Render r = render(s, t, quick(t), {}, 32);
        expectInvariants(r, t);
        size_t lit = 0, n = 0;
        for (size_t i = 0; i < r.ids.data.size(); ++i) {
            if (r.ids.data[i] != 0.0f) continue;
            ++n;
            lit += r.visibility.data[i] > 0.99f;
        }
        EXPECT_GE(double(lit) / double(n), 0.99) << t;
    }
}

}  // namespace
}  // namespace shadowlab
