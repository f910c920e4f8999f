// Helpers of the hard-case suite (tests/hard_cases/*.cpp): scenes written to the test folder,
// one render with every buffer, the invariants every case checks, square-occluder at any scale and
// its closed form, and floor comparisons.
#pragma once
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "graph/renderer.h"
#include "scene/scene.h"
#include "shared/shared.h"

namespace shadowlab::hardcase {

using Sets = std::vector<std::pair<std::string, std::string>>;
using namespace shared;

// Each test writes into its own folder: ctest runs tests in parallel processes, and two tests
// writing the same name ("so.json") would read each other's half-written file.
inline std::string writeScene(const std::string& folder, const std::string& name, const std::string& text) {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::filesystem::path dir = std::filesystem::path(SHADOWLAB_TEST_TMP) / folder;
    if (test) dir /= std::string(test->test_suite_name()) + "." + test->name();
    std::filesystem::create_directories(dir);
    const std::string path = (dir / (name + ".json")).string();
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    return path;
}

struct Render {
    Image visibility, positions, ids, image;
    Image normals;  // the G-buffer's geometric normal (the tangent plane visibility uses), 3 channels
    double seconds = 0.0;  // to render, renderer set-up included
};

inline Render render(const Scene& scene, const std::string& technique, const Sets& sets = {}, std::optional<float> lightSize = {},
              int size = 48) {
    RenderOptions options;
    options.width = options.height = size;
    options.technique = technique;
    options.sets = sets;
    options.lightSize = lightSize;
    const auto t0 = std::chrono::steady_clock::now();
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"visibility", "gbuffer", "image"});
    Render r{renderer.visibility(), renderer.positions(), renderer.ids(), renderer.image(), renderer.normals()};
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

// The invariants every case checks: v in [0, 1]; visibility and image finite; positions finite on
// geometry (background positions are NaN by definition, ids -1).
inline void expectInvariants(const Render& r, const std::string& what) {
    size_t bad = 0;
    for (float v : r.visibility.data) bad += !(v >= 0.0f && v <= 1.0f);
    EXPECT_EQ(bad, 0u) << what << ": visibility outside [0, 1] or NaN";
    bad = 0;
    for (float c : r.image.data) bad += !std::isfinite(c);
    EXPECT_EQ(bad, 0u) << what << ": image has NaN/Inf";
    bad = 0;
    for (size_t i = 0; i < r.ids.data.size(); ++i) {
        if (r.ids.data[i] < 0.0f) continue;
        for (int k = 0; k < 3; ++k) bad += !std::isfinite(r.positions.data[i * 3 + k]);
    }
    EXPECT_EQ(bad, 0u) << what << ": positions of geometry pixels have NaN/Inf";
}

// square-occluder scaled by s about the origin (DESIGN.md section 5 at s = 1). plateHalf and
// plateY let cases move and grow the plate; lightWidth 0 writes a point light.
inline std::string squareOccluder(double s, double plateHalf = 0.5, double plateY = 2.0, double lightWidth = 1.0,
                           double nearPlane = 0.1, double farPlane = 50.0, const char* extraObjects = "") {
    char buffer[4096];
    std::snprintf(buffer, sizeof buffer, R"({
      "camera": {"position": [0, %.9g, %.9g], "target": [0, 0, %.9g], "fov_deg": 40, "near": %.9g, "far": %.9g},
      "lights": [{"type": "square", "position": [0, %.9g, 0], "direction": [0, -1, 0], "up": [0, 0, -1], "width": %.9g}],
      "objects": [
        {"name": "floor", "id": 0, "type": "quad", "size": [%.9g, %.9g], "casts_shadows": false},
        {"name": "plate", "id": 1, "type": "box", "size": [%.9g, %.9g, %.9g], "transform": {"translate": [0, %.9g, 0]}}%s
      ]})",
                  5.5 * s, 6.5 * s, 0.3 * s, nearPlane * s, farPlane * s, 4 * s, lightWidth * s, 8 * s, 8 * s,
                  2 * plateHalf * s, 0.001 * s, 2 * plateHalf * s, plateY * s, extraObjects);
    return buffer;
}

// RMSE of the floor's visibility against the closed form (positions divided by the scale s).
inline double closedFormRmse(const Render& r, double s, float plateHalf = 0.5f, float plateY = 2.0f, float lightWidth = 1.0f,
                      size_t* count = nullptr) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < r.ids.data.size(); ++i) {
        if (r.ids.data[i] != 0.0f) continue;
        const glm::vec3 p(float(r.positions.data[i * 3] / s), 0.0f, float(r.positions.data[i * 3 + 2] / s));
        const double d = r.visibility.data[i] - squareOccluderVisibility(p, plateHalf, plateY, 4.0f, lightWidth);
        sum += d * d;
        ++n;
    }
    if (count) *count = n;
    return n ? std::sqrt(sum / double(n)) : INFINITY;
}

// Mean |a - b| over floor pixels (id 0 in `ids`).
inline double floorMeanAbs(const Render& a, const Render& b) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < a.ids.data.size(); ++i) {
        if (a.ids.data[i] != 0.0f) continue;
        sum += std::abs(a.visibility.data[i] - b.visibility.data[i]);
        ++n;
    }
    return n ? sum / double(n) : INFINITY;
}

// Fraction of floor pixels where a and b agree within tol.
inline double floorAgreement(const Render& a, const Render& b, float tol) {
    size_t same = 0, n = 0;
    for (size_t i = 0; i < a.ids.data.size(); ++i) {
        if (a.ids.data[i] != 0.0f || b.ids.data[i] != 0.0f) continue;
        ++n;
        same += std::abs(a.visibility.data[i] - b.visibility.data[i]) <= tol;
    }
    return n ? double(same) / double(n) : 0.0;
}

}  // namespace shadowlab::hardcase
