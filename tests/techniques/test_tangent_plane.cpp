// The visibility convention's shared math (shaders/shared/tangent_plane.glsl; DESIGN.md section
// 5): the fraction of a square, disk or sphere light in front of a receiver's tangent plane,
// against closed forms on the CPU, and the GPU against the same source compiled as C++ on a grid.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "gl/util.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

using namespace shared;
constexpr float kPi = 3.14159265358979323846f;

// A light of shape `shape` and size `size` centred at the origin in the plane y = 0 (right = +x,
// up = -z, as the scenes' default), and a receiver at height h below it whose normal makes the
// tangent plane cut the light plane along the line x = c (the plane through p containing the
// z axis direction, tilted so that it meets y = 0 at x = c).
float fractionWithPlaneAt(int shape, float size, float c) {
    // Receiver p = (c, -1, 0) + the plane through it with normal (1, 0, 0) meets the light plane at
    // x = c; the front side is x > c.
    glm::vec3 p(c, -1.0f, 0.0f), n(1.0f, 0.0f, 0.0f);
    return lightFractionInFront(shape, glm::vec3(0.0f), glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), size, p, n);
}

TEST(TangentPlane, SquareFractionIsTheClippedArea) {
    // Width 2 (half width 1): the part x > c of [-1,1]^2 has area 2 (1 - c), fraction (1 - c) / 2.
    for (float c : {-1.5f, -1.0f, -0.75f, -0.3f, 0.0f, 0.2f, 0.5f, 0.99f, 1.0f, 2.0f}) {
        float expected = std::clamp((1.0f - c) / 2.0f, 0.0f, 1.0f);
        EXPECT_NEAR(fractionWithPlaneAt(LIGHT_SHAPE_SQUARE, 2.0f, c), expected, 1e-6f) << c;
    }
    // Through the centre: half; tangent to the border: all or nothing; wholly behind: none.
    EXPECT_NEAR(fractionWithPlaneAt(LIGHT_SHAPE_SQUARE, 3.0f, 0.0f), 0.5f, 1e-6f);
    EXPECT_EQ(fractionWithPlaneAt(LIGHT_SHAPE_SQUARE, 3.0f, 1.5f), 0.0f);
    EXPECT_EQ(fractionWithPlaneAt(LIGHT_SHAPE_SQUARE, 3.0f, -1.5f), 1.0f);
    // A diagonal line through the centre and through a corner: half, and the corner triangle.
    EXPECT_NEAR(squareFractionInFront(glm::vec2(1.0f, 1.0f), 0.0f), 0.5f, 1e-6f);
    // x + y > 1: the triangle (1,0), (1,1), (0,1) of area 1/2, an eighth of the square.
    EXPECT_NEAR(squareFractionInFront(glm::vec2(1.0f, 1.0f), -1.0f), 0.125f, 1e-6f);
    // x + y > 2 touches only the corner (1, 1).
    EXPECT_EQ(squareFractionInFront(glm::vec2(1.0f, 1.0f), -2.0f), 0.0f);
    // A plane parallel to the light (g = 0): the light wholly in front or wholly behind.
    EXPECT_EQ(squareFractionInFront(glm::vec2(0.0f), 0.3f), 1.0f);
    EXPECT_EQ(squareFractionInFront(glm::vec2(0.0f), -0.3f), 0.0f);
    EXPECT_EQ(squareFractionInFront(glm::vec2(0.0f), 0.0f), 0.0f);  // the plane of the light itself
}

