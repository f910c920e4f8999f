// The back-projection math (shaders/shared/backprojection.glsl) gives the same answers on the GPU
// as in C++, on a grid of inputs including the singular ones (edges through the light centre, on its
// border, of zero length): one source of truth, checked on both compilers (STYLE.md 4).
#include <gtest/gtest.h>

#include <random>

#include "gl/util.h"
#include "graph/renderer.h"
#include "scene/scene.h"
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

// The production HSM (shaders/backprojection/hsm_first.frag and hsm.comp, run by ssm-contour's hsm pass) against a CPU
// min/max pyramid built from the read-back shadow map by the paper's rule (each texel the min and
// max of the 2x2 below, widened on an odd level's last row and column; the no-caster marker FLT_MAX
// kept): equal texel for texel, at an odd and a power-of-two size. A pyramid built one level off,
// from the wrong source level or with the wrong footprint, differs (min and max are exact in float).
TEST_F(BackprojectionGpu, ProductionHsmEqualsCpuMinMaxOfTheShadowMap) {
    const Scene scene = loadScene("plant");
    for (const char* smSize : {"37", "64"}) {
        SCOPED_TRACE(std::string("sm_size ") + smSize);
        RenderOptions options;
        options.width = options.height = 32;
        options.technique = "ssm-contour";
        options.sets = {{"sm_size", smSize}};
        Renderer renderer(scene, options);
        renderer.renderFrame(0, {"visibility"});
        const Resource* mapResource = renderer.pool().find("L0/shadow_map");
        const Resource* hsmResource = renderer.pool().find("L0/hsm");
        ASSERT_TRUE(mapResource && hsmResource);
        const Image map = readTextureLevel(mapResource->texture, 0);
        const int size = map.width;
        ASSERT_EQ(size, std::stoi(smSize));
        // Level 0 in GL texel coordinates (read-back rows run from the top).
        std::vector<glm::vec2> below(size_t(size) * size);
        size_t noCaster = 0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const float z = map.at(x, size - 1 - y);
                below[size_t(y) * size + x] = glm::vec2(z);
                noCaster += z > 1e30f;
            }
        EXPECT_GT(noCaster, 0u);  // the floor casts no shadow: the marker is in the map
        int belowSize = size;
        const int levels = hsmResource->texture.levels();
        ASSERT_GE(levels, 3);
        for (int level = 1; level <= levels; ++level) {
            const int n = shared::hsmLevelSize(level, size);
            std::vector<glm::vec2> cpu(size_t(n) * n);
            for (int py = 0; py < n; ++py)
                for (int px = 0; px < n; ++px) {
                    glm::ivec2 lo(2 * px, 2 * py), hi(std::min(2 * px + 1, belowSize - 1), std::min(2 * py + 1, belowSize - 1));
                    if (px == n - 1) hi.x = belowSize - 1;
                    if (py == n - 1) hi.y = belowSize - 1;
                    glm::vec2 range(3.4e38f, -3.4e38f);
                    for (int y = lo.y; y <= hi.y; ++y)
                        for (int x = lo.x; x <= hi.x; ++x) {
                            const glm::vec2 v = below[size_t(y) * belowSize + x];
                            range = glm::vec2(std::min(range.x, v.x), std::max(range.y, v.y));
                        }
                    cpu[size_t(py) * n + px] = range;
                }
            const Image gpu = readTextureLevel(hsmResource->texture, level - 1);
            ASSERT_EQ(gpu.width, n) << "level " << level;
            size_t bad = 0;
            for (int py = 0; py < n; ++py)
                for (int px = 0; px < n; ++px) {
                    const glm::vec2 c = cpu[size_t(py) * n + px];
                    const float gmin = gpu.at(px, n - 1 - py, 0), gmax = gpu.at(px, n - 1 - py, 1);
                    if ((gmin != c.x || gmax != c.y) && bad++ < 5)
                        ADD_FAILURE() << "level " << level << " texel " << px << "," << py << ": gpu (" << gmin << ", "
                                      << gmax << ") cpu (" << c.x << ", " << c.y << ")";
                }
            EXPECT_EQ(bad, 0u) << "level " << level;
            below = cpu;
            belowSize = n;
        }
    }
}

}  // namespace
}  // namespace shadowlab
