// pcss (Fernando 2005; buades2015 sec. 2, eq. 1): the shared penumbra math on the CPU with the hard
// cases of DESIGN.md section 9, the same GLSL on the GPU, and end-to-end renders against the
// square-occluder closed form and hard shadows; bad parameter values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "error.h"
#include "gl/util.h"
#include "graph/internals.h"
#include "graph/renderer.h"
#include "image/metrics.h"
#include "pcss/pcss.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/cli_run.h"
#include "support/gl_fixture.h"
#include "support/shadow_map_settings.h"

namespace shadowlab {
namespace {

using namespace shared;

// ---- blocker averaging (buades2015 sec. 4, blocker_sum / blocker_count) ---------------------------
TEST(PenumbraMath, BlockerAverageOfThePapersExample) {
    // buades2015 Fig. 2: 20 samples in front of a receiver at 15 (bias 1, so depth < 14) summing to
    // 163: z_avg = 8.15; eq. 1 then gives w_light * 0.84.
    vec2 acc(0.0f);
    const float stored[] = {8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 9, 10, 14, 15, 20};
    for (float z : stored) acc = accumulateBlocker(acc, z, 15.0f, 1.0f);
    EXPECT_FLOAT_EQ(acc.y, 20.0f);
    EXPECT_FLOAT_EQ(acc.x, 163.0f);
    EXPECT_FLOAT_EQ(averageBlockerDepth(acc), 8.15f);
    EXPECT_NEAR(penumbraWidth(1.0f, 15.0f, averageBlockerDepth(acc)), (15.0 - 8.15) / 8.15, 1e-5);
    EXPECT_NEAR(penumbraWidth(1.0f, 15.0f, averageBlockerDepth(acc)), 0.84, 0.005);  // the paper's rounding
    // Fig. 4: 17 samples summing to 130 -> 7.65 -> 0.96.
    EXPECT_NEAR(penumbraWidth(1.0f, 15.0f, averageBlockerDepth(vec2(130.0f, 17.0f))), 0.96, 0.005);
}

TEST(PenumbraMath, NoBlockerFoundIsLit) {
    vec2 acc(0.0f);
    for (float z : {15.0f, 14.5f, 20.0f, std::numeric_limits<float>::max()}) acc = accumulateBlocker(acc, z, 15.0f, 1.0f);
    EXPECT_EQ(acc.y, 0.0f);
    EXPECT_EQ(averageBlockerDepth(acc), -1.0f);
    EXPECT_EQ(penumbraWidth(1.0f, 15.0f, averageBlockerDepth(acc)), 0.0f);
}

TEST(PenumbraMath, OccluderTouchingTheReceiverGivesAHardEdge) {
    // A blocker at the receiver's own depth is not a blocker (bias); just in front of it, eq. 1
    // gives a vanishing penumbra: the contact shadow is hard.
    EXPECT_EQ(accumulateBlocker(vec2(0.0f), 4.0f, 4.0f, 0.01f).y, 0.0f);
    EXPECT_EQ(penumbraWidth(1.0f, 4.0f, 4.0f), 0.0f);
    EXPECT_NEAR(penumbraWidth(1.0f, 4.0f, 3.999f), 1.0f * 0.001f / 3.999f, 1e-7);
    EXPECT_EQ(penumbraWidth(1.0f, 4.0f, 4.5f), 0.0f);  // a blocker behind (averaging noise): no negative width
}

TEST(PenumbraMath, OccluderAtTheLightStaysFiniteAndKernelsAreCapped) {
    for (float zAvg : {1e-3f, 1e-9f, 0.0f}) {
        float w = penumbraWidth(1.0f, 4.0f, zAvg);
        EXPECT_TRUE(std::isfinite(w)) << zAvg;
        EXPECT_GT(w, 100.0f) << zAvg;  // eq. 1 grows without bound as z_avg -> 0
        EXPECT_EQ(penumbraKernelTexels(w, 4.0f, 1.0f, 1024.0f, 41.0f), 41.0f);
        EXPECT_EQ(penumbraKernelPixels(w, 0.01f, 41.0f), 41.0f);
    }
}

TEST(PenumbraMath, PenumbraWidthFollowsEquationOne) {
    // Parallel planes (square-occluder): light width 1 at z = 0, occluder at 2, floor at 4: the
    // closed form's penumbra is 1 world unit wide (|x| from 0.5 to 1.5).
    EXPECT_FLOAT_EQ(penumbraWidth(1.0f, 4.0f, 2.0f), 1.0f);
    EXPECT_FLOAT_EQ(penumbraWidth(0.5f, 4.0f, 2.0f), 0.5f);  // linear in w_light
    EXPECT_EQ(penumbraWidth(0.0f, 4.0f, 2.0f), 0.0f);        // a point light: hard
    // In texels at the receiver: 1 world / (2 * 4 * tan / size).
    EXPECT_NEAR(penumbraKernelTexels(1.0f, 4.0f, 1.0f, 256.0f, 127.0f), 32.0f, 1e-4);
    EXPECT_EQ(penumbraKernelTexels(1e-6f, 4.0f, 1.0f, 256.0f, 41.0f), 1.0f);  // at least the centre tap
}

TEST(PenumbraMath, BlockerSearchRegionFromLightAndReceiver) {
    // Width at the near plane: w_l (z_r - z_n) / z_r over a texel there (2 z_n tan / size).
    float expected = 1.0f * (4.0f - 1.8f) / 4.0f / (2.0f * 1.8f * 1.0f / 256.0f);
    EXPECT_NEAR(blockerSearchWidthTexels(1.0f, 4.0f, 1.8f, 1.0f, 256.0f, 127.0f), expected, 1e-3);
    EXPECT_EQ(blockerSearchWidthTexels(1.0f, 4.0f, 1.8f, 1.0f, 256.0f, 29.0f), 29.0f);  // capped at n
    EXPECT_EQ(blockerSearchWidthTexels(0.0f, 4.0f, 1.8f, 1.0f, 256.0f, 29.0f), 1.0f);   // point light
    EXPECT_EQ(blockerSearchWidthTexels(1.0f, 1.8f, 1.8f, 1.0f, 256.0f, 29.0f), 1.0f);   // receiver at the near plane
    // Grows with the light and with the receiver's distance.
    EXPECT_LT(blockerSearchWidthTexels(0.2f, 4.0f, 1.8f, 1.0f, 256.0f, 127.0f),
              blockerSearchWidthTexels(0.4f, 4.0f, 1.8f, 1.0f, 256.0f, 127.0f));
    EXPECT_LT(blockerSearchWidthTexels(0.2f, 3.0f, 1.8f, 1.0f, 256.0f, 127.0f),
              blockerSearchWidthTexels(0.2f, 4.0f, 1.8f, 1.0f, 256.0f, 127.0f));
    // Occluder plane at the light (near -> 0): the width is finite and capped.
    EXPECT_EQ(blockerSearchWidthTexels(1.0f, 4.0f, 0.0f, 1.0f, 256.0f, 29.0f), 29.0f);
}

TEST(PenumbraMath, KernelLargerThanTheMapIsClamped) {
    // Documented clamp: 2 sm_size - 1, from which every texel is reachable.
    EXPECT_EQ(maxKernelForMap(1.0f), 1.0f);
    EXPECT_EQ(maxKernelForMap(8.0f), 15.0f);
    EXPECT_EQ(blockerSearchWidthTexels(1.0f, 4.0f, 0.1f, 1.0f, 8.0f, 127.0f), 15.0f);  // 39 unclamped
    EXPECT_EQ(penumbraKernelTexels(100.0f, 4.0f, 1.0f, 8.0f, 127.0f), 15.0f);
    EXPECT_EQ(penumbraKernelTexels(100.0f, 4.0f, 1.0f, 1.0f, 127.0f), 1.0f);
}

TEST(PenumbraMath, ReuseCriteria) {
    // Step 2: |d - d_t| < alpha (strict), alpha 0 reuses nothing, not even the pixel's own row.
    EXPECT_TRUE(reuseBlockerRow(4.0f, 4.05f, 0.1f));
    EXPECT_FALSE(reuseBlockerRow(4.0f, 4.1f, 0.05f));
    EXPECT_FALSE(reuseBlockerRow(4.0f, 4.0f, 0.0f));
    EXPECT_FALSE(reuseBlockerRow(4.0f, -1e30f, 100.0f));  // step 1's "no receiver" marker
    EXPECT_TRUE(reuseBlockerRow(4.0f, 3.6f, 0.5f));
    // Step 3: against the depth of the pixel's tangent plane.
    EXPECT_TRUE(reuseShadowRow(5.02f, 5.0f, 0.1f));
    EXPECT_FALSE(reuseShadowRow(4.5f, 5.0f, 0.1f));
    EXPECT_FALSE(reuseShadowRow(5.0f, 5.0f, 0.0f));
}

TEST(PenumbraMath, TangentPlaneDepthAdjustsForTheNormal) {
    // A floor plane y = -1 seen by a camera at the origin looking down -z: along the view ray
    // through ndc y, the plane's depth is 1 / (-ndc.y tan) (ray (x, y tan, -1) meets y = -1).
    vec3 p(0.0f, -1.0f, -4.0f), n(0.0f, 1.0f, 0.0f);
    float tan = 0.5f;
    for (float ndcY : {-0.8f, -0.5f, -0.1f}) {
        float depth = tangentPlaneDepth(p, n, vec2(0.3f, ndcY), tan, 1.5f);
        EXPECT_NEAR(depth, 1.0f / (-ndcY * tan), 1e-4) << ndcY;
    }
    // Looking above the horizon the plane is behind: no depth.
    EXPECT_EQ(tangentPlaneDepth(p, n, vec2(0.0f, 0.3f), tan, 1.0f), -1.0f);
    // A plane facing the camera has the same depth everywhere.
    EXPECT_NEAR(tangentPlaneDepth(vec3(0, 0, -3), vec3(0, 0, 1), vec2(0.7f, -0.4f), tan, 1.0f), 3.0f, 1e-5);
}

TEST(PenumbraMath, KernelWeights) {
    // Mean: the box covers width texels in total, continuously in the width.
    for (float width : {1.0f, 2.5f, 7.0f, 41.0f}) {
        int r = kernelRadius(width);
        float sum = 0.0f;
        for (int i = -r - 2; i <= r + 2; ++i) {
            float w = kernelWeight(float(i), width, FILTER_MEAN, 0.5f);
            if (std::abs(i) > r) EXPECT_EQ(w, 0.0f) << width << " " << i;  // loops to r miss nothing
            sum += w;
        }
        EXPECT_NEAR(sum, width, 1e-4) << width;
    }
    EXPECT_EQ(kernelRadius(1.0f), 0);
    EXPECT_EQ(kernelRadius(41.0f), 20);
    // Gaussian N(0, 0.5) over the half-width: symmetric, largest at the centre, e^-2 at the edge
    // (where the box covers half of the last tap's cell).
    EXPECT_FLOAT_EQ(kernelWeight(0.0f, 41.0f, FILTER_GAUSSIAN, 0.5f), 1.0f);
    EXPECT_FLOAT_EQ(kernelWeight(5.0f, 41.0f, FILTER_GAUSSIAN, 0.5f), kernelWeight(-5.0f, 41.0f, FILTER_GAUSSIAN, 0.5f));
    EXPECT_NEAR(kernelWeight(20.0f, 40.0f, FILTER_GAUSSIAN, 0.5f), 0.5f * std::exp(-2.0f), 1e-6);
}

TEST(PenumbraMath, PoissonDiskIsInTheUnitDiskAndSpread) {
    const auto& disk = poissonDisk32();
    for (size_t i = 0; i < disk.size(); ++i) {
        EXPECT_LE(glm::length(disk[i]), 1.0f);
        for (size_t k = 0; k < i; ++k) EXPECT_GE(glm::distance(disk[i], disk[k]), 0.25f);
    }
}

// ---- the same GLSL on the GPU ---------------------------------------------------------------------
class PenumbraMathGpu : public testing::GLTest {};

TEST_F(PenumbraMathGpu, MatchesCpuOnAGrid) {
    constexpr int n = 64;
    Texture a(n, n, GL_RGBA32F), b(n, n, GL_RGBA32F);
    Framebuffer fbo({&a, &b}, nullptr);
    ShaderProgram program("common/fullscreen.vert", "tests/penumbra_math.frag");
    program.use();
    fbo.bind(n, n);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    drawFullscreenTriangle();
    auto read = [&](const Texture& t) {
        std::vector<float> v(size_t(n) * n * 4);
        glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(v.size() * 4), v.data());
        return v;
    };
    std::vector<float> ga = read(a), gb = read(b);
    // Same operations; the GPU may fuse multiply-adds and round division and exp its own way: a few
    // ulps relative, and kernel sizes up to 127 -> 1e-4 relative is generous and still catches any
    // change of formula.
    auto near = [](float gpu, float cpu) { return std::abs(gpu - cpu) <= 1e-4f * std::max(1.0f, std::abs(cpu)); };
    int bad = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            size_t i = size_t(y) * n + x;
            // Mirrors shaders/tests/penumbra_math.frag.
            float zr = 0.5f + 0.1f * float(y);
            float zb = 0.05f * float(x) - 0.2f;  // includes "no blocker" (-) and the light (0)
            float lw = 0.02f * float(x % 16);
            vec2 acc = accumulateBlocker(accumulateBlocker(vec2(0.0f), zb, zr, 0.01f), zb + 0.3f, zr, 0.01f);
            float zAvg = averageBlockerDepth(acc);
            float cpuA[4] = {zAvg, penumbraWidth(lw, zr, zAvg),
                             blockerSearchWidthTexels(lw, zr, 0.3f + 0.01f * float(x), 0.8f, 64.0f + float(y), 29.0f),
                             penumbraKernelTexels(penumbraWidth(lw, zr, zAvg), zr, 0.8f, 256.0f, 41.0f)};
            float cpuB[4] = {reuseBlockerRow(zr, zb, 0.02f * float(x % 8)) ? 1.0f : 0.0f,
                             reuseShadowRow(zr, zb, 0.03f * float(y % 8)) ? 1.0f : 0.0f,
                             kernelWeight(float(x % 21 - 10), 0.5f + 0.3f * float(y), y % 2, 0.5f),
                             tangentPlaneDepth(vec3(0.1f, -1.0f, -4.0f), normalize(vec3(0.2f, 1.0f, 0.1f)),
                                               vec2(float(x) / 32.0f - 1.0f, float(y) / 32.0f - 1.0f), 0.4f, 1.3f)};
            for (int k = 0; k < 4; ++k) {
                if (!near(ga[i * 4 + k], cpuA[k]) && bad++ < 10) ADD_FAILURE() << "A" << k << " at " << x << "," << y << ": gpu " << ga[i * 4 + k] << " cpu " << cpuA[k];
                if (!near(gb[i * 4 + k], cpuB[k]) && bad++ < 10) ADD_FAILURE() << "B" << k << " at " << x << "," << y << ": gpu " << gb[i * 4 + k] << " cpu " << cpuB[k];
            }
        }
    EXPECT_EQ(bad, 0);
}