TEST(TangentPlane, DiskFractionIsTheCircularSegment) {
    // Radius 1: the part x > c of the unit disk, (acos c - c sqrt(1 - c^2)) / pi.
    for (float c : {-1.0f, -0.9f, -0.5f, 0.0f, 0.25f, 0.5f, 0.8f, 1.0f}) {
        double k = c;
        float expected = float((std::acos(k) - k * std::sqrt(1.0 - k * k)) / kPi);
        EXPECT_NEAR(fractionWithPlaneAt(LIGHT_SHAPE_DISK, 1.0f, c), expected, 2e-6f) << c;
        // A sphere light is the disk through its centre facing the light direction.
        EXPECT_EQ(fractionWithPlaneAt(LIGHT_SHAPE_SPHERE, 1.0f, c), fractionWithPlaneAt(LIGHT_SHAPE_DISK, 1.0f, c));
    }
    EXPECT_NEAR(fractionWithPlaneAt(LIGHT_SHAPE_DISK, 2.0f, 0.0f), 0.5f, 1e-6f);  // through the centre
    EXPECT_EQ(fractionWithPlaneAt(LIGHT_SHAPE_DISK, 2.0f, 2.0f), 0.0f);            // tangent, behind
    EXPECT_EQ(fractionWithPlaneAt(LIGHT_SHAPE_DISK, 2.0f, -2.0f), 1.0f);           // tangent, in front
    EXPECT_EQ(fractionWithPlaneAt(LIGHT_SHAPE_DISK, 2.0f, 5.0f), 0.0f);            // wholly behind
    EXPECT_EQ(diskFractionInFront(glm::vec2(0.0f), 1.0f), 1.0f);
    EXPECT_EQ(diskFractionInFront(glm::vec2(0.0f), -1.0f), 0.0f);
    // Scale invariance: the same line in other units gives the same fraction.
    EXPECT_NEAR(diskFractionInFront(glm::vec2(3.0f, 4.0f), 2.5f), diskFractionInFront(glm::vec2(0.6f, 0.8f), 0.5f), 1e-6f);
}

TEST(TangentPlane, PointLightAndFacingReceivers) {
    // A point light: by its centre alone.
    glm::vec3 centre(0.0f, 4.0f, 0.0f);
    EXPECT_EQ(lightFractionInFront(LIGHT_SHAPE_POINT, centre, glm::vec3(0), glm::vec3(0), 0.0f, glm::vec3(0), glm::vec3(0, 1, 0)), 1.0f);
    EXPECT_EQ(lightFractionInFront(LIGHT_SHAPE_POINT, centre, glm::vec3(0), glm::vec3(0), 0.0f, glm::vec3(0), glm::vec3(0, -1, 0)), 0.0f);
    // The floor under a square light faces all of it; a receiver facing away sees none of it.
    for (int shape : {LIGHT_SHAPE_SQUARE, LIGHT_SHAPE_DISK, LIGHT_SHAPE_SPHERE}) {
        EXPECT_EQ(lightFractionInFront(shape, centre, glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), 1.0f, glm::vec3(0.3f, 0, 0.2f), glm::vec3(0, 1, 0)), 1.0f);
        EXPECT_EQ(lightFractionInFront(shape, centre, glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), 1.0f, glm::vec3(0.3f, 0, 0.2f), glm::vec3(0, -1, 0)), 0.0f);
    }
    EXPECT_TRUE(inFrontOfTangentPlane(glm::vec3(0), glm::vec3(0, 1, 0), centre));
    EXPECT_FALSE(inFrontOfTangentPlane(glm::vec3(0), glm::vec3(0, -1, 0), centre));
    EXPECT_FALSE(inFrontOfTangentPlane(glm::vec3(0), glm::vec3(1, 0, 0), centre));  // in the plane: not in front
}

// The fraction agrees with counting a fine grid of light points in front of the plane (the way the
// references decide it per sample), for random receivers, normals and light frames.
TEST(TangentPlane, FractionMatchesCountingLightPoints) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const int grid = 400;  // the count's error is at most ~2 / grid of the light's width
    for (int trial = 0; trial < 60; ++trial) {
        int shape = trial % 3 == 0 ? LIGHT_SHAPE_SQUARE : trial % 3 == 1 ? LIGHT_SHAPE_DISK : LIGHT_SHAPE_SPHERE;
        glm::vec3 centre(u(rng), 3.0f + u(rng), u(rng));
        glm::vec3 right = glm::normalize(glm::vec3(1.0f, 0.3f * u(rng), 0.3f * u(rng)));
        glm::vec3 up = glm::normalize(glm::cross(right, glm::vec3(0.2f * u(rng), 1.0f, 0.2f * u(rng))));
        float size = 0.5f + std::abs(u(rng));
        glm::vec3 p(u(rng), 2.5f + u(rng), u(rng));
        glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        int inside = 0, front = 0;
        for (int j = 0; j < grid; ++j)
            for (int i = 0; i < grid; ++i) {
                glm::vec2 uv((i + 0.5f) / grid, (j + 0.5f) / grid);
                glm::vec2 o = (uv - 0.5f) * 2.0f;  // [-1,1]^2
                if (shape != LIGHT_SHAPE_SQUARE && glm::dot(o, o) > 1.0f) continue;
                float unit = shape == LIGHT_SHAPE_SQUARE ? 0.5f * size : size;
                glm::vec3 l = centre + unit * (o.x * right + o.y * up);
                ++inside;
                front += inFrontOfTangentPlane(p, n, l);
            }
        float counted = float(front) / float(inside);
        float exact = lightFractionInFront(shape, centre, right, up, size, p, n);
        EXPECT_NEAR(exact, counted, 0.006f) << "trial " << trial;
    }
}

