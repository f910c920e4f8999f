// GPU/CPU agreement of the shared math, every function (issue 11 item 2; label `hard-case`: this file
// joins shadowlab_hard_cases by the tests/hard_cases/*.cpp glob). HardCaseGpu.SharedMathAgreesWithCpu
// (test_hard_cases.cpp) and the shared_math / penumbra_math / backprojection_math shaders compare
// most functions; shaders/tests/shared_every_function.comp runs the rest over a grid of inputs,
// hard cases included, and this file compares each result with the same source run in C++
// (shaders/shared/shared.h). A guard fails when a shared function is compared by no test shader
// (shaders/tests and its subfolders).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "gl/util.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

namespace fs = std::filesystem;
using namespace shared;

struct Case {
    glm::vec4 segment, kernel, depths, sizes, world, normal;
    glm::ivec4 ints;
    glm::uvec4 bits;
};
struct Result {
    glm::vec4 light;
    glm::ivec4 range0, rangeL, levels;
    glm::vec4 region, ray, clip, clipLight, contour;
    glm::ivec4 tests;
    glm::vec4 receiver, samplePos, plane;
};

// Picks element (i * stride + offset) % size of a list: every list is walked, and combinations
// vary because the strides are coprime with the sizes.
template <typename T, size_t N>
T pick(const T (&list)[N], size_t i, size_t stride, size_t offset = 0) {
    return list[(i * stride + offset) % N];
}

std::vector<Case> cases() {
    // Light-coordinate points: the square's border (+-1), its corners, the centre, just inside and
    // outside, far outside; pairs of them give segments on the border, through the centre, of zero
    // length (same point twice) and outside the light.
    const glm::vec2 points[] = {{0, 0},  {1, 0},       {1, 1},       {-1, -1}, {1, -0.5f}, {1, 0.5f}, {-0.5f, -0.5f},
                                {0.5f, 0.5f}, {0.999999f, 0}, {1.000001f, 0}, {-3, 2},  {0.3f, -0.7f}, {0, -1}, {2.5f, 2.5f}};
    const float kernels[] = {0.0f, 1e-3f, 1.5f, 2.0f, 2.0001f, 7.9f, 64.0f, 1e6f};
    const float smSizes[] = {1.0f, 2.0f, 7.0f, 256.0f, 1024.0f};
    const float tans[] = {0.1f, 1.0201f, 5.67f};
    const float ts[] = {-1.0f, 0.0f, 0.3f, 1.0f};
    // (zSample, zReceiver, zPlane, bias): equal depths, a sample exactly at the receiver minus the
    // bias, on the receiver's plane, far apart, near/far 1e5.
    const glm::vec4 depths[] = {{1, 2, 2, 0.01f}, {2, 2, 2, 0}, {1.99f, 2, 1.995f, 0.01f}, {0.5f, 3, 0.5f, 0},
                                {1e-6f, 1e5f, 1e4f, 1e-3f}, {1.9f, 2, 5, 0.1f}, {3, 2, 1, 0.01f}};
    const float penumbras[] = {0.0f, 1e-3f, 0.5f, 1e6f};
    const float perPixel[] = {0.0f, 1e-4f, 0.01f, 2.0f};
    const float widths[] = {0.0f, 1.0f, 1.5f, 2.0f, 41.0f, 1e4f};
    const float lightSizes[] = {0.0f, 1.0f, 2.5f};
    const glm::vec3 receivers[] = {{0, 0, 0}, {1, 0, 0}, {0.3f, 1.2f, -0.7f}, {5, 0, 5}, {0, 3.9999f, 0}, {-2, 0.5f, 1}};
    const float slabP[] = {-1.0f, 1.0f, 0.3f, 2.0f, -1.000001f};
    const glm::vec3 normals[] = {{0, 1, 0}, {1, 0, 0}, {0, -1, 0}, glm::normalize(glm::vec3(0.3f, 1, 0.2f)),
                                 glm::normalize(glm::vec3(0, 1e-4f, 1))};
    const float slabD[] = {0.0f, 1.0f, -2.0f, 1e-7f};
    const int shapes[] = {BP_LIGHT_SQUARE, BP_LIGHT_DISK};
    const int masks[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14};
    std::vector<Case> out;
    for (size_t i = 0; i < 2048; ++i) {
        Case c;
        const glm::vec2 a = pick(points, i, 1), b = pick(points, i, 3);
        c.segment = glm::vec4(a, b);
        c.kernel = glm::vec4(pick(kernels, i, 3), pick(smSizes, i, 7), pick(tans, i, 2, 1), pick(ts, i, 3, 2));
        // Texel coordinates too: a scaled to the map, so kernels land on its border and corners.
        if (i % 3 == 0) c.segment = glm::vec4((a * 0.5f + 0.5f) * c.kernel.y, b);
        c.depths = pick(depths, i, 3);
        c.sizes = glm::vec4(pick(penumbras, i, 3), pick(perPixel, i, 5), pick(widths, i, 1), pick(lightSizes, i, 2));
        c.world = glm::vec4(pick(receivers, i, 5), pick(slabP, i, 2));
        c.normal = glm::vec4(pick(normals, i, 3), pick(slabD, i, 3, 1));
        const int mask = pick(masks, i, 3);
        c.ints = glm::ivec4(pick(shapes, i, 1), int(i % 11), mask, int((i / 7) % 2) < contourRule(mask).x ? int((i / 7) % 2) : 0);
        c.bits = glm::uvec4(uint(i) * 2654435761u, uint(i % 4), uint((i / 4) % 4), uint((i / 16) % 2));
        out.push_back(c);
    }
    return out;
}