// ---- end to end -----------------------------------------------------------------------------------
struct Frame {
    Image visibility, positions, ids;
};

Frame renderPcss(const std::string& sceneName, const std::string& technique,
                 std::vector<std::pair<std::string, std::string>> sets, std::optional<float> lightSize = {},
                 int size = 128) {
    Scene scene = loadScene(sceneName);
    RenderOptions options;
    options.width = options.height = size;
    options.technique = technique;
    options.sets = std::move(sets);
    options.lightSize = lightSize;
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"visibility", "gbuffer"});
    return {renderer.visibility(), renderer.positions(), renderer.ids()};
}

// RMSE of the floor pixels (id 0) against the closed form of DESIGN.md section 5.
double floorRmseVsClosedForm(const Frame& f, float lightWidth) {
    double sum = 0.0;
    size_t n = 0;
    for (int y = 0; y < f.visibility.height; ++y)
        for (int x = 0; x < f.visibility.width; ++x) {
            if (f.ids.at(x, y) != 0.0f) continue;
            glm::vec3 p(f.positions.at(x, y, 0), 0.0f, f.positions.at(x, y, 2));
            double d = f.visibility.at(x, y) - squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, lightWidth);
            sum += d * d;
            ++n;
        }
    EXPECT_GT(n, 1000u);
    return std::sqrt(sum / double(n));
}

