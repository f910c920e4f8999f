// The light-space multi-resolution of guennebaud2007 sec. 5.1 in ssm-contour and ssm-gbp06: the
// shared functions (eq. 2, eq. 3, the blending pseudo-code, z_occ, the per-level occlusion test)
// on the CPU and against the GPU, and the renders: blending removes the seams of Fig. 6a, and the
// adaptive walk stays within the 0.005 RMSE of the full-resolution walk.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gl/buffer.h"
#include "gl/program.h"
#include "graph/renderer.h"
#include "image/metrics.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

using namespace shared;

TEST(LightLevels, EquationTwoIsTheFinestLevelUnderTk) {
    EXPECT_EQ(lightLevelForKernel(10.0f, 16.0f, 10), 0);
    EXPECT_EQ(lightLevelForKernel(16.0f, 16.0f, 10), 0);
    EXPECT_EQ(lightLevelForKernel(16.5f, 16.0f, 10), 1);
    EXPECT_EQ(lightLevelForKernel(32.0f, 16.0f, 10), 1);
    EXPECT_EQ(lightLevelForKernel(100.0f, 16.0f, 10), 3);  // 100 / 8 = 12.5 <= 16 < 25
    EXPECT_EQ(lightLevelForKernel(1e6f, 16.0f, 5), 5);     // clamped to the top level
    for (float w = 1.0f; w < 4000.0f; w *= 1.07f) {
        int lod = lightLevelForKernel(w, 16.0f, 12);
        EXPECT_LE(w / float(1 << lod), 16.0f * (1.0f + 1e-6f)) << w;           // under t_k at its level
        if (lod > 0) EXPECT_GT(w / float(1 << (lod - 1)), 16.0f) << w;         // and the finest such level
    }
}

TEST(LightLevels, BlendingIsContinuousAndBoundsTheKernel) {
    const float beta = 0.05f;
    const int top = 9;
    // Sweep lambda finely: the blended level value lod + weight (other - lod) is continuous (the
    // paper's printed weight (d / beta) / 2 would jump to 10 at d -> 1).
    float previous = -1.0f;
    for (float lambda = 0.0f; lambda <= float(top); lambda += 1e-4f) {
        glm::vec3 b = lightLevelBlend(lambda, beta, top);
        EXPECT_GE(b.z, 0.0f);
        EXPECT_LE(b.z, 0.5f + 1e-6f);
        float effective = b.x + b.z * (b.y - b.x);
        if (previous >= 0.0f) EXPECT_LT(std::abs(effective - previous), 0.01f) << lambda;
        previous = effective;
        // Outside the bands, one level only.
        float d = lambda - std::floor(lambda);
        if (d > beta && d < 1.0f - beta) EXPECT_EQ(b.z, 0.0f) << lambda;
    }
    // No blending with beta = 0.
    EXPECT_EQ(lightLevelBlend(2.01f, 0.0f, top).z, 0.0f);
    // The clamp of eq. 3: never below log2(w_k / (4 t_k)), so the level walked has a kernel of at
    // most 2^(3 + beta) t_k of its texels (8 t_k, and the band below) whatever z_occ says; where z_occ agrees with z_min (ratio 1) at most
    // 2^(1 + beta) t_k (eq. 2's 2 t_k, and the blending band's level below); and the floor is
    // continuous in w_k (no seam of its own).
    for (float w = 1.0f; w < 5000.0f; w *= 1.11f)
        for (float ratio : {0.01f, 0.3f, 1.0f}) {
            float lambda = lightLevelContinuous(w * ratio, w, 16.0f, 12);
            glm::vec3 b = lightLevelBlend(lambda, beta, 12);
            int finest = b.z > 0.0f ? int(std::min(b.x, b.y)) : int(b.x);
            EXPECT_LE(w / float(1 << finest), std::pow(2.0f, (ratio == 1.0f ? 1.0f : 3.0f) + beta) * 16.0f * (1.0f + 1e-5f)) << w << " " << ratio;
            EXPECT_LT(std::abs(lightLevelContinuous(w * ratio * 1.0001f, w * 1.0001f, 16.0f, 12) - lambda), 1e-3f);
        }
}

