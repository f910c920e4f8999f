// The back-projection math (shaders/shared/backprojection.glsl) gives the same answers on the GPU
// as in C++, on a grid of inputs including the singular ones (edges through the light centre, on its
// border, of zero length): one source of truth, checked on both compilers (STYLE.md 4).
#include <gtest/gtest.h>

#include <random>

#include "gl/util.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

class BackprojectionGpu : public testing::GLTest {};

TEST_F(BackprojectionGpu, SharedMathMatchesCpuOnAGrid) {
    constexpr int n = 64;
    // Edge inputs: random ones in and around the light, plus exact singular cases every few pixels.
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-1.6f, 1.6f);
    Image edgeInput(n, n, 4);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            glm::vec4 e(u(rng), u(rng), u(rng), u(rng));
            switch ((x + 3 * y) % 11) {
                case 0: e = glm::vec4(0.5f, 0.0f, -0.7f, 0.0f); break;   // through the centre
                case 1: e = glm::vec4(1.0f, -0.5f, 1.0f, 0.75f); break;  // on the square's border
                case 2: e = glm::vec4(e.x, e.y, e.x, e.y); break;        // zero length
                case 3: e = glm::vec4(0.0f, 0.0f, e.z, e.w); break;      // from the centre
                case 4: e = glm::vec4(e.x, e.y, -e.x, -e.y); break;      // through the centre, any direction
                default: break;
            }
            for (int k = 0; k < 4; ++k) edgeInput.at(x, n - 1 - y, k) = e[k];  // top-first Image, GL row y
        }
    Texture edges = Texture::create2D(n, n, Format::RGBA32F);
    uploadTexture(edges, 0, 0, edgeInput);
    Texture rule(n, n, GL_RGBA32F), area(n, n, GL_RGBA32F), project(n, n, GL_RGBA32F), sweep(n, n, GL_RGBA32F);
    Framebuffer fbo({&rule, &area, &project, &sweep}, nullptr);
    ShaderProgram program("common/fullscreen.vert", "tests/backprojection_math.frag");
    program.use();
    glBindTextureUnit(0, edges.id());
    program.set("edges", 0);
    fbo.bind(n, n);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    drawFullscreenTriangle();
    auto read = [&](const Texture& t) {
        std::vector<float> v(size_t(n) * n * 4);
        glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(v.size() * 4), v.data());
        return v;
    };
    std::vector<float> ru = read(rule), ar = read(area), pr = read(project), sw = read(sweep);

    // Tolerances: the same float operations, but the GPU compiler may fuse multiply-adds and use its
    // own sqrt/atan/division rounding: a few ulps of values of order 1, more through the divisions of
    // the back-projection (values up to ~100) and the disk's square root near tangency.
    using namespace shared;
    int singular = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            SCOPED_TRACE(std::to_string(x) + "," + std::to_string(y));
            size_t i = (size_t(y) * n + x) * 4;
            int mask = x % 16, which = (x / 16) % 2;
            float t = -1.0f + 2.0f * float(y % 9) / 8.0f;
            glm::vec4 want = which < contourRule(mask).x ? contourEdge(mask, t, which) : glm::vec4(-9.0f);
            for (int k = 0; k < 4; ++k) ASSERT_EQ(ru[i + k], want[k]);  // exact: halves and quarters
            glm::vec4 e(edgeInput.at(x, n - 1 - y, 0), edgeInput.at(x, n - 1 - y, 1), edgeInput.at(x, n - 1 - y, 2),
                        edgeInput.at(x, n - 1 - y, 3));
            glm::vec2 a(e.x, e.y), b(e.z, e.w);
            if (cross2(a, b) == 0.0f) ++singular;
            glm::vec4 rect(std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y));
            bool inside = contourCentreOccluded(mask, t, cross2(a, b), cross2(b, a + glm::vec2(0.1f, 0.0f)));
            EXPECT_NEAR(ar[i + 0], edgeOccludedArea(BP_LIGHT_SQUARE, a, b), 2e-5f);
            EXPECT_NEAR(ar[i + 1], edgeOccludedArea(BP_LIGHT_DISK, a, b), 5e-5f);
            EXPECT_NEAR(ar[i + 2], rectOccludedArea(BP_LIGHT_DISK, rect), 5e-5f);
            EXPECT_EQ(ar[i + 3], inside ? 1.0f : 0.0f);
            glm::vec3 receiver(a.x, a.y, 3.0f + b.x);
            glm::vec2 texel(float(x) * 4.0f + 0.5f, float(y) * 4.0f + 0.25f);
            glm::vec2 l = backprojectToLight(receiver, texel, 1.0f + 0.5f * b.y, 256.0f, 0.75f, 0.5f);
            glm::vec3 nrm = receiverNormalTowardLight(glm::normalize(glm::vec3(b.x, b.y, 1.0f)), receiver);
            float k = hsmKernelTexels(1.0f, 256.0f, 0.75f, 1.0f + 0.5f * b.y, receiver.z);
            float zPlane = receiverPlaneDepth(nrm, receiver, texel, 256.0f, 0.75f);
            EXPECT_NEAR(pr[i + 0], l.x, 1e-5f * std::max(1.0f, std::abs(l.x)));
            EXPECT_NEAR(pr[i + 1], l.y, 1e-5f * std::max(1.0f, std::abs(l.y)));
            EXPECT_NEAR(pr[i + 2], k, 1e-5f * std::max(1.0f, std::abs(k)));
            // Near-grazing rays make n . d a small difference of order-1 terms: 1e-4 relative.
            EXPECT_NEAR(pr[i + 3], zPlane, 1e-4f * std::max(1.0f, std::abs(zPlane)));
            glm::vec2 clip = clipSegmentToDisk(a, b);
            EXPECT_NEAR(sw[i + 0], radialSweep(BP_LIGHT_SQUARE, a, b, edgeTurn(a, b)), 2e-5f);
            EXPECT_NEAR(sw[i + 1], radialSweep(BP_LIGHT_DISK, a, b, edgeTurn(a, b)), 2e-5f);
            if (clip.x <= clip.y) {
                EXPECT_NEAR(sw[i + 2], clip.x, 5e-5f);
                EXPECT_NEAR(sw[i + 3], clip.y, 5e-5f);
            } else {
                EXPECT_GT(sw[i + 2], sw[i + 3]);
            }
        }
    EXPECT_GT(singular, 500);  // the singular cases were exercised
}

}  // namespace
}  // namespace shadowlab