class PcssRender : public testing::GLTest {};

// Light and occluder parallel: PCSS's assumption holds, so eq. 1 is the true penumbra width and a
// box kernel of that width gives the closed form up to texel discretisation. sm_size 256 keeps the
// 1-unit penumbra (32 texels) under the m = 41 cap. Tolerance: the 0.03.
TEST_F(PcssRender, SquareOccluderMatchesClosedForm) {
    Frame f = renderPcss("square-occluder", "pcss", {{"sm_size", "256"}});
    double rmse = floorRmseVsClosedForm(f, 1.0f);
    RecordProperty("rmse", std::to_string(rmse));
    EXPECT_LE(rmse, 0.03);
    // And it is soft: pcf's fixed 5-texel kernel is much further from the closed form.
    Frame pcf = renderPcss("square-occluder", "pcf", {{"sm_size", "256"}});
    EXPECT_GT(floorRmseVsClosedForm(pcf, 1.0f), 2.0 * rmse);
}

// Clamped kernels said (issue 17), both ways. square-occluder's 1-unit penumbra is about 31 texels
// at sm_size 512 (the default) and 63 at 1024: under and over the m = 41 cap. --stats counts the pixels whose
// eq. 1 kernel hit the cap among those where the filter ran; at 1024 it is all of them, and the
// truncated penumbra shows in the closed-form error (measured 0.0062 at 512, 0.045 at 1024 at
// 256 x 256: bounds 0.02 and "more than 3x the unclamped one").
TEST_F(PcssRender, ClampedKernelIsCountedAndCostsAccuracy) {
    struct Run {
        nlohmann::json cap;
        double rmse;
    };
    auto run = [](const char* smSize) {
        Scene scene = loadScene("square-occluder");
        RenderOptions options;
        options.width = options.height = 256;
        options.technique = "pcss";
        options.sets = {{"sm_size", smSize}};
        Renderer renderer(scene, options);
        renderer.renderFrame(0, {"visibility", "gbuffer"});
        nlohmann::json stats = renderer.stats({}, 0);
        EXPECT_EQ(stats["lights"][0]["kernel_caps"].size(), 1u);
        Frame f{renderer.visibility(), renderer.positions(), renderer.ids()};
        return Run{stats["lights"][0]["kernel_caps"][0], floorRmseVsClosedForm(f, 1.0f)};
    };
    const Run fits = run("512"), clamped = run("1024");
    std::printf("pcss closed-form RMSE: sm_size 512 %.4f (clamped %.3f), 1024 %.4f (clamped %.3f)\n", fits.rmse,
                fits.cap["clamped_fraction"].get<double>(), clamped.rmse, clamped.cap["clamped_fraction"].get<double>());
    EXPECT_EQ(fits.cap["parameter"], "filter_kernel");
    EXPECT_EQ(fits.cap["cap"], 41.0);
    EXPECT_GT(fits.cap["pixels"].get<size_t>(), 1000u);
    EXPECT_EQ(fits.cap["clamped_pixels"], 0u);
    EXPECT_LT(fits.cap["largest"].get<double>(), 41.0);
    EXPECT_LE(fits.rmse, 0.02);
    EXPECT_GT(clamped.cap["clamped_fraction"].get<double>(), 0.99);
    EXPECT_EQ(clamped.cap["largest"].get<double>(), 41.0);
    EXPECT_GT(clamped.rmse, 3.0 * fits.rmse);
    // The command line warns at a setting that clamps, naming the parameter to raise; the default
    // (sm_size 512) does not clamp.
    test::Result r = test::run("render --scene square-occluder --technique pcss --set sm_size=1024 --size 64x64 --out " +
                               test::testPath("pcss", "clamp.png"));
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.output.find("filter_kernel clamped the kernel"), std::string::npos) << r.output;
    test::Result quiet = test::run("render --scene square-occluder --technique pcss --size 64x64 --out " +
                                   test::testPath("pcss", "noclamp.png"));
    EXPECT_EQ(quiet.code, 0);
    EXPECT_EQ(quiet.output.find("clamped"), std::string::npos) << quiet.output;
}