class HardCaseGpuEvery : public testing::GLTest {};

// Tolerances, by kind of result:
//  - integer results (texel ranges, HSM levels and sizes, contour holders, kernel radius) and
//    results of comparisons and exact operations (light area and width, hash to unit, the depth
//    tests, the contour's degenerate test and sample positions, maxKernelForMap): exact. The one
//    transcendental, hsmRefinementLevel's floor(log2(w)), may differ only within 1e-5 of a power of
//    two; bpSampleOccludes and bpClassify only where the CPU's own margin to the threshold is
//    under 1e-4 relative (the receiver comes from 4x4 matrix products, which the GPU may fuse).
//  - float results built from a few operations (clipping parameters, texel rays, border positions,
//    contour crossings, sample positions, kernel pixels, region texels): 1e-5 relative to
//    max(1, |value|), i.e. a few ulps at 1; the border position also where it wraps from 8 to 0.
//  - receiver-plane and inverse-depth results (divisions by small dot products): 1e-4 relative.
TEST_F(HardCaseGpuEvery, EveryOtherSharedFunctionAgreesWithCpu) {
    const std::vector<Case> input = cases();
    Buffer in(input.size() * sizeof(Case), input.data());
    Buffer out(input.size() * sizeof(Result));
    const glm::vec3 lightPosition(0.0f, 4.0f, 0.0f);
    const glm::mat4 view = glm::lookAt(lightPosition, glm::vec3(0.0f), glm::vec3(0, 0, -1));
    const glm::mat4 clip = glm::perspective(glm::radians(90.0f), 1.0f, 1e-3f, 1e2f);
    const ShaderProgram& program = programCache().compute("tests/shared_every_function.comp");
    program.set("lightViewFromWorld", view);
    program.set("lightClipFromView", clip);
    program.set("lightPosition", lightPosition);
    program.set("count", unsigned(input.size()));
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.dispatch(GLuint((input.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const std::vector<Result> gpu = out.read<Result>();
    ASSERT_EQ(gpu.size(), input.size());

    auto near = [](float g, float c, float rel) {
        if (std::isnan(c) || std::isnan(g)) return std::isnan(c) && std::isnan(g);
        if (std::isinf(c) || std::isinf(g)) return g == c;
        return std::abs(g - c) <= rel * std::max(1.0f, std::abs(c));
    };
    size_t checked = 0, nearThreshold = 0, degenerate = 0, clippedEmpty = 0;
    for (size_t i = 0; i < input.size(); ++i) {
        const Case& c = input[i];
        const Result& g = gpu[i];
        SCOPED_TRACE("case " + std::to_string(i));
        const int shape = c.ints.x, level = c.ints.y, mask = c.ints.z, which = c.ints.w;
        const int smSize = int(c.kernel.y);
        const glm::vec2 a(c.segment.x, c.segment.y), b(c.segment.z, c.segment.w);
        // Light and hash: exact.
        EXPECT_EQ(g.light.x, bpLightArea(shape));
        EXPECT_EQ(g.light.y, bpLightWidth(shape, c.sizes.w));
        EXPECT_EQ(g.light.z, bpVisibility(c.segment.x + 2.0f, shape));
        EXPECT_EQ(g.light.w, hashToUnit(c.bits.x));
        // Kernel ranges and HSM levels: exact (integer arithmetic on exactly rounded floats).
        const glm::ivec4 range0 = kernelTexelRange(a, c.kernel.x, smSize);
        EXPECT_EQ(g.range0, range0);
        const int levelSize = hsmLevelSize(level, smSize);
        const glm::ivec4 rangeL = levelTexelRange(range0, level, levelSize);
        EXPECT_EQ(g.rangeL, rangeL);
        const float lg = c.kernel.x > 0.0f ? std::log2(c.kernel.x) : 0.0f;
        if (std::abs(lg - std::round(lg)) > 1e-5f) EXPECT_EQ(g.levels.x, hsmRefinementLevel(c.kernel.x, 9));
        EXPECT_EQ(g.levels.y, levelSize);
        const glm::ivec2 holders = contourEdgeHolders(mask, which);
        EXPECT_EQ(g.levels.z, holders.x);
        EXPECT_EQ(g.levels.w, holders.y);
        const glm::vec4 region = levelRegionTexels(rangeL, level, levelSize, smSize);
        for (int k = 0; k < 4; ++k) EXPECT_EQ(g.region[k], region[k]);
        // Rays, border positions, clipping: a few ulps.
        const glm::vec3 ray = texelRay(a, c.kernel.y, c.kernel.z);
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(g.ray[k], ray[k], 1e-5f)) << g.ray[k] << " vs " << ray[k];
        const float border = squareBorderPosition(a);
        EXPECT_TRUE(near(g.ray.w, border, 1e-5f) || near(std::abs(g.ray.w - border), 8.0f, 1e-5f)) << g.ray.w << " vs " << border;
        const glm::vec2 slab = clipSlab(glm::vec2(-0.5f, 1.5f), c.world.w, c.normal.w);
        const glm::vec2 square = clipSegmentToSquare(a, b);
        const glm::vec2 light = clipSegmentToLight(shape, a, b);
        for (int k = 0; k < 2; ++k) {
            EXPECT_TRUE(near(g.clip[k], slab[k], 1e-5f)) << g.clip[k] << " vs " << slab[k];
            EXPECT_TRUE(near(g.clip[2 + k], square[k], 1e-5f)) << g.clip[2 + k] << " vs " << square[k];
            EXPECT_TRUE(near(g.clipLight[k], light[k], 1e-5f)) << g.clipLight[k] << " vs " << light[k];
        }
        clippedEmpty += light.x > light.y;
        degenerate += a == b;
        const glm::vec2 sampleK = contourSamplePosition(int(c.bits.y));
        EXPECT_EQ(g.clipLight.z, sampleK.x);
        EXPECT_EQ(g.clipLight.w, sampleK.y);
        const int side = int(c.bits.z), occluder = c.bits.w == 0u ? side : (side + 1) % 4;
        const glm::vec2 crossing = contourCrossing(side, occluder, c.kernel.w);
        EXPECT_TRUE(near(g.contour.x, crossing.x, 1e-6f) && near(g.contour.y, crossing.y, 1e-6f));
        EXPECT_EQ(g.contour.z, maxKernelForMap(c.kernel.y));
        EXPECT_TRUE(near(g.contour.w, penumbraKernelPixels(c.sizes.x, c.sizes.y, maxKernelForMap(c.kernel.y)), 1e-5f));
        // The receiver's tests.
        const glm::vec3 worldPos(c.world), worldNormal(c.normal);
        const BpReceiver rec = bpReceiver(view, clip, worldPos, worldNormal, lightPosition, c.kernel.z, c.kernel.y, 1.0f, 2.0f);
        EXPECT_TRUE(near(g.samplePos.w, rec.bias, 1e-4f)) << g.samplePos.w << " vs " << rec.bias;
        EXPECT_EQ(g.tests.x, sampleOccludes(c.depths.x, c.depths.y, c.depths.z, c.depths.w) ? 1 : 0);
        EXPECT_EQ(g.tests.y, contourEdgeDegenerate(mask, c.kernel.w, which) ? 1 : 0);
        EXPECT_EQ(g.tests.w, kernelRadius(c.sizes.z));
        const glm::vec2 texelCentre(region.x + 0.5f, region.y + 0.5f);
        const float zPlane = receiverPlaneDepth(rec.normal, rec.position, texelCentre, c.kernel.y, c.kernel.z);
        const float planeMin = regionPlaneDepthMin(rec, region, c.kernel.y, c.kernel.z);
        auto margin = [](float x, float threshold) { return std::abs(x - threshold) <= 1e-4f * std::max(1.0f, std::abs(threshold)); };
        const bool occludesClose = margin(c.depths.x, rec.position.z - rec.bias) || margin(std::abs(c.depths.x - zPlane), rec.bias);
        if (!occludesClose) EXPECT_EQ(g.tests.z, bpSampleOccludes(rec, texelCentre, c.depths.x, c.kernel.y, c.kernel.z) ? 1 : 0);
        EXPECT_TRUE(near(g.receiver.x, planeMin, 1e-4f)) << g.receiver.x << " vs " << planeMin;
        const glm::vec2 bounds0(c.depths.x, c.depths.y), bounds1(c.depths.x * 0.5f, c.depths.x * 0.9f);
        const float threshold = std::min(rec.position.z, planeMin) - rec.bias;
        const bool classifyClose = margin(bounds0.x, rec.position.z - rec.bias) || margin(bounds0.y, threshold) ||
                                   margin(bounds1.x, rec.position.z - rec.bias) || margin(bounds1.y, threshold);
        if (classifyClose) ++nearThreshold;
        else EXPECT_EQ(g.receiver.y, bpClassify(rec, bounds0, planeMin) + 4.0f * bpClassify(rec, bounds1, planeMin));
        EXPECT_EQ(g.receiver.z, shadowDepthTest(c.depths.y, c.depths.x, c.depths.w));
        const glm::vec3 s = lightSamplePosition(lightPosition, glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), shape, c.sizes.w,
                                                glm::fract(b));
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(g.samplePos[k], s[k], 1e-5f)) << g.samplePos[k] << " vs " << s[k];
        const glm::vec3 plane = planeInverseDepth(worldPos, worldNormal, a, c.kernel.z, 1.5f);
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(g.plane[k], plane[k], 1e-4f)) << g.plane[k] << " vs " << plane[k];
        ++checked;
    }
    EXPECT_EQ(checked, 2048u);
    std::printf("%zu cases: %zu zero-length segments, %zu segments outside the light, %zu classifications within 1e-4 of "
                "their threshold (not compared)\n",
                checked, degenerate, clippedEmpty, nearThreshold);
    // The grid does reach its hard cases: zero-length segments, segments entirely outside the
    // light, and classifications decided by less than the tolerance are all present but rare.
    EXPECT_GT(degenerate, 50u);
    EXPECT_GT(clippedEmpty, 50u);
    EXPECT_LT(nearThreshold, 200u);
}