// The row-bit walk (backprojection.glsl section 9) finds exactly the blocks the plain walk's
// "mask != 0 && mask != 15" finds, with the same masks, on random rows of every chunk length.
TEST(LightLevels, RowBitsFindExactlyTheContourBlocks) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 2000; ++trial) {
        const int blocks = 1 + int(rng() % BP_ROW_CHUNK);
        const float density = float(rng() % 100) / 100.0f;
        bool below[32], above[32];
        uint b = 0u, a = 0u;
        for (int i = 0; i <= blocks; ++i) {
            below[i] = float(rng() % 1000) / 1000.0f < density;
            above[i] = float(rng() % 1000) / 1000.0f < density;
            if (below[i]) b |= 1u << uint(i);
            if (above[i]) a |= 1u << uint(i);
        }
        // Bits past the chunk must be ignored.
        if (blocks + 1 < 32 && rng() % 2) b |= 0xffffffffu << uint(blocks + 1);
        uint found = contourBlockBits(b, a, blocks);
        for (int i = 0; i < blocks; ++i) {
            int mask = (below[i] ? 1 : 0) | (below[i + 1] ? 2 : 0) | (above[i + 1] ? 4 : 0) | (above[i] ? 8 : 0);
            bool contour = mask != 0 && mask != 15;
            ASSERT_EQ(((found >> uint(i)) & 1u) != 0u, contour) << "trial " << trial << " block " << i;
            if (contour) ASSERT_EQ(contourBlockMask(b, a, i), mask) << "trial " << trial << " block " << i;
        }
        ASSERT_EQ(found >> uint(blocks), 0u) << "a block past the chunk";
    }
}

TEST(LightLevels, OccluderDepthHint) {
    const glm::vec4 z(2.0f, 3.0f, 9.0f, 4.0f);
    // Only texels nearer than the limit count, renormalised; never nearer than z_min.
    EXPECT_FLOAT_EQ(occluderDepthHint(z, {0.0f, 0.0f}, 5.0f, 1.0f), 2.0f);
    EXPECT_FLOAT_EQ(occluderDepthHint(z, {1.0f, 0.0f}, 5.0f, 1.0f), 3.0f);
    EXPECT_FLOAT_EQ(occluderDepthHint(z, {1.0f, 1.0f}, 5.0f, 1.0f), 1.0f);  // texel 11 does not occlude: z_min
    EXPECT_FLOAT_EQ(occluderDepthHint(z, {0.5f, 0.0f}, 5.0f, 1.0f), 2.5f);
    EXPECT_FLOAT_EQ(occluderDepthHint(z, {0.5f, 0.5f}, 5.0f, 2.5f), 3.0f);  // (2 + 3 + 4) / 3
    EXPECT_FLOAT_EQ(occluderDepthHint(z, {0.5f, 0.5f}, 5.0f, 3.5f), 3.5f);  // clamped to z_min
}