// A wrong method fails (issue 17): on overlapping-occluders the penumbra's width varies with the
// occluder's height, so no fixed kernel fits. Penumbra RMSE against `raytraced` (256 rays) at
// 128 x 128, measured: pcf 9, 15, 21, 41 texels 0.244, 0.220, 0.196, 0.129; pcss 0.037; sssm
// 0.080. Bounds: pcss under half the best fixed PCF, sssm under 0.8 of it (a fixed kernel passed
// off as either fails), and each under 1.5x its own measurement.
TEST_F(PcssRender, BeatsEveryFixedKernelOnOverlappingOccluders) {
    const Frame ray = renderPcss("overlapping-occluders", "raytraced", {{"rays", "256"}});
    const std::vector<uint8_t> mask = penumbraMask(ray.visibility);
    double bestPcf = 1e9;
    for (const char* n : {"9", "15", "21", "41"}) {
        const Frame pcf = renderPcss("overlapping-occluders", "pcf", {{"pcf_kernel", n}});
        bestPcf = std::min(bestPcf, computeMetrics(pcf.visibility, ray.visibility, &mask).rmse);
    }
    const double pcss = computeMetrics(renderPcss("overlapping-occluders", "pcss", {}).visibility, ray.visibility, &mask).rmse;
    const double sssm = computeMetrics(renderPcss("overlapping-occluders", "sssm", {}).visibility, ray.visibility, &mask).rmse;
    std::printf("overlapping-occluders penumbra RMSE: best fixed pcf %.4f, pcss %.4f, sssm %.4f\n", bestPcf, pcss, sssm);
    EXPECT_LT(pcss, 0.5 * bestPcf);
    EXPECT_LT(sssm, 0.8 * bestPcf);
    EXPECT_LT(pcss, 1.5 * 0.037);
    EXPECT_LT(sssm, 1.5 * 0.080);
}

