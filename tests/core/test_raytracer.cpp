// The `raytraced` reference against the closed-form square-occluder visibility (DESIGN.md
// section 5), on a hand-built scene so the test depends on neither the scene loader nor GL.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>

#include "shared/shared.h"
#include "visibility/raytracer.h"

using namespace shadowlab;

namespace {

constexpr int kGrid = 64;  // receiver points per side over the floor region [-2, 2]^2

Object quad(const std::string& name, int id) {
    Object floor;
    floor.name = name;
    floor.id = id;
    floor.mesh.positions = {{-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4}};
    floor.mesh.normals.assign(4, glm::vec3(0, 1, 0));
    floor.mesh.indices = {0, 2, 1, 0, 3, 2};
    return floor;
}

// Closed box of the given size centred at `centre`: 8 corners, 12 triangles.
Object box(const std::string& name, int id, glm::vec3 centre, glm::vec3 size) {
    Object object;
    object.name = name;
    object.id = id;
    for (int i = 0; i < 8; ++i) {
        glm::vec3 corner((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f);
        object.mesh.positions.push_back(centre + corner * size);
        object.mesh.normals.push_back(glm::normalize(corner));
    }
    // Faces as quads of corner indices (bit 0 = x, bit 1 = y, bit 2 = z).
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        object.mesh.indices.insert(object.mesh.indices.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
    }
    return object;
}

// DESIGN.md section 5, `square-occluder`.
Scene squareOccluderScene() {
    Scene scene;
    scene.name = "square-occluder (test)";
    scene.objects.push_back(quad("floor", 0));
    scene.objects.push_back(box("occluder", 1, glm::vec3(0, 2, 0), glm::vec3(1, 0.001f, 1)));
    Light light;
    light.name = "square";
    light.shape = LightShape::Square;
    light.position = glm::vec3(0, 4, 0);
    light.direction = glm::vec3(0, -1, 0);
    light.up = glm::vec3(0, 0, -1);
    light.size = 1.0f;
    scene.lights.push_back(light);
    return scene;
}

float gridCoordinate(int i) { return -2.0f + 4.0f * (float(i) + 0.5f) / float(kGrid); }

// A synthetic G-buffer: floor points over [-2,2]^2 (row y is z, column x is x), normal +y.
void floorGBuffer(Image& positions, Image& normals) {
    positions = Image(kGrid, kGrid, 3);
    normals = Image(kGrid, kGrid, 3);
    for (int y = 0; y < kGrid; ++y) {
        for (int x = 0; x < kGrid; ++x) {
            positions.at(x, y, 0) = gridCoordinate(x);
            positions.at(x, y, 1) = 0.0f;
            positions.at(x, y, 2) = gridCoordinate(y);
            normals.at(x, y, 1) = 1.0f;
        }
    }
}

float closedForm(const Image& positions, int x, int y, float lightWidth) {
    glm::vec3 p(positions.at(x, y, 0), positions.at(x, y, 1), positions.at(x, y, 2));
    return shared::squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, lightWidth);
}

}  // namespace

TEST(RayTracer, CountsTheCastersTriangles) {
    Scene scene = squareOccluderScene();
    EXPECT_EQ(RayTracer(scene, 0.0).triangleCount(), 14u);
    scene.objects[0].castsShadows = false;
    EXPECT_EQ(RayTracer(scene, 0.0).triangleCount(), 12u);
}

TEST(RayTracer, SoftShadowMatchesTheClosedForm) {
    Scene scene = squareOccluderScene();
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    const int rays = 1024;
    auto start = std::chrono::steady_clock::now();
    Image v = tracer.visibility(positions, normals, scene.lights[0], rays);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "[ raytraced ] " << kGrid << "x" << kGrid << " x " << rays << " rays in " << seconds << " s = "
              << double(kGrid) * kGrid * rays / seconds / 1e6 << " Mrays/s\n";

    double sumSquared = 0.0;
    double maxAbs = 0.0;
    for (int y = 0; y < kGrid; ++y) {
        for (int x = 0; x < kGrid; ++x) {
            double e = double(v.at(x, y)) - closedForm(positions, x, y, 1.0f);
            sumSquared += e * e;
            maxAbs = std::max(maxAbs, std::abs(e));
        }
    }
    double rmse = std::sqrt(sumSquared / (kGrid * kGrid));
    // Tolerance: 1024 stratified samples (32 x 32 jittered cells) are exact in every cell that an
    // occluder edge does not cross. The plate's edges are parallel to the strata, so at most one
    // column and one row of 32 cells are crossed, each sample there off by at most its cell's area
    // with variance <= 1/4 (1/1024)^2: a per-pixel standard deviation <= sqrt(64 / 4) / 1024 = 0.004
    // in the penumbra and exactly 0 in the umbra and the lit region (measured: RMSE 0.00035, max
    // 0.003). The 0.001-thick box differs from the ideal plate by under 0.1%. So 0.01 is loose for
    // noise but still catches real errors: a light 10% too wide alone gives RMSE 0.018.
    std::cout << "[ raytraced ] RMSE " << rmse << ", max abs error " << maxAbs << " against the closed form\n";
    EXPECT_LE(rmse, 0.01) << "max abs error " << maxAbs;
    EXPECT_LE(maxAbs, 0.05);
}