TEST(LightLevels, LevelZeroOcclusionIsTheMapTest) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int k = 0; k < 2000; ++k) {
        BpReceiver r{};
        r.inside = 1.0f;
        r.position = glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, 2.0f + 3.0f * u(rng));
        r.normal = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, -1.0f));
        r.bias = 0.01f * u(rng);
        glm::ivec2 t(int(512.0f * u(rng)), int(512.0f * u(rng)));
        float z = r.position.z * (0.5f + 0.6f * u(rng));
        EXPECT_EQ(bpLevelSampleOccludes(r, 0, t, z, 512.0f, 0.6f), bpSampleOccludes(r, glm::vec2(t) + 0.5f, z, 512.0f, 0.6f));
    }
    // On a coarse level the bias grows with the texel: a tilted receiver's own min depth over a
    // level-3 texel is not an occluder there, though it is beyond level 0's bias.
    BpReceiver r{};
    r.inside = 1.0f;
    r.position = glm::vec3(0.0f, 0.0f, 4.0f);
    r.normal = glm::normalize(glm::vec3(0.3f, 0.0f, -1.0f));
    r.bias = 0.004f;
    const glm::ivec2 t(255, 256);  // level 3 texel 31: map texels 248..255 around the centre 256
    float zCentre = receiverPlaneDepth(r.normal, r.position, (glm::vec2(t) + 0.5f) * 1.0f, 512.0f, 0.6f);
    float own = zCentre - 0.02f;  // the plane 8 texels further
    EXPECT_TRUE(bpLevelSampleOccludes(r, 0, t, own, 512.0f, 0.6f));
    glm::ivec2 t3(31, 32);
    float zCentre3 = receiverPlaneDepth(r.normal, r.position, (glm::vec2(t3) + 0.5f) * 8.0f, 512.0f, 0.6f);
    EXPECT_FALSE(bpLevelSampleOccludes(r, 3, t3, zCentre3 - 0.02f, 512.0f, 0.6f));
    EXPECT_TRUE(bpLevelSampleOccludes(r, 3, t3, zCentre3 - 0.5f, 512.0f, 0.6f));  // a real occluder still is
}

// The depth_levels atlas (visibility_common.glsl): HSM levels 1 .. top side by side in an N x N layer,
// level k at x = n_1 + ... + n_(k-1), for every map size the parameter table accepts: the offsets are
// the running sum of the level sizes, and the levels neither overlap nor leave the layer.
TEST(LightLevels, AtlasHoldsEveryLevelSideBySide) {
    for (int n = 1; n <= 8192; ++n) {
        int x = 0, top = 1;
        while (hsmLevelSize(top, n) > 1) ++top;  // the HSM's top level: the first 1x1 one
        for (int level = 1; level <= top; ++level) {
            ASSERT_EQ(hsmLevelAtlasX(level, n), x) << "N " << n << " level " << level;
            x += hsmLevelSize(level, n);
            ASSERT_LE(hsmLevelSize(level, n), n) << "N " << n << " level " << level;
        }
        ASSERT_LE(x, n) << "N " << n << ": the levels' widths add up to more than the layer";
    }
    EXPECT_EQ(hsmLevelAtlasX(0, 1024), 0);
    EXPECT_EQ(hsmLevelAtlasX(2, 1024), 512);
    EXPECT_EQ(hsmLevelAtlasX(3, 1024), 768);
}

struct MathCase {
    glm::vec4 kernel, depths, hint, receiver, normal;
    glm::ivec4 ints;
};
struct MathResult {
    glm::vec4 levels, blend;
    glm::ivec4 atlas;
};

class LightLevelsGpu : public testing::GLTest {};