struct Case {
    glm::vec4 receiver, normal, centre, right, up;
};
struct Result {
    glm::vec4 fractions;
};

class TangentPlaneGpu : public testing::GLTest {};

// Tolerances: the clipped polygon is a few operations; 2e-6 absolute covers the GPU's fused
// multiply-adds (fractions are in [0, 1]). The circular segment goes through acos, which GLSL
// computes to less precision (llvmpipe's differs from the C library's by up to 5e-5): 1e-4. The in-front test is
// exact except where n . (l - p) is within rounding of 0, which the grid avoids (|value| > 1e-4).
TEST_F(TangentPlaneGpu, AgreesWithCpuOnAGrid) {
    std::vector<Case> cases;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 2048; ++i) {
        int shape = i % 4;  // point, square, disk, sphere
        glm::vec3 right = glm::normalize(glm::vec3(1.0f, 0.2f * u(rng), 0.2f * u(rng)));
        glm::vec3 up = glm::normalize(glm::cross(right, glm::vec3(0, 1, 0)));
        glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        glm::vec3 p(u(rng), u(rng), u(rng));
        glm::vec3 c(u(rng), 2.0f + u(rng), u(rng));
        if (std::abs(glm::dot(n, c - p)) < 1e-4f) c.y += 0.01f;
        // The 2D forms: lines through the light's border, its centre, corners and parallel to it.
        glm::vec2 g(u(rng), u(rng));
        float d = i % 7 == 0 ? 0.0f : i % 11 == 0 ? glm::length(g) : 1.5f * u(rng);
        if (i % 13 == 0) g = glm::vec2(0.0f);
        cases.push_back({glm::vec4(p, 0.2f + std::abs(u(rng))), glm::vec4(n, float(shape)), glm::vec4(c, g.x),
                         glm::vec4(right, g.y), glm::vec4(up, d)});
    }
    Buffer in(cases.size() * sizeof(Case), cases.data());
    Buffer out(cases.size() * sizeof(Result));
    const ShaderProgram& program = programCache().compute("tests/tangent_plane.comp");
    program.set("count", unsigned(cases.size()));
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.dispatch(GLuint((cases.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const std::vector<Result> gpu = out.read<Result>();
    ASSERT_EQ(gpu.size(), cases.size());
    int partial = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
        const Case& c = cases[i];
        SCOPED_TRACE("case " + std::to_string(i));
        glm::vec3 p(c.receiver), n(c.normal), centre(c.centre), right(c.right), up(c.up);
        glm::vec2 g(c.centre.w, c.right.w);
        float light = lightFractionInFront(int(c.normal.w), centre, right, up, c.receiver.w, p, n);
        const int shape = int(c.normal.w);
        EXPECT_NEAR(gpu[i].fractions.x, light, shape == LIGHT_SHAPE_DISK || shape == LIGHT_SHAPE_SPHERE ? 1e-4f : 2e-6f);
        EXPECT_NEAR(gpu[i].fractions.y, squareFractionInFront(g, c.up.w), 2e-6f);
        EXPECT_NEAR(gpu[i].fractions.z, diskFractionInFront(g, c.up.w), 1e-4f);
        EXPECT_EQ(gpu[i].fractions.w, inFrontOfTangentPlane(p, n, centre) ? 1.0f : 0.0f);
        partial += light > 0.0f && light < 1.0f;
    }
    EXPECT_GT(partial, 200);  // the grid cuts lights in two, not only all-or-nothing cases
}

}  // namespace
}  // namespace shadowlab
