// The shared math (shaders/shared/*.glsl) gives the same answers on the GPU as in C++, on a grid of
// inputs: one source of truth, checked on both compilers (STYLE.md 4).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/util.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

class SharedMathGpu : public testing::GLTest {};

TEST_F(SharedMathGpu, MatchesCpuOnAGrid) {
    constexpr int n = 64;
    Texture square(n, n, GL_RGBA32F), sample(n, n, GL_RGBA32F), project(n, n, GL_RGBA32F), hash(n, n, GL_R32UI);
    Framebuffer fbo({&square, &sample, &project, &hash}, nullptr);
    glm::mat4 view = glm::lookAt(glm::vec3(0.3f, 4.0f, 0.1f), glm::vec3(0.3f, 3.0f, 0.1f), glm::vec3(0, 0, -1));
    glm::mat4 clip = glm::perspective(glm::radians(120.0f), 1.0f, 0.1f, 10.0f);
    ShaderProgram program("common/fullscreen.vert", "tests/shared_math.frag");
    program.use();
    program.set("lightViewFromWorld", view);
    program.set("lightClipFromView", clip);
    fbo.bind(n, n);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    drawFullscreenTriangle();
    auto read = [&](const Texture& t) {
        std::vector<float> v(size_t(n) * n * 4);
        glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(v.size() * 4), v.data());
        return v;
    };
    std::vector<float> sq = read(square), sa = read(sample), pr = read(project);
    std::vector<uint32_t> hs(size_t(n) * n);
    glGetTextureImage(hash.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(hs.size() * 4), hs.data());

    // Tolerances: the same float operations, but the GPU compiler may fuse multiply-adds and use
    // its own sqrt/division/cos rounding: a few ulps of values of order 1.
    const float tol = 2e-5f;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            size_t i = size_t(y) * n + x;
            glm::vec3 p(-3.0f + 6.0f * float(x) / 63.0f, 0.0f, -3.0f + 6.0f * float(y) / 63.0f);
            using namespace shared;
            EXPECT_NEAR(sq[i * 4 + 0], squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f), tol) << x << "," << y;
            EXPECT_EQ(sq[i * 4 + 1], squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 0.0f)) << x << "," << y;
            EXPECT_NEAR(sq[i * 4 + 2], squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 2.5f), tol);
            EXPECT_NEAR(sq[i * 4 + 3], squareOccluderVisibility(p, 0.25f, 1.0f, 4.0f, 1e-3f), 1e-3f);
            glm::vec3 s = stratifiedSample(uint(x), uint(y + 1), 7u);
            EXPECT_NEAR(sa[i * 4 + 0], s.x, tol);
            EXPECT_NEAR(sa[i * 4 + 1], s.y, tol);
            EXPECT_NEAR(sa[i * 4 + 2], s.z, tol);
            EXPECT_NEAR(sa[i * 4 + 3], concentricSquareToDisk(glm::vec2(s.x, s.y)).x, 1e-4f);
            glm::vec4 c = shadowMapCoord(view, clip, p + glm::vec3(0.0f, float(x % 3), 0.0f));
            for (int k = 0; k < 4; ++k) EXPECT_NEAR(pr[i * 4 + k], c[k], 1e-4f * std::max(1.0f, std::abs(c[k])));
            EXPECT_EQ(hs[i], pcgHash(uint(x + 64 * y)));
        }
}

}  // namespace
}  // namespace shadowlab