// Every SHARED_FN of shaders/shared/*.glsl is called (outside comments) by at least one test shader
// in shaders/tests/, so a new shared function without a GPU comparison fails here.
TEST(HardCaseGpuCoverage, EverySharedFunctionIsComparedOnTheGpu) {
    const fs::path root = fs::path(projectRoot()) / "shaders";
    auto withoutComments = [](const fs::path& p) {
        std::ifstream in(p);
        std::stringstream text;
        std::string line;
        while (std::getline(in, line)) text << line.substr(0, line.find("//")) << "\n";
        return text.str();
    };
    std::string tests;
    for (const auto& e : fs::recursive_directory_iterator(root / "tests"))
        if (e.is_regular_file()) tests += withoutComments(e.path());
    const std::regex declaration(R"(SHARED_FN\s+[A-Za-z0-9_]+\s+([A-Za-z0-9_]+)\s*\()");
    size_t functions = 0;
    std::vector<std::string> missing;
    for (const auto& e : fs::directory_iterator(root / "shared")) {
        if (e.path().extension() != ".glsl") continue;
        const std::string text = withoutComments(e.path());
        for (std::sregex_iterator it(text.begin(), text.end(), declaration), end; it != end; ++it) {
            const std::string name = (*it)[1];
            ++functions;
            if (!std::regex_search(tests, std::regex("\\b" + name + "\\s*\\("))) missing.push_back(e.path().filename().string() + ": " + name);
        }
    }
    EXPECT_GT(functions, 60u);
    std::string list;
    for (const std::string& m : missing) list += "\n  " + m;
    EXPECT_TRUE(missing.empty()) << "shared functions no test shader compares:" << list;
}

}  // namespace
}  // namespace shadowlab