// The Poisson pattern (32 taps in a disk) approximates a round light: looser, 0.06.
TEST_F(PcssRender, PoissonPatternIsCloseToClosedForm) {
    Frame f = renderPcss("square-occluder", "pcss", {{"sm_size", "256"}, {"pattern", "poisson"}});
    EXPECT_LE(floorRmseVsClosedForm(f, 1.0f), 0.06);
}

TEST_F(PcssRender, LightSizeZeroIsTheHardShadow) {
    for (const char* technique : {"pcss", "sssm"}) {
        Frame f = renderPcss("square-occluder", technique, {}, 0.0f);
        // The `hard` that replaces it keeps its shadow-map settings (sm_size 512).
        Frame hard = renderPcss("square-occluder", "hard", testing::shadowMapSettingsOf(technique), 0.0f);
        EXPECT_EQ(f.visibility.data, hard.visibility.data) << technique;
        // and that is the closed form's hard shadow except at a few edge pixels
        EXPECT_LE(floorRmseVsClosedForm(f, 0.0f), 0.1) << technique;
    }
}

// A tiny light (no point: the soft passes run) converges to the hard shadow.
TEST_F(PcssRender, TinyLightConvergesToHard) {
    for (const char* technique : {"pcss", "sssm"}) {
        Frame f = renderPcss("square-occluder", technique, {}, 1e-4f);
        Frame hard = renderPcss("square-occluder", "hard", testing::shadowMapSettingsOf(technique));
        size_t differ = 0;
        for (size_t i = 0; i < f.visibility.data.size(); ++i) differ += std::abs(f.visibility.data[i] - hard.visibility.data[i]) > 0.01f;
        EXPECT_LE(double(differ) / double(f.visibility.data.size()), 0.002) << technique;
    }
}