TEST_F(LightLevelsGpu, SharedMathAgreesWithCpu) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<MathCase> cases;
    for (int k = 0; k < 1024; ++k) {
        MathCase c{};
        float w = std::exp2(12.0f * u(rng));
        float tk = k % 7 == 0 ? 16.0f : 2.0f + 30.0f * u(rng);
        float beta = k % 5 == 0 ? 0.0f : 0.2f * u(rng);
        c.kernel = glm::vec4(w, k % 9 == 0 ? 0.0f : w * u(rng), tk, beta);
        c.depths = glm::vec4(1.0f + 5.0f * u(rng), 1.0f + 5.0f * u(rng), k % 3 ? 3.4e38f : 1.0f + 5.0f * u(rng), 1.0f + 5.0f * u(rng));
        c.hint = glm::vec4(u(rng), u(rng), 2.0f + 3.0f * u(rng), 0.5f + 2.0f * u(rng));
        c.receiver = glm::vec4(u(rng) - 0.5f, u(rng) - 0.5f, 2.0f + 3.0f * u(rng), 0.02f * u(rng));
        glm::vec3 n = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, -0.2f - u(rng)));
        int level = k % 6;
        int n0 = 512 >> level;
        c.ints = glm::ivec4(k % 4 == 0 ? 3 : 9, level, int(float(n0) * u(rng)), int(float(n0) * u(rng)));
        c.normal = glm::vec4(n, c.receiver.z * (0.4f + 0.7f * u(rng)));
        cases.push_back(c);
    }
    Buffer in(cases.size() * sizeof(MathCase), cases.data()), out(cases.size() * sizeof(MathResult));
    const ShaderProgram& program = programCache().compute("tests/visibility/light_levels_math.comp");
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.set("count", unsigned(cases.size()));
    program.dispatch(GLuint((cases.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<MathResult> gpu = out.read<MathResult>();
    // Tolerance: the same float operations; the GPU's log2 and division round their own way, a
    // few ulps of values of order 1-10. Occlusion decisions within 1e-4 of the bias are skipped.
    size_t compared = 0, occluding = 0, blended = 0;
    for (size_t k = 0; k < cases.size(); ++k) {
        const MathCase& c = cases[k];
        const MathResult& g = gpu[k];
        int top = c.ints.x;
        float lambda = lightLevelContinuous(c.kernel.y, c.kernel.x, c.kernel.z, top);
        EXPECT_EQ(g.levels.x, float(lightLevelForKernel(c.kernel.x, c.kernel.z, top))) << k;
        EXPECT_NEAR(g.levels.y, lambda, 1e-5f * std::max(1.0f, lambda)) << k;
        float hint = occluderDepthHint(c.depths, glm::vec2(c.hint), c.hint.z, c.hint.w);
        EXPECT_NEAR(g.levels.z, hint, 1e-5f * std::max(1.0f, hint)) << k;
        BpReceiver r{1.0f, glm::vec3(c.receiver), glm::vec3(c.normal), glm::vec2(0.0f), c.receiver.w};
        bool occ = bpLevelSampleOccludes(r, c.ints.y, glm::ivec2(c.ints.z, c.ints.w), c.normal.w, 512.0f, 0.6f);
        float s = float(1 << c.ints.y);
        float zPlane = receiverPlaneDepth(r.normal, r.position, (glm::vec2(c.ints.z, c.ints.w) + 0.5f) * s, 512.0f, 0.6f);
        bool near = std::abs(std::abs(c.normal.w - zPlane) - r.bias * s) < 1e-4f ||
                    std::abs(c.normal.w - (r.position.z - r.bias * s)) < 1e-4f;
        if (!near) EXPECT_EQ(g.levels.w, occ ? 1.0f : 0.0f) << k;
        occluding += occ;
        glm::vec3 b = lightLevelBlend(lambda, c.kernel.w, top);
        float d = lambda - std::floor(lambda);
        bool edge = std::abs(d - c.kernel.w) < 1e-4f || std::abs(1.0f - d - c.kernel.w) < 1e-4f || d < 1e-4f || d > 1.0f - 1e-4f;
        if (!edge) {
            EXPECT_EQ(g.blend.x, b.x) << k;
            EXPECT_EQ(g.blend.y, b.y) << k;
            EXPECT_NEAR(g.blend.z, b.z, 1e-3f) << k;
        }
        EXPECT_EQ(g.atlas.x, hsmLevelAtlasX(c.ints.y, 7 * c.ints.z + 1)) << k;
        EXPECT_EQ(g.atlas.y, hsmLevelAtlasX(c.ints.y, 8192)) << k;
        blended += b.z > 0.0f;
        ++compared;
    }
    EXPECT_EQ(compared, cases.size());
    EXPECT_GT(occluding, 100u);  // both outcomes are reached
    EXPECT_LT(occluding, cases.size() - 100u);
    EXPECT_GT(blended, 20u);
}

}  // namespace
}  // namespace shadowlab