TEST(RayTracer, PointLightGivesTheHardShadow) {
    Scene scene = squareOccluderScene();
    Light point = scene.lights[0];
    point.shape = LightShape::Point;
    point.size = 0.0f;
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    // A point light casts one ray whatever `rays` says.
    Image v1 = tracer.visibility(positions, normals, point, 1);
    Image v16 = tracer.visibility(positions, normals, point, 16);
    EXPECT_EQ(v1.data, v16.data);
    int compared = 0;
    for (int y = 0; y < kGrid; ++y) {
        for (int x = 0; x < kGrid; ++x) {
            float px = positions.at(x, y, 0);
            float pz = positions.at(x, y, 2);
            // The hard shadow is the floor square [-1,1]^2; skip points on its border.
            if (std::abs(std::abs(px) - 1.0f) < 1e-3f || std::abs(std::abs(pz) - 1.0f) < 1e-3f) continue;
            EXPECT_EQ(v1.at(x, y), closedForm(positions, x, y, 0.0f)) << "at (" << px << ", " << pz << ")";
            ++compared;
        }
    }
    EXPECT_GT(compared, kGrid * kGrid / 2);
}

TEST(RayTracer, VisibilityInRangeBackgroundLitAndDeterministic) {
    Scene scene = squareOccluderScene();
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int x = 0; x < kGrid; ++x) {
        for (int c = 0; c < 3; ++c) positions.at(x, 5, c) = nan;  // a background row
    }
    positions.at(30, 30, 0) = nan;  // one background pixel under the umbra
    normals.at(31, 31, 1) = nan;    // a pixel without a normal still gets an answer

    size_t lastDone = 0, lastTotal = 0, calls = 0;
    Image a = tracer.visibility(positions, normals, scene.lights[0], 64, [&](size_t done, size_t total) {
        EXPECT_GE(done, lastDone);
        lastDone = done;
        lastTotal = total;
        ++calls;
    });
    EXPECT_GE(calls, 1u);
    EXPECT_EQ(lastDone, size_t(kGrid) * kGrid);
    EXPECT_EQ(lastTotal, size_t(kGrid) * kGrid);
    Image b = tracer.visibility(positions, normals, scene.lights[0], 64);
    ASSERT_EQ(a.width, kGrid);
    ASSERT_EQ(a.height, kGrid);
    ASSERT_EQ(a.channels, 1);
    EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
    for (float v : a.data) {
        EXPECT_TRUE(v >= 0.0f && v <= 1.0f) << v;
    }
    for (int x = 0; x < kGrid; ++x) EXPECT_EQ(a.at(x, 5), 1.0f);
    EXPECT_EQ(a.at(30, 30), 1.0f);
    EXPECT_EQ(a.at(31, 31), 0.0f);  // umbra
    EXPECT_EQ(a.at(0, 0), 1.0f);    // lit corner
}

// Each pixel's samples depend only on the pixel index, so the thread count cannot change a bit.
TEST(RayTracer, BitIdenticalForEveryThreadCount) {
    Scene scene = squareOccluderScene();
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    Image reference = tracer.visibility(positions, normals, scene.lights[0], 32);
    for (unsigned threads : {1u, 3u, 7u, 200u}) {
        tracer.setThreadCount(threads);
        Image v = tracer.visibility(positions, normals, scene.lights[0], 32);
        EXPECT_EQ(std::memcmp(v.data.data(), reference.data.data(), v.data.size() * sizeof(float)), 0)
            << threads << " threads";
    }
}

