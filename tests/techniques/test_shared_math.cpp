// CPU tests of the math shared by the shaders and the host (shaders/shared/*.glsl through
// shared/shared.h), with the hard cases of DESIGN.md section 9.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "shared/shared.h"

using namespace shadowlab;

namespace {

// DESIGN.md section 5, written out independently of square_occluder.glsl:
// v(p) = 1 - len([-1 - p.x, 1 - p.x] ∩ [-0.5, 0.5]) * len([-1 - p.z, 1 - p.z] ∩ [-0.5, 0.5]).
double designVisibility(double px, double pz) {
    auto len = [](double a0, double a1) { return std::max(0.0, std::min(a1, 0.5) - std::max(a0, -0.5)); };
    return 1.0 - len(-1.0 - px, 1.0 - px) * len(-1.0 - pz, 1.0 - pz);
}

float squareScene(glm::vec3 p, float lightWidth = 1.0f, float occluderHalf = 0.5f) {
    return shared::squareOccluderVisibility(p, occluderHalf, 2.0f, 4.0f, lightWidth);
}

}  // namespace

// ---- light_sampling.glsl ----------------------------------------------------------------------

// For every n the n samples fall in n distinct cells that tile the unit square: r = strataRows(n)
// rows of equal height, the first n % r rows holding n / r + 1 cells and the others n / r.
TEST(StratifiedSample, CellsPartitionTheSquareForEveryN) {
    for (uint32_t n = 1; n <= 300; ++n) {
        SCOPED_TRACE("n = " + std::to_string(n));
        const uint32_t r = shared::strataRows(n);
        ASSERT_GE(r, 1u);
        ASSERT_LE(r, n);
        const uint32_t q = n / r;
        const uint32_t extra = n % r;
        std::vector<int> hits(size_t(r) * (q + 1), 0);
        double weightSum = 0.0;
        for (uint32_t seed : {0u, 1u, 0xDEADBEEFu}) {
            std::fill(hits.begin(), hits.end(), 0);
            weightSum = 0.0;
            for (uint32_t i = 0; i < n; ++i) {
                glm::vec3 s = shared::stratifiedSample(i, n, seed);
                ASSERT_GE(s.x, 0.0f);
                ASSERT_LT(s.x, 1.0f);
                ASSERT_GE(s.y, 0.0f);
                ASSERT_LT(s.y, 1.0f);
                const uint32_t row = uint32_t(std::floor(double(s.y) * r));
                ASSERT_LT(row, r);
                const uint32_t cells = row < extra ? q + 1 : q;
                const uint32_t col = uint32_t(std::floor(double(s.x) * cells));
                ASSERT_LT(col, cells);
                hits[size_t(row) * (q + 1) + col] += 1;
                // The weight is the area of the sample's cell.
                EXPECT_NEAR(s.z, 1.0 / (double(r) * cells), 1e-7);
                weightSum += s.z;
            }
            for (uint32_t row = 0; row < r; ++row) {
                const uint32_t cells = row < extra ? q + 1 : q;
                for (uint32_t col = 0; col < cells; ++col) {
                    EXPECT_EQ(hits[size_t(row) * (q + 1) + col], 1) << "cell (" << row << ", " << col << ")";
                }
            }
            EXPECT_NEAR(weightSum, 1.0, 1e-6);
        }
    }
}

TEST(StratifiedSample, PerfectSquaresAreRegularGrids) {
    for (uint32_t k : {1u, 2u, 4u, 16u, 32u}) {
        EXPECT_EQ(shared::strataRows(k * k), k);
    }
    EXPECT_EQ(shared::strataRows(0), 1u);
    // Different seeds jitter differently, the same seed repeats.
    glm::vec3 a = shared::stratifiedSample(5, 16, 1);
    glm::vec3 b = shared::stratifiedSample(5, 16, 2);
    glm::vec3 c = shared::stratifiedSample(5, 16, 1);
    EXPECT_NE(a, b);
    EXPECT_EQ(a, c);
}