TEST_F(PcssRender, KernelLargerThanTheMapIsClampedAndFinite) {
    for (const char* technique : {"pcss", "sssm"}) {
        Frame f = renderPcss("square-occluder", technique, {{"sm_size", "4"}, {"blocker_kernel", "127"}, {"filter_kernel", "127"}}, {}, 48);
        for (float v : f.visibility.data) {
            ASSERT_TRUE(std::isfinite(v)) << technique;
            ASSERT_GE(v, 0.0f);
            ASSERT_LE(v, 1.0f);
        }
    }
}

// A live change of a parameter that only the later passes read (the pass graph re-runs them alone)
// gives the same picture as a fresh renderer with that value. sssm's step 2 once found step 1's
// stencil marks already advanced by its previous run and left every penumbra hard. Exact equality:
// same passes, same inputs, same GL state.
TEST_F(PcssRender, LiveParameterChangeEqualsAFreshRender) {
    const std::vector<std::tuple<std::string, std::string, std::string>> changes = {
        {"sssm", "alpha", "0.01"}, {"sssm", "beta", "0.5"}, {"sssm", "filter", "mean"},
        {"sssm", "sigma", "1"},    {"sssm", "filter_kernel", "15"}, {"pcss", "filter_kernel", "7"}};
    for (const auto& [technique, key, value] : changes) {
        Scene scene = loadScene("plant");
        RenderOptions options;
        options.width = options.height = 96;
        options.technique = technique;
        Renderer live(scene, options);
        live.renderFrame(0, {"visibility"});
        live.setParam(key, value);
        live.renderFrame(1, {"visibility"});
        options.sets = {{key, value}};
        Renderer fresh(scene, options);
        fresh.renderFrame(0, {"visibility"});
        EXPECT_EQ(live.visibility().data, fresh.visibility().data) << technique << " " << key << "=" << value;
    }
}