TEST(RayTracer, DiskAndSphereLightsStayInRange) {
    Scene scene = squareOccluderScene();
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    for (LightShape shape : {LightShape::Disk, LightShape::Sphere}) {
        Light light = scene.lights[0];
        light.shape = shape;
        light.size = 0.5f;
        Image v = tracer.visibility(positions, normals, light, 64);
        for (float value : v.data) EXPECT_TRUE(value >= 0.0f && value <= 1.0f);
        EXPECT_EQ(v.at(kGrid / 2, kGrid / 2), 0.0f);  // under the plate's centre: umbra
        EXPECT_EQ(v.at(0, 0), 1.0f);
    }
}

TEST(RayTracer, EmptySceneIsLit) {
    Scene scene = squareOccluderScene();
    scene.objects.clear();
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    Image v = tracer.visibility(positions, normals, scene.lights[0], 4);
    for (float value : v.data) EXPECT_EQ(value, 1.0f);
}

// The window's progressive ray tracer: batches of samples taken in spreadSampleOrder, added to
// SampleSums, give visibility()'s result once they cover all M (the same rays and weights; only
// the order of the doubles' additions differs: at most a float ulp), and every partial estimate is
// a visibility. The spread order is a permutation of the M strata.
TEST(RayTracer, BatchesOfSpreadSamplesSumToTheWholeTrace) {
    for (uint32_t n : {1u, 2u, 16u, 37u, 256u}) {
        std::vector<bool> seen(n, false);
        for (uint32_t k = 0; k < n; ++k) seen[spreadSampleOrder(k, n)] = true;
        EXPECT_EQ(std::count(seen.begin(), seen.end(), true), int(n)) << "M = " << n;
    }
    Scene scene = squareOccluderScene();
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    const int rays = 37;  // not a square: the strata's last row is partial
    const Image whole = tracer.visibility(positions, normals, scene.lights[0], rays);
    SampleSums sums;
    sums.reset(kGrid, kGrid, rays);
    double firstError = 0.0;
    uint32_t first = 0;
    for (uint32_t count : {1u, 3u, 7u, 100u}) {
        tracer.traceSamples(positions, normals, scene.lights[0], rays, first, count, sums, true);
        first = std::min<uint32_t>(rays, first + count);
        EXPECT_EQ(sums.traced, first);
        Image partial = sums.image();
        double error = 0.0;
        for (size_t i = 0; i < partial.data.size(); ++i) {
            ASSERT_TRUE(partial.data[i] >= 0.0f && partial.data[i] <= 1.0f);
            error += std::abs(partial.data[i] - whole.data[i]);
        }
        if (first == 1) firstError = error;
        if (first == uint32_t(rays)) EXPECT_LT(error, firstError);  // the estimate converged
    }
    ASSERT_TRUE(sums.complete());
    const Image done = sums.image();
    double maxDiff = 0.0;
    size_t penumbra = 0;
    for (size_t i = 0; i < done.data.size(); ++i) {
        maxDiff = std::max(maxDiff, double(std::abs(done.data[i] - whole.data[i])));
        if (whole.data[i] > 0.01f && whole.data[i] < 0.99f) ++penumbra;
    }
    EXPECT_LT(maxDiff, 1e-6);  // 37 weights summed in two orders in double, then rounded to float
    EXPECT_GT(penumbra, 200u);  // a real penumbra, not a trivially equal pair
    // Umbra and lit pixels are exact whatever the order: every sample agrees.
    EXPECT_EQ(done.at(kGrid / 2, kGrid / 2), 0.0f);
    EXPECT_EQ(done.at(0, 0), 1.0f);
}

// A cancelled batch leaves the sums as they were said to be: `traced` does not move, so the next
// batch is refused rather than summing a half-traced one.
TEST(RayTracer, ACancelledBatchDoesNotCount) {
    Scene scene = squareOccluderScene();
    RayTracer tracer(scene, 0.0);
    Image positions, normals;
    floorGBuffer(positions, normals);
    SampleSums sums;
    sums.reset(kGrid, kGrid, 16);
    std::atomic<bool> cancel{true};
    tracer.traceSamples(positions, normals, scene.lights[0], 16, 0, 4, sums, true, &cancel);
    EXPECT_EQ(sums.traced, 0u);
    EXPECT_THROW(tracer.traceSamples(positions, normals, scene.lights[0], 16, 4, 4, sums, true), std::exception);
    SampleSums wrong;
    wrong.reset(kGrid, kGrid, 8);  // M of another trace
    EXPECT_THROW(tracer.traceSamples(positions, normals, scene.lights[0], 16, 0, 4, wrong, true), std::exception);
}