// Hard case: the largest jitter a hash can give, (2^24 - 1) / 2^24, in the last cell of a row.
// float(col) + jitter rounds up to col + 1 once col >= 1, which puts the sample at u = 1, on the
// light's edge and outside its own cell. The seeds below were found by searching for hashes
// pcgHash(seed * 0x9E3779B9u + i) whose top 24 bits are all ones.
TEST(StratifiedSample, LargestJitterStaysInsideItsCell) {
    struct Case {
        uint32_t n, i, seed;
    };
    for (Case c : {Case{4, 3, 38204152u}, Case{1024, 1023, 3279267u}}) {
        glm::vec3 s = shared::stratifiedSample(c.i, c.n, c.seed);
        EXPECT_LT(s.x, 1.0f) << "n = " << c.n << ", i = " << c.i << ", seed = " << c.seed;
        EXPECT_LT(s.y, 1.0f) << "n = " << c.n << ", i = " << c.i << ", seed = " << c.seed;
    }
}

TEST(ConcentricDisk, MapsInsideTheDiskAndPreservesArea) {
    // Uniform random points of the square (a regular grid would not do: the map sends square
    // annuli to rings, so a grid's rows quantise every ring's count by a few percent).
    const int points = 1000000;
    const int rings = 8;
    const int sectors = 8;
    std::vector<int> ringCount(rings, 0);
    std::vector<int> sectorCount(sectors, 0);
    std::mt19937 rng(2024);
    for (int k = 0; k < points; ++k) {
        glm::vec2 uv(float(rng() >> 8) / 16777216.0f, float(rng() >> 8) / 16777216.0f);
        glm::vec2 d = shared::concentricSquareToDisk(uv);
        float r2 = glm::dot(d, d);
        ASSERT_LE(r2, 1.0f + 1e-6f) << uv.x << " " << uv.y;
        // Rings of equal area: ring k holds r^2 in [k/rings, (k+1)/rings).
        ringCount[std::min(int(r2 * rings), rings - 1)] += 1;
        double angle = std::atan2(double(d.y), double(d.x)) + std::numbers::pi;
        sectorCount[std::min(int(angle / (2.0 * std::numbers::pi) * sectors), sectors - 1)] += 1;
    }
    // An area-preserving map puts points / 8 = 125000 in each; one standard deviation is 0.3%.
    const double expected = double(points) / rings;
    for (int k = 0; k < rings; ++k) {
        EXPECT_NEAR(ringCount[k] / expected, 1.0, 0.015) << "ring " << k;
    }
    for (int k = 0; k < sectors; ++k) {
        EXPECT_NEAR(sectorCount[k] / (double(points) / sectors), 1.0, 0.015) << "sector " << k;
    }
    EXPECT_EQ(shared::concentricSquareToDisk(glm::vec2(0.5f, 0.5f)), glm::vec2(0.0f, 0.0f));
    // Corners of the square go to the circle.
    EXPECT_NEAR(glm::length(shared::concentricSquareToDisk(glm::vec2(1.0f, 1.0f))), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(shared::concentricSquareToDisk(glm::vec2(0.0f, 1.0f))), 1.0f, 1e-6f);
}

TEST(LightSample, SquareAndDiskOffsetsAlongTheLightAxes) {
    const glm::vec3 centre(0, 4, 0), right(1, 0, 0), up(0, 0, -1);
    glm::vec3 corner = shared::lightSamplePosition(centre, right, up, shared::LIGHT_SHAPE_SQUARE, 1.0f, glm::vec2(0, 0));
    EXPECT_EQ(corner, glm::vec3(-0.5f, 4.0f, 0.5f));
    glm::vec3 middle = shared::lightSamplePosition(centre, right, up, shared::LIGHT_SHAPE_DISK, 2.0f, glm::vec2(0.5f, 0.5f));
    EXPECT_EQ(middle, centre);
    glm::vec3 rim = shared::lightSamplePosition(centre, right, up, shared::LIGHT_SHAPE_SPHERE, 2.0f, glm::vec2(1.0f, 0.5f));
    EXPECT_NEAR(glm::length(rim - centre), 2.0f, 1e-6f);
    glm::vec3 point = shared::lightSamplePosition(centre, right, up, shared::LIGHT_SHAPE_POINT, 5.0f, glm::vec2(0.1f, 0.9f));
    EXPECT_EQ(point, centre);
}

// ---- shadow_projection.glsl -------------------------------------------------------------------