// ---- bad values ---------------------------------------------------------------------------------
// The picked pixel's record shows what pcss fetched (the shadow-map view draws it): the blocker
// search's square of 2 kernelRadius(search width) + 1 texels around the receiver's texel and, when
// a blocker was found, the filter kernel's square, both from the pixel's own `blockers` values;
// where no blocker was found, only the search (before: the receiver's texel alone, as for `hard`).
TEST_F(PcssRender, PixelRecordShowsTheSearchAndFilterRegions) {
    Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 96;
    o.technique = "pcss";
    o.sets = {{"sm_size", "256"}};
    Renderer renderer(scene, o);
    renderer.renderFrame(0, renderer.internalRequests(true));
    const Image v = renderer.visibility();
    int penumbra = 0, noBlocker = 0;
    for (int x = 4; x < 96; x += 4) {
        const glm::ivec2 p(x, 60);
        if (renderer.ids().at(p.x, p.y) < 0.0f) continue;
        const std::string dir = std::string(SHADOWLAB_TEST_TMP) + "/pcss-record-" + std::to_string(x);
        std::filesystem::create_directories(dir);
        OutputSet outputs;
        InternalWriter writer(dir, outputs);
        renderer.writeInternals(writer, p);
        outputs.commit();
        std::ifstream in(dir + "/pixel.json");
        const nlohmann::json all = nlohmann::json::parse(in);
        const nlohmann::json& rec = all["lights"][0];
        SCOPED_TRACE("pixel " + std::to_string(x) + ": " + rec.dump());
        ASSERT_TRUE(rec.contains("blocker_search"));
        const glm::ivec2 texel(rec["shadow_map_texel"][0].get<int>(), rec["shadow_map_texel"][1].get<int>());
        auto width = [](const nlohmann::json& r) { return r[2].get<int>() - r[0].get<int>() + 1; };
        const nlohmann::json& search = rec["blocker_search"]["texels"];
        const int rs = shared::kernelRadius(rec["blocker_search"]["width_texels"].get<float>());
        EXPECT_EQ(width(search), 2 * rs + 1);  // the map is 256: nothing clamps at this size
        EXPECT_EQ(search[0].get<int>(), texel.x - rs);
        EXPECT_EQ(search[1].get<int>(), texel.y - rs);
        EXPECT_EQ(rec["texels_read"][0], search);
        if (rec["filter"].is_null()) {
            ++noBlocker;
            EXPECT_EQ(rec["texels_read"].size(), 1u);
            EXPECT_FLOAT_EQ(v.at(p.x, p.y), 1.0f);  // no blocker: lit
            continue;
        }
        ASSERT_EQ(rec["texels_read"].size(), 2u);
        const int rf = shared::kernelRadius(rec["filter"]["kernel_texels"].get<float>());
        EXPECT_EQ(width(rec["filter"]["texels"]), 2 * rf + 1);
        EXPECT_EQ(rec["texels_read"][1], rec["filter"]["texels"]);
        if (v.at(p.x, p.y) > 0.02f && v.at(p.x, p.y) < 0.98f) {
            ++penumbra;
            EXPECT_GT(rf, 1);  // a penumbra pixel filters over more than its own texel
        }
    }
    EXPECT_GE(penumbra, 2);
    EXPECT_GE(noBlocker, 2);
}