TEST(ShadowProjection, AgreesWithLookAtAndPerspective) {
    // The square-occluder light: at (0,4,0) looking down, up = -z, a 90 degree frustum.
    glm::mat4 lightViewFromWorld = glm::lookAt(glm::vec3(0, 4, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
    glm::mat4 lightClipFromView = glm::perspective(glm::radians(90.0f), 1.0f, 0.1f, 10.0f);
    glm::vec4 c = shared::shadowMapCoord(lightViewFromWorld, lightClipFromView, glm::vec3(0, 0, 0));
    EXPECT_NEAR(c.x, 0.5f, 1e-6f);
    EXPECT_NEAR(c.y, 0.5f, 1e-6f);
    EXPECT_NEAR(c.z, 4.0f, 1e-6f);
    EXPECT_EQ(c.w, 1.0f);
    // x is the light's right axis; -z its up axis; tan(45 deg) = 1, so at depth 4 one unit = 1/8 of the map.
    glm::vec4 r = shared::shadowMapCoord(lightViewFromWorld, lightClipFromView, glm::vec3(1, 0, 0));
    EXPECT_NEAR(r.x, 0.625f, 1e-6f);
    EXPECT_NEAR(r.y, 0.5f, 1e-6f);
    glm::vec4 u = shared::shadowMapCoord(lightViewFromWorld, lightClipFromView, glm::vec3(0, 0, -1));
    EXPECT_NEAR(u.x, 0.5f, 1e-6f);
    EXPECT_NEAR(u.y, 0.625f, 1e-6f);
    // Same answer as projecting with GLM directly.
    for (glm::vec3 p : {glm::vec3(0.3f, 1.0f, -0.7f), glm::vec3(-2.0f, 0.0f, 1.5f), glm::vec3(3.9f, 0.0f, 3.9f)}) {
        glm::vec4 clip = lightClipFromView * lightViewFromWorld * glm::vec4(p, 1.0f);
        glm::vec4 s = shared::shadowMapCoord(lightViewFromWorld, lightClipFromView, p);
        EXPECT_NEAR(s.x, clip.x / clip.w * 0.5f + 0.5f, 1e-6f);
        EXPECT_NEAR(s.y, clip.y / clip.w * 0.5f + 0.5f, 1e-6f);
        EXPECT_NEAR(s.z, 4.0f - p.y, 1e-5f);
        EXPECT_EQ(s.w, 1.0f);
    }
    // Outside the frustum and behind the light: not inside.
    EXPECT_EQ(shared::shadowMapCoord(lightViewFromWorld, lightClipFromView, glm::vec3(5, 0, 0)).w, 0.0f);
    glm::vec4 behind = shared::shadowMapCoord(lightViewFromWorld, lightClipFromView, glm::vec3(0, 5, 0));
    EXPECT_EQ(behind.w, 0.0f);
    EXPECT_LT(behind.z, 0.0f);
}

TEST(ShadowProjection, TexelSize) {
    EXPECT_NEAR(shared::shadowTexelWorldSize(4.0f, 1.0f, 1024.0f), 8.0f / 1024.0f, 1e-9f);
    EXPECT_NEAR(shared::shadowTexelWorldSize(4.0f, 1.0f, 1.0f), 8.0f, 1e-6f);  // a 1x1 shadow map
}

TEST(ShadowDepthBias, GrowsWithTheAngleAndIsClamped) {
    const float texel = 0.01f, constTexels = 1.5f, slopeTexels = 2.0f;
    float previous = -1.0f;
    for (int degrees = 0; degrees <= 90; ++degrees) {
        float cosTheta = std::cos(glm::radians(float(degrees)));
        float bias = shared::shadowDepthBias(texel, constTexels, slopeTexels, cosTheta);
        EXPECT_TRUE(std::isfinite(bias));
        EXPECT_GE(bias, previous) << degrees << " degrees";
        EXPECT_LE(bias, texel * (constTexels + slopeTexels * 10.0f) * (1.0f + 1e-6f));
        previous = bias;
    }
    EXPECT_FLOAT_EQ(shared::shadowDepthBias(texel, constTexels, slopeTexels, 1.0f), texel * constTexels);
    EXPECT_NEAR(shared::shadowDepthBias(texel, constTexels, slopeTexels, std::cos(glm::radians(45.0f))),
                texel * (constTexels + slopeTexels), 1e-6f);
    // Grazing, back-facing and out-of-range cosines all hit the clamp, never Inf or NaN.
    const float clamped = texel * (constTexels + slopeTexels * 10.0f);
    for (float cosTheta : {0.0f, -0.5f, -1.0f, 1e-8f}) {
        EXPECT_FLOAT_EQ(shared::shadowDepthBias(texel, constTexels, slopeTexels, cosTheta), clamped) << cosTheta;
    }
    EXPECT_FLOAT_EQ(shared::shadowDepthBias(texel, constTexels, slopeTexels, 2.0f), texel * constTexels);
}

TEST(ShadowDepthTest, Williams) {
    EXPECT_EQ(shared::shadowDepthTest(3.0f, 3.0f, 0.0f), 1.0f);
    EXPECT_EQ(shared::shadowDepthTest(3.0f, 2.0f, 0.5f), 0.0f);
    EXPECT_EQ(shared::shadowDepthTest(3.0f, 2.0f, 1.0f), 1.0f);
}

// ---- square_occluder.glsl ---------------------------------------------------------------------

TEST(SquareOccluder, EqualsTheDesignFormulaOnAGrid) {
    for (int j = 0; j <= 160; ++j) {
        for (int i = 0; i <= 160; ++i) {
            float x = -4.0f + 0.05f * i;
            float z = -4.0f + 0.05f * j;
            float v = squareScene(glm::vec3(x, 0.0f, z));
            EXPECT_NEAR(v, designVisibility(x, z), 1e-6) << "at (" << x << ", " << z << ")";
            EXPECT_GE(v, 0.0f);
            EXPECT_LE(v, 1.0f);
        }
    }
    // Umbra, lit, and the half-covered point straight under the plate's edge.
    EXPECT_EQ(squareScene(glm::vec3(0, 0, 0)), 0.0f);
    EXPECT_EQ(squareScene(glm::vec3(3, 0, 0)), 1.0f);
    EXPECT_FLOAT_EQ(squareScene(glm::vec3(1, 0, 0)), 0.5f);
}

TEST(SquareOccluder, MonotoneAsTheOccluderGrows) {
    for (float x : {-2.0f, -1.2f, -0.5f, 0.0f, 0.3f, 1.0f, 1.49f, 2.5f}) {
        for (float z : {-1.7f, 0.0f, 0.6f, 1.1f}) {
            float previous = 2.0f;
            for (int k = 0; k <= 200; ++k) {
                float half = 0.01f * k;
                float v = squareScene(glm::vec3(x, 0.0f, z), 1.0f, half);
                EXPECT_LE(v, previous) << "p = (" << x << ", " << z << "), half = " << half;
                EXPECT_GE(v, 0.0f);
                previous = v;
            }
        }
    }
}

TEST(SquareOccluder, PointLightIsTheHardShadow) {
    for (int j = 0; j <= 80; ++j) {
        for (int i = 0; i <= 80; ++i) {
            float x = -2.0f + 0.05f * i + 0.0125f;  // never on the border |x| = 1
            float z = -2.0f + 0.05f * j + 0.0125f;
            bool inside = std::abs(x) < 1.0f && std::abs(z) < 1.0f;
            EXPECT_EQ(squareScene(glm::vec3(x, 0, z), 0.0f), inside ? 0.0f : 1.0f) << x << " " << z;
        }
    }
}

// Hard case (DESIGN.md section 9): the light size goes to 0 and the soft shadow converges to the
// hard one; the penumbra is then a band of width w_l (s - 1) = 1e-6 around the border.
TEST(SquareOccluder, TinyLightConvergesToTheHardShadow) {
    const float tiny = 1e-6f;
    for (int j = 0; j <= 80; ++j) {
        for (int i = 0; i <= 80; ++i) {
            float x = -2.0f + 0.05f * i + 0.0125f;
            float z = -2.0f + 0.05f * j + 0.0125f;
            float v = squareScene(glm::vec3(x, 0, z), tiny);
            EXPECT_EQ(v, squareScene(glm::vec3(x, 0, z), 0.0f)) << x << " " << z;
        }
    }
    // On the hard-shadow border itself the tiny light is half covered (x = 1) or a quarter (corner).
    float edge = squareScene(glm::vec3(1.0f, 0.0f, 0.0f), tiny);
    EXPECT_TRUE(edge >= 0.0f && edge <= 1.0f);
    EXPECT_NEAR(edge, 0.5f, 0.05f);
    float corner = squareScene(glm::vec3(1.0f, 0.0f, 1.0f), tiny);
    EXPECT_NEAR(corner, 0.75f, 0.05f);
}

// Hard case: receiver points exactly on the inner (umbra) and outer (lit) penumbra borders. In
// this scene the penumbra along x is 0.5 <= |p.x| <= 1.5.
TEST(SquareOccluder, ExactlyOnThePenumbraBorders) {
    EXPECT_EQ(squareScene(glm::vec3(1.5f, 0.0f, 0.0f)), 1.0f);
    EXPECT_EQ(squareScene(glm::vec3(-1.5f, 0.0f, 0.0f)), 1.0f);
    EXPECT_EQ(squareScene(glm::vec3(0.0f, 0.0f, 1.5f)), 1.0f);
    EXPECT_EQ(squareScene(glm::vec3(0.5f, 0.0f, 0.0f)), 0.0f);
    EXPECT_EQ(squareScene(glm::vec3(-0.5f, 0.0f, -0.5f)), 0.0f);
    EXPECT_EQ(squareScene(glm::vec3(1.5f, 0.0f, 1.5f)), 1.0f);
    EXPECT_EQ(squareScene(glm::vec3(0.5f, 0.0f, 1.5f)), 1.0f);
    // Just inside each border.
    EXPECT_LT(squareScene(glm::vec3(1.49f, 0.0f, 0.0f)), 1.0f);
    EXPECT_GT(squareScene(glm::vec3(0.51f, 0.0f, 0.0f)), 0.0f);
}

// Hard case: the receiver almost touches the occluder (s = (lightY - p.y) / (occluderY - p.y)
// becomes huge). The plate then hides the whole light from points under it and none from points
// beside it; v stays in [0,1] and never NaN.
TEST(SquareOccluder, ReceiverAlmostTouchingTheOccluder) {
    const float occluderY = 2.0f;
    for (float gap : {1e-3f, 1e-5f, 2.5e-7f}) {
        float y = occluderY - gap;
        ASSERT_LT(y, occluderY);
        EXPECT_EQ(shared::squareOccluderVisibility(glm::vec3(0.0f, y, 0.0f), 0.5f, occluderY, 4.0f, 1.0f), 0.0f);
        EXPECT_EQ(shared::squareOccluderVisibility(glm::vec3(0.4f, y, -0.3f), 0.5f, occluderY, 4.0f, 1.0f), 0.0f);
        EXPECT_EQ(shared::squareOccluderVisibility(glm::vec3(0.6f, y, 0.0f), 0.5f, occluderY, 4.0f, 1.0f), 1.0f);
        EXPECT_EQ(shared::squareOccluderVisibility(glm::vec3(-3.0f, y, 2.0f), 0.5f, occluderY, 4.0f, 1.0f), 1.0f);
        for (float x : {0.5f, -0.5f, 0.49999f, 0.50001f}) {
            float v = shared::squareOccluderVisibility(glm::vec3(x, y, 0.0f), 0.5f, occluderY, 4.0f, 1.0f);
            EXPECT_TRUE(v >= 0.0f && v <= 1.0f) << "x = " << x << ", gap = " << gap << ": v = " << v;
        }
    }
    // On the plate's plane and above it nothing is hidden.
    EXPECT_EQ(shared::squareOccluderVisibility(glm::vec3(0.0f, 2.0f, 0.0f), 0.5f, 2.0f, 4.0f, 1.0f), 1.0f);
    EXPECT_EQ(shared::squareOccluderVisibility(glm::vec3(0.0f, 3.0f, 0.0f), 0.5f, 2.0f, 4.0f, 1.0f), 1.0f);
    // The smallest possible gap below a plate at height 0: s overflows to infinity, and a point
    // exactly under the plate's edge computes s * 0 = inf * 0.
    const float below = -std::numeric_limits<float>::denorm_min();
    for (float x : {0.0f, 0.5f, -0.5f, 0.7f}) {
        float v = shared::squareOccluderVisibility(glm::vec3(x, below, 0.0f), 0.5f, 0.0f, 4.0f, 1.0f);
        EXPECT_TRUE(v >= 0.0f && v <= 1.0f) << "x = " << x << ": v = " << v;
    }
}