TEST(PcssParams, BadValuesAreRefusedNamingTheRule) {
    for (const char* id : {"pcss", "sssm"}) {
        const TechniqueDesc& d = requireTechnique(id, "test");
        ParamValues v(d);
        auto refuse = [&](const std::string& key, const std::string& value, const std::string& words) {
            try {
                v.set(d, key, value, "--set");
                ADD_FAILURE() << id << " accepted " << key << "=" << value;
            } catch (const InputError& e) {
                EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
                EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
            }
        };
        refuse("blocker_kernel", "28", "odd");
        refuse("blocker_kernel", "-3", "");
        refuse("blocker_kernel", "nan", "");
        refuse("filter_kernel", "129", "");
        refuse("filter_kernel", "0", "");
        if (std::string(id) == "sssm") {
            for (const char* key : {"alpha", "beta"}) {
                refuse(key, "-0.1", "");
                refuse(key, "nan", "");
                refuse(key, "inf", "");
                v.set(d, key, "0", "--set");  // 0 is valid: no reuse at all (documented)
            }
            refuse("sigma", "0", "");
            refuse("filter", "box", "gaussian");
        } else {
            refuse("pattern", "hex", "regular");
        }
    }
}

TEST(PcssParams, CliRefusesNegativeAlphaWithExitCode2) {
    auto r = test::run("render --scene square-occluder --technique sssm --size 16x16 --set alpha=-1 --out " +
                       test::testPath("pcss", "x.png"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("alpha"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace shadowlab
