// Pull-push reconstruction and the discontinuity buffer of guennebaud2007 sec. 5.2
// (techniques/core/visibility/pull_push.h, discontinuities.h): the CPU mirrors on cases with known
// answers, the GPU passes against the CPU mirrors, and the pyramids' level convention.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "error.h"
#include "gl/buffer.h"
#include "graph/renderer.h"
#include "graph/resources.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"
#include "support/real_meshes.h"
#include "visibility/discontinuities.h"
#include "visibility/pull_push.h"

namespace shadowlab {
namespace {

// A (v, w) image with v = f(x, y) where sampled(x, y), w = 1 there and 0 (v = 0) elsewhere.
template <class F, class S>
Image sparse(int w, int h, F f, S sampled) {
    Image vw(w, h, 2);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (sampled(x, y)) {
                vw.at(x, y, 0) = f(x, y);
                vw.at(x, y, 1) = 1.0f;
            }
    return vw;
}

// Random visibilities, ~`fraction` of the pixels computed (w = 1), a few with a partial weight.
Image randomSparse(int w, int h, float fraction, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Image vw(w, h, 2);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float r = u(rng);
            vw.at(x, y, 0) = u(rng);
            vw.at(x, y, 1) = r < fraction ? 1.0f : r < fraction + 0.05f ? u(rng) : 0.0f;
        }
    return vw;
}

// ---- pull-push, CPU --------------------------------------------------------------------------------

TEST(PullPushCpu, ConstantStaysConstant) {
    for (auto [w, h] : {std::pair{1, 1}, {2, 1}, {37, 23}, {64, 64}, {200, 131}}) {
        Image vw = randomSparse(w, h, 0.1f, 7u);
        for (size_t i = 0; i < vw.pixelCount(); ++i) vw.data[i * 2] = 0.37f;
        vw.at(0, 0, 1) = 1.0f;  // at least one sample
        Image out = pullPushCpu(vw);
        for (size_t i = 0; i < out.pixelCount(); ++i) ASSERT_NEAR(out.data[i], 0.37f, 1e-6f) << w << "x" << h << " pixel " << i;
    }
}

TEST(PullPushCpu, FullySampledBufferIsUnchangedExactly) {
    Image vw = randomSparse(37, 23, 1.0f, 3u);
    Image out = pullPushCpu(vw);
    for (size_t i = 0; i < out.pixelCount(); ++i) ASSERT_EQ(out.data[i], vw.data[i * 2]) << i;
}

TEST(PullPushCpu, OneSampleFillsEverythingWithItsValue) {
    for (auto [x, y] : {std::pair{0, 0}, {36, 22}, {17, 5}}) {
        Image vw(37, 23, 2);
        vw.at(x, y, 0) = 0.8f;
        vw.at(x, y, 1) = 1.0f;
        Image out = pullPushCpu(vw);
        for (size_t i = 0; i < out.pixelCount(); ++i) ASSERT_EQ(out.data[i], 0.8f) << "sample at " << x << "," << y << " pixel " << i;
    }
}

TEST(PullPushCpu, NoSampleGivesZero) {
    Image out = pullPushCpu(Image(9, 5, 2));
    for (float v : out.data) EXPECT_EQ(v, 0.0f);
}

// Every step is a convex combination (weighted means, bilinear blends, w v + (1 - w) c), so for a
// linear f the reconstruction at pixel p is f(p + e) with e the offset of the mean position of
// the samples it blends: the error is |df/dx| |e_x| + |df/dy| |e_y|.
//  - Every 4th pixel (both axes, a 64 x 64 frame, samples at 0, 4, ..., 60): level 1 holds a sample
//    in one texel of four, 0.5 px before that texel's centre; level 2 and above are complete and each
//    texel's samples sit 1.5 px before its centre (one sample per 4 x 4 block, at its first pixel).
//    The push blends these, so |e| <= 1.5 px per axis away from the border. At the far border the
//    clamped bilinear repeats the last coarse texel: the pixels 61-63 after the last sample column
//    get e up to 63 - 60 = 3 px. Tolerances: 1.5 px of slope inside, 3 px everywhere.
//  - Random 10%: a 4 x 4 block holds no sample with probability 0.9^16 = 0.19, an 8 x 8 block with
//    0.9^64 = 1e-3, so gaps are filled from levels 2-3, whose texels cover 4-8 px: the mean offset
//    stays within half of it (2 px) on average; isolated empty 8 x 8 blocks borrow from 16 x 16 texels
//    (8 px). Tolerances: mean |e| <= 2 px, max |e| <= 8 px of slope.
TEST(PullPushCpu, LinearRampOnARegularGridIsReconstructed) {
    const float a = 0.01f, b = 0.005f;  // slopes per pixel of v = 0.1 + a x + b y (in [0.1, 1.05])
    auto f = [&](int x, int y) { return 0.1f + a * (float(x) + 0.5f) + b * (float(y) + 0.5f); };
    Image out = pullPushCpu(sparse(64, 64, f, [](int x, int y) { return x % 4 == 0 && y % 4 == 0; }));
    float inside = 0.0f, all = 0.0f;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            float e = std::abs(out.at(x, y) - f(x, y));
            all = std::max(all, e);
            if (x < 60 && y < 60) inside = std::max(inside, e);
        }
    EXPECT_LE(inside, 1.5f * (a + b) + 1e-6f);
    EXPECT_LE(all, 3.0f * (a + b) + 1e-6f);
    RecordProperty("max_error_inside", std::to_string(inside));
    RecordProperty("max_error", std::to_string(all));
    std::printf("regular grid: max error inside %.6f (bound %.6f), everywhere %.6f (bound %.6f)\n", inside,
                1.5f * (a + b), all, 3.0f * (a + b));
}

TEST(PullPushCpu, LinearRampOnRandomTenPercentIsReconstructed) {
    const float a = 0.004f, b = 0.006f;
    auto f = [&](int x, int y) { return 0.05f + a * (float(x) + 0.5f) + b * (float(y) + 0.5f); };
    std::mt19937 rng(11u);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Image vw = sparse(128, 96, f, [&](int, int) { return u(rng) < 0.1f; });
    Image out = pullPushCpu(vw);
    double sum = 0.0;
    float worst = 0.0f;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 128; ++x) {
            float e = std::abs(out.at(x, y) - f(x, y));
            if (vw.at(x, y, 1) == 1.0f) ASSERT_EQ(out.at(x, y), vw.at(x, y, 0));  // computed pixels kept
            sum += e;
            worst = std::max(worst, e);
        }
    double mean = sum / (128.0 * 96.0);
    EXPECT_LE(mean, 2.0 * (a + b));
    EXPECT_LE(worst, 8.0f * (a + b));
    std::printf("random 10%%: mean error %.6f (bound %.6f), max %.6f (bound %.6f)\n", mean, 2.0 * (a + b), worst,
                8.0f * (a + b));
}

// pull_push.h: level k >= 1 is ceil(n / 2) >> (k - 1) (at least 1) down to 1x1 in both mirrors,
// and the pass's pyramid declaration allocates exactly those levels.
TEST(PullPushCpu, PyramidLevelsFollowTheConvention) {
    for (auto [w, h] : {std::pair{1, 1}, {2, 1}, {37, 23}, {64, 64}, {200, 131}}) {
        std::vector<Image> pull, push;
        pullPushCpu(randomSparse(w, h, 0.2f, 5u), &pull, &push);
        ASSERT_EQ(pull.size(), size_t(fullMipLevels((w + 1) / 2, (h + 1) / 2))) << w << "x" << h;
        ASSERT_EQ(push.size(), pull.size());
        for (size_t m = 0; m < pull.size(); ++m) {
            EXPECT_EQ(pull[m].width, shared::pullPushLevelSize(int(m) + 1, w));
            EXPECT_EQ(pull[m].height, shared::pullPushLevelSize(int(m) + 1, h));
            EXPECT_EQ(pull[m].width, std::max(1, ((w + 1) / 2) >> m));
            EXPECT_EQ(push[m].width, pull[m].width);
            EXPECT_EQ(push[m].height, pull[m].height);
            EXPECT_EQ(pull[m].channels, 2);
        }
        EXPECT_EQ(pull.back().width, 1);
        EXPECT_EQ(pull.back().height, 1);
    }
    EXPECT_EQ(shared::pullPushLevelSize(0, 200), 200);
    EXPECT_EQ(shared::pullPushLevelSize(1, 200), 100);
    EXPECT_EQ(shared::pullPushLevelSize(1, 131), 66);
    EXPECT_EQ(shared::pullPushLevelSize(2, 131), 33);
    EXPECT_EQ(shared::pullPushLevelSize(3, 131), 16);
    EXPECT_EQ(shared::pullPushLevelSize(7, 131), 1);
    EXPECT_EQ(shared::pullPushLevelSize(8, 131), 1);
}

// Every fine texel is counted by exactly one coarse texel, for every size pair of the chain.
TEST(PullPushCpu, PullBlocksPartitionTheFineLevel) {
    for (int n0 : {1, 2, 3, 5, 23, 37, 131, 200}) {
        for (int k = 0; shared::pullPushLevelSize(k, n0) > 1 || k == 0; ++k) {
            int fine = shared::pullPushLevelSize(k, n0), coarse = shared::pullPushLevelSize(k + 1, n0);
            std::vector<int> count(size_t(fine), 0);
            for (int p = 0; p < coarse; ++p) {
                glm::ivec4 b = shared::pullBlock(glm::ivec2(p, 0), glm::ivec2(coarse, 1), glm::ivec2(fine, 1));
                for (int x = b.x; x <= b.z; ++x) count[size_t(x)] += 1;
            }
            for (int x = 0; x < fine; ++x) ASSERT_EQ(count[size_t(x)], 1) << n0 << " level " << k << " texel " << x;
        }
    }
}

TEST(PullPushDescriptor, DeclaresThePyramidsAndTheOutput) {
    PassDesc p = pullPushPass("sparse_visibility", "visibility", "screen_spacing > 1");
    ASSERT_EQ(p.creates.size(), 3u);
    EXPECT_EQ(p.reads, std::vector<std::string>{"sparse_visibility"});
    EXPECT_TRUE(p.wholeFrame);
    EXPECT_TRUE(p.soft);
    for (int i = 0; i < 2; ++i) {
        EXPECT_EQ(p.creates[size_t(i)].kind, ResourceKind::Pyramid);
        EXPECT_EQ(p.creates[size_t(i)].format, Format::RG32F);
        EXPECT_EQ(p.creates[size_t(i)].levels, 0);
        EXPECT_EQ(p.creates[size_t(i)].size.kind, SizeRule::Kind::Frame);
        EXPECT_EQ(p.creates[size_t(i)].size.scaleDown, 2);
    }
    EXPECT_EQ(p.creates[0].name, "pull_push.pull");
    EXPECT_EQ(p.creates[1].name, "pull_push.push");
    EXPECT_EQ(p.creates[2].name, "visibility");
    EXPECT_EQ(p.creates[2].format, Format::R32F);
    for (const ResourceDesc& r : p.creates) EXPECT_EQ(r.appliesWhen, "screen_spacing > 1");
    std::vector<InternalDesc> internals = pullPushInternals();
    ASSERT_EQ(internals.size(), 2u);
    for (const InternalDesc& i : internals) {
        EXPECT_EQ(i.kind, InternalDesc::Kind::Pyramid);
        EXPECT_EQ(i.channels, (std::vector<std::string>{"visibility", "weight"}));
        EXPECT_EQ(i.name, i.resource);
        EXPECT_FALSE(i.doc.empty());
    }
    EXPECT_EQ(internals[0].resource, "pull_push.pull");
    EXPECT_EQ(internals[1].resource, "pull_push.push");
}

// ---- pull-push, GPU ------------------------------------------------------------------------------

class PullPushGpu : public testing::GLTest {};

// The pyramids as the pass allocates them (ResourcePool, the pass's own declarations).
struct PullPushTextures {
    ResourcePool pool;
    Texture input, output;
    Texture* pull = nullptr;
    Texture* push = nullptr;
    PullPushTextures(int w, int h) {
        input = Texture::create2D(w, h, Format::RG32F);
        output = Texture::create2D(w, h, Format::R32F);
        PassDesc p = pullPushPass("in", "out", "");
        pull = &pool.ensure("frame/pull_push.pull", p.creates[0], (w + 1) / 2, (h + 1) / 2).texture;
        push = &pool.ensure("frame/pull_push.push", p.creates[1], (w + 1) / 2, (h + 1) / 2).texture;
    }
};

TEST_F(PullPushGpu, MatchesCpuOnRandomSparseBuffers) {
    float worst = 0.0f;
    for (auto [w, h] : {std::pair{1, 1}, {2, 1}, {37, 23}, {64, 64}, {200, 131}}) {
        Image vw = randomSparse(w, h, 0.12f, unsigned(w * 1000 + h));
        PullPushTextures t(w, h);
        uploadTexture(t.input, 0, 0, vw);
        PullPush().run(programCache(), t.input, *t.pull, *t.push, t.output);
        std::vector<Image> pull, push;
        Image cpu = pullPushCpu(vw, &pull, &push);
        Image gpu = readTexture(t.output, 1);
        for (size_t i = 0; i < cpu.pixelCount(); ++i) {
            ASSERT_NEAR(gpu.data[i], cpu.data[i], 1e-5f) << w << "x" << h << " pixel " << i;
            worst = std::max(worst, std::abs(gpu.data[i] - cpu.data[i]));
            if (vw.data[i * 2 + 1] == 1.0f) ASSERT_EQ(gpu.data[i], vw.data[i * 2]) << "a computed pixel changed";
        }
        ASSERT_EQ(t.pull->levels(), int(pull.size()));
        for (int m = 0; m < t.pull->levels(); ++m) {
            Image gp = readTextureLevel(*t.pull, m), gq = readTextureLevel(*t.push, m);
            ASSERT_EQ(gp.width, pull[size_t(m)].width);
            ASSERT_EQ(gp.height, pull[size_t(m)].height);
            for (size_t i = 0; i < pull[size_t(m)].pixelCount(); ++i)
                for (int c = 0; c < 2; ++c) {
                    ASSERT_NEAR(gp.data[i * gp.channels + c], pull[size_t(m)].data[i * 2 + c], 1e-5f) << "pull mip " << m;
                    ASSERT_NEAR(gq.data[i * gq.channels + c], push[size_t(m)].data[i * 2 + c], 1e-5f) << "push mip " << m;
                    worst = std::max(worst, std::abs(gq.data[i * gq.channels + c] - push[size_t(m)].data[i * 2 + c]));
                }
        }
    }
    std::printf("GPU vs CPU: largest difference %.3g\n", worst);
}

// The pass through its own declaration: resources allocated as the renderer does (frame size,
// SizeRule::frame(2)), accessed through a PassContext that allows only what the pass declares.
TEST_F(PullPushGpu, PassRunsThroughItsDeclaration) {
    const int w = 45, h = 30;
    PassDesc desc = pullPushPass("sparse", "filled", "");
    ResourcePool pool;
    Texture& sparseTexture = pool.ensure("frame/sparse", ResourceDesc::texture("sparse", Format::RG32F, SizeRule::frame(), "input"), w, h).texture;
    for (const ResourceDesc& r : desc.creates) {
        int s = r.size.scaleDown;
        pool.ensure("frame/" + r.name, r, (w + s - 1) / s, (h + s - 1) / s);
    }
    Image vw = randomSparse(w, h, 0.1f, 99u);
    uploadTexture(sparseTexture, 0, 0, vw);
    FrameState frame;
    frame.programs = &programCache();
    frame.width = w;
    frame.height = h;
    std::set<std::string> declared(desc.reads.begin(), desc.reads.end());
    for (const std::string& name : desc.writes()) declared.insert(name);
    PassContext ctx(frame, nullptr, pool, "test/pull_push", declared);
    desc.create()->execute(ctx);
    std::vector<Image> pull, push;
    Image cpu = pullPushCpu(vw, &pull, &push);
    Image gpu = readTexture(pool.find("frame/filled")->texture, 1);
    for (size_t i = 0; i < cpu.pixelCount(); ++i) ASSERT_NEAR(gpu.data[i], cpu.data[i], 1e-5f) << i;
    const Texture& pushTexture = pool.find("frame/pull_push.push")->texture;
    ASSERT_EQ(pushTexture.levels(), int(push.size()));
    Image top = readTextureLevel(pushTexture, pushTexture.levels() - 1);
    EXPECT_NEAR(top.data[0], push.back().data[0], 1e-5f);
}

TEST_F(PullPushGpu, RefusesPyramidsOfAnotherSize) {
    PullPushTextures t(37, 23);
    Texture wrong = Texture::create2D(19, 12, Format::RG32F, 2);
    EXPECT_THROW(PullPush().run(programCache(), t.input, wrong, *t.push, t.output), InternalError);
    Texture r32 = Texture::create2D(37, 23, Format::R32F);
    EXPECT_THROW(PullPush().run(programCache(), r32, *t.pull, *t.push, t.output), InternalError);
}

// ---- the shared functions, GPU against C++ ---------------------------------------------------------

struct MathCase {
    glm::ivec4 texel, sizes;
    glm::vec4 values, corners, position, normal, above, row, below;
};
struct MathResult {
    glm::ivec4 block, taps, ints;
    glm::vec4 pull, push, blend, edges;
};
static_assert(sizeof(MathCase) == 9 * 16 && sizeof(MathResult) == 7 * 16, "std430 layout of tests/visibility/pull_push_discontinuity_math.comp");

class PullPushSharedMathGpu : public testing::GLTest {};

// Every function of pull_push.glsl and discontinuity.glsl, through
// shaders/tests/visibility/pull_push_discontinuity_math.comp, against the same source compiled as C++.
TEST_F(PullPushSharedMathGpu, AgreesWithCpu) {
    using namespace shared;
    std::mt19937 rng(21u);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<MathCase> cases;
    for (int n0 : {1, 2, 3, 23, 37, 131, 200})
        for (int level = 0; level < 9; ++level) {
            const int fineN = pullPushLevelSize(level, n0), coarseN = pullPushLevelSize(level + 1, n0);
            for (int x : {0, 1, coarseN - 1, fineN - 1, fineN / 2}) {
                MathCase c{};
                c.texel = glm::ivec4(std::max(x, 0), std::max(fineN - 1 - x, 0), coarseN, std::max(1, coarseN - 1));
                c.sizes = glm::ivec4(fineN, std::max(1, fineN - 1), level, n0);
                float w = cases.size() % 4 == 0 ? 0.0f : cases.size() % 4 == 1 ? 1.0f : u(rng);
                c.values = glm::vec4(u(rng), w, cases.size() % 3 == 0 ? 0.0f : 3.0f * u(rng), cases.size() % 3 == 0 ? 0.0f : 2.5f * u(rng));
                c.corners = glm::vec4(u(rng), u(rng), u(rng), u(rng));
                c.position = glm::vec4(4.0f * u(rng) - 2.0f, 2.0f * u(rng), 4.0f * u(rng) - 2.0f, 1.0f + 9.0f * u(rng));
                c.normal = glm::vec4(u(rng) - 0.5f, u(rng), u(rng) - 0.5f, u(rng));
                if (cases.size() % 5 == 0) c.normal = glm::vec4(0.0f, 0.0f, 1.0f, 0.0f);  // grazing or facing, per the camera
                c.above = glm::vec4(5.0f + u(rng), 5.0f + u(rng), 5.0f + u(rng), 0.03f);
                c.row = glm::vec4(5.0f + u(rng), 5.0f + u(rng), 5.0f + u(rng), 0.5f);
                c.below = glm::vec4(5.0f + u(rng), 5.0f + u(rng), 5.0f + u(rng), 0.06f * u(rng));
                c.texel.w = int(cases.size() % 10);  // covered pixels 0 .. 9
                cases.push_back(c);
            }
        }
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 5, 7), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    Buffer in(cases.size() * sizeof(MathCase), cases.data()), out(cases.size() * sizeof(MathResult));
    const ShaderProgram& program = programCache().compute("tests/visibility/pull_push_discontinuity_math.comp");
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.set("count", unsigned(cases.size()));
    program.set("viewFromWorld", view);
    program.dispatch(GLuint((cases.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<MathResult> gpu = out.read<MathResult>();
    // Tolerance: the same float operations; the GPU may fuse multiply-adds and round its own
    // division, sqrt and normalize: a few ulps of values of order 1 to 10.
    const float tol = 1e-5f;
    auto near4 = [&](glm::vec4 a, glm::vec4 b, size_t k, const char* what) {
        for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], tol * std::max(1.0f, std::abs(b[i]))) << what << "[" << i << "] case " << k;
    };
    for (size_t k = 0; k < cases.size(); ++k) {
        const MathCase& c = cases[k];
        const MathResult& r = gpu[k];
        glm::ivec2 p(c.texel.x, c.texel.y), coarse(c.texel.z, c.texel.w), fine(c.sizes.x, c.sizes.y);
        EXPECT_EQ(r.block, pullBlock(p, coarse, fine)) << k;
        EXPECT_EQ(r.taps, pushTaps(p, coarse)) << k;
        glm::ivec2 range = dilationRange(p.x, c.texel.z, c.sizes.w);
        EXPECT_EQ(r.ints, glm::ivec4(pullPushLevelSize(c.sizes.z, c.sizes.w), range.x, range.y,
                                     int(coverageDiscontinuity(c.texel.w)))) << k;
        glm::vec2 values(c.values.x, c.values.y), sums(c.values.z, c.values.w);
        near4(r.pull, glm::vec4(pullAccumulate(sums, values), pullResult(sums)), k, "pull");
        glm::vec2 f = pushFractions(p, coarse);
        near4(r.push, glm::vec4(pushCoarseCoordinate(p.x, coarse.x), f, pushBilinear(c.corners.x, c.corners.y, c.corners.z, c.corners.w, f)), k, "push");
        glm::vec3 above(c.above), row(c.row), below(c.below), position(c.position), normal(c.normal);
        glm::vec2 g = sobelGradient(above, row, below), g2 = sobelGradient(row, below, above);
        near4(r.blend, glm::vec4(pushBlend(values, c.corners.x), cameraDepth(view, position), cosIncidence(view, position, normal),
                                 relativeDepthEdge(g, c.position.w, c.normal.w)), k, "blend");
        near4(r.edges, glm::vec4(g, normalEdge(g, g2, values), discontinuityMark(c.below.w, c.values.y, c.above.w, c.row.w)), k, "edges");
        if (c.values.y == 1.0f) EXPECT_EQ(r.blend.x, c.values.x) << "pushBlend keeps a weight-1 texel exactly, case " << k;
    }
}

// ---- discontinuity buffer ---------------------------------------------------------------------------

// A synthetic G-buffer seen by a camera at the origin looking down -z (viewFromWorld = identity),
// pixel (x, y) on the ray d = (0.01 (x - w / 2 + 0.5), 0.01 (y - h / 2 + 0.5), -1) (0.01 rad per
// pixel), at camera depth depth(x, y) (the point d depth), with normal normal(x, y); background
// where depth <= 0.
struct SyntheticGBuffer {
    Image position, normal;
    template <class D, class N>
    SyntheticGBuffer(int w, int h, D depth, N normalAt) : position(w, h, 4), normal(w, h, 4) {
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float z = depth(x, y);
                glm::vec3 n = normalAt(x, y);
                if (z > 0.0f) {
                    glm::vec3 p = ray(w, h, x, y) * z;
                    for (int c = 0; c < 3; ++c) position.at(x, y, c) = p[c];
                    position.at(x, y, 3) = 1.0f;
                }
                for (int c = 0; c < 3; ++c) normal.at(x, y, c) = n[c];
                normal.at(x, y, 3) = 1.0f;
            }
    }
    static glm::vec3 ray(int w, int h, float x, float y) {
        return glm::vec3(0.01f * (x - 0.5f * float(w) + 0.5f), 0.01f * (y - 0.5f * float(h) + 0.5f), -1.0f);
    }
    Image marks(int radius = 0) const {
        return discontinuitiesCpu(position, normal, glm::mat4(1.0f), DiscontinuityBuffer::kDefaultDepthThreshold,
                                  DiscontinuityBuffer::kDefaultNormalThreshold, radius);
    }
};

const glm::vec3 kFacing(0.0f, 0.0f, 1.0f);
glm::vec3 tilted(float degrees) {
    float a = glm::radians(degrees);
    return glm::vec3(std::sin(a), 0.0f, std::cos(a));
}
// The depth along pixel (x, y)'s ray of the plane through `point` with normal n.
float planeDepth(int w, int h, int x, int y, glm::vec3 n, glm::vec3 point) {
    return glm::dot(n, point) / glm::dot(n, SyntheticGBuffer::ray(w, h, float(x), float(y)));
}

// The marked columns of row y.
std::vector<int> markedColumns(const Image& m, int y) {
    std::vector<int> out;
    for (int x = 0; x < m.width; ++x)
        if (m.at(x, y) != 0.0f) out.push_back(x);
    return out;
}

TEST(DiscontinuityCpu, FlatPlaneAndSmoothRampAreNotMarked) {
    auto plane = [](float degrees) {  // a plane through (0, 0, -5) seen at `degrees` of incidence
        glm::vec3 n = tilted(degrees);
        return SyntheticGBuffer(32, 16, [=](int x, int y) { return planeDepth(32, 16, x, y, n, glm::vec3(0, 0, -5)); },
                                [=](int, int) { return n; });
    };
    // Facing, then ramps in depth: at 80 degrees the depth changes by 5.7% per pixel (the plain
    // |Sobel z| / z reads 0.11 there, 0.02 times the cosine).
    for (float degrees : {0.0f, 45.0f, 70.0f, 80.0f})
        for (float v : plane(degrees).marks().data) ASSERT_EQ(v, 0.0f) << degrees << " degrees";
    // A smooth turn of the normal, 5 degrees per pixel (reads 0.087 per pixel).
    Image turning = SyntheticGBuffer(32, 16, [](int, int) { return 5.0f; },
                                     [](int x, int) { return tilted(5.0f * float(x)); }).marks();
    for (float v : turning.data) ASSERT_EQ(v, 0.0f);
}

TEST(DiscontinuityCpu, DepthStepAndNormalCreaseAreMarkedBesideThem) {
    // 5% step between facing planes, between columns 15 and 16: reads 0.25 / 5 and 0.25 / 5.25
    // (times cosines of 0.99) on the two columns beside it; a 2% step (0.02) is below the threshold.
    Image step = SyntheticGBuffer(32, 16, [](int x, int) { return x < 16 ? 5.0f : 5.25f; },
                                  [](int, int) { return kFacing; }).marks();
    Image small = SyntheticGBuffer(32, 16, [](int x, int) { return x < 16 ? 5.0f : 5.1f; },
                                   [](int, int) { return kFacing; }).marks();
    // Creases: a facing plane and one turned by `degrees` meeting on the ray between columns 15 and
    // 16: 45 degrees reads 2 sin 22.5 = 0.77 and is marked, 20 degrees (0.35) is not.
    auto crease = [](float degrees) {
        glm::vec3 edge = SyntheticGBuffer::ray(32, 16, 15.5f, 7.5f) * 5.0f, n = tilted(degrees);
        return SyntheticGBuffer(32, 16,
                                [=](int x, int y) { return x < 16 ? planeDepth(32, 16, x, y, kFacing, edge) : planeDepth(32, 16, x, y, n, edge); },
                                [=](int x, int) { return x < 16 ? kFacing : n; }).marks();
    };
    Image sharp = crease(45.0f), soft = crease(20.0f);
    for (int y = 0; y < 16; ++y) {
        EXPECT_EQ(markedColumns(step, y), (std::vector<int>{15, 16})) << "row " << y;
        EXPECT_EQ(markedColumns(sharp, y), (std::vector<int>{15, 16})) << "row " << y;
        EXPECT_TRUE(markedColumns(small, y).empty()) << "row " << y;
        EXPECT_TRUE(markedColumns(soft, y).empty()) << "row " << y;
    }
}

TEST(DiscontinuityCpu, BackgroundNextToGeometryIsASilhouette) {
    // A flat disc of radius 8 facing the camera, background around it.
    auto inside = [](int x, int y) { return (x - 16) * (x - 16) + (y - 12) * (y - 12) <= 64; };
    Image m = SyntheticGBuffer(32, 24, [&](int x, int y) { return inside(x, y) ? 5.0f : 0.0f; },
                               [](int, int) { return kFacing; }).marks();
    int marked = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            bool mixed = false;
            for (int j = -1; j <= 1; ++j)
                for (int i = -1; i <= 1; ++i) {
                    int qx = std::clamp(x + i, 0, 31), qy = std::clamp(y + j, 0, 23);
                    mixed |= inside(qx, qy) != inside(x, y);
                }
            ASSERT_EQ(m.at(x, y), mixed ? 1.0f : 0.0f) << x << "," << y;
            marked += mixed;
        }
    EXPECT_GT(marked, 50);  // both sides of the circle's outline
}

TEST(DiscontinuityCpu, WideningReachesTheRadiusOnEachSide) {
    SyntheticGBuffer g(40, 20, [](int x, int) { return x < 20 ? 5.0f : 6.0f; }, [](int, int) { return kFacing; });
    for (int r : {1, 3, 5}) {
        Image m = g.marks(r);
        for (int y = 0; y < 20; ++y) {
            std::vector<int> expected;
            for (int x = 19 - r; x <= 20 + r; ++x) expected.push_back(x);
            ASSERT_EQ(markedColumns(m, y), expected) << "radius " << r << " row " << y;
        }
    }
    // Any pattern: the widened buffer is the (2 r + 1)^2 max of the unwidened one.
    SyntheticGBuffer disc(33, 21, [](int x, int y) { return (x - 12) * (x - 12) + (y - 9) * (y - 9) < 30 ? 4.0f : 5.0f; },
                          [](int x, int y) { return x == 27 && y == 15 ? tilted(80.0f) : kFacing; });
    Image m0 = disc.marks(0), m2 = disc.marks(2);
    for (int y = 0; y < 21; ++y)
        for (int x = 0; x < 33; ++x) {
            float expected = 0.0f;
            for (int j = std::max(0, y - 2); j <= std::min(20, y + 2); ++j)
                for (int i = std::max(0, x - 2); i <= std::min(32, x + 2); ++i) expected = std::max(expected, m0.at(i, j));
            ASSERT_EQ(m2.at(x, y), expected) << x << "," << y;
        }
    EXPECT_EQ(dilationRadiusForSpacing(4), 2);
    EXPECT_EQ(dilationRadiusForSpacing(3), 2);
    EXPECT_EQ(dilationRadiusForSpacing(1), 1);
}

class DiscontinuityGpu : public testing::GLTest {};

Image runGpu(DiscontinuityBuffer& buffer, const Image& position, const Image& normal, const glm::mat4& view, int radius) {
    Texture p = Texture::create2D(position.width, position.height, Format::RGBA32F);
    Texture n = Texture::create2D(position.width, position.height, Format::RGBA32F);
    uploadTexture(p, 0, 0, position);
    uploadTexture(n, 0, 0, normal);
    Texture out = Texture::create2D(position.width, position.height, Format::R32F);
    buffer.run(programCache(), p, n, view, out, DiscontinuityBuffer::kDefaultDepthThreshold,
               DiscontinuityBuffer::kDefaultNormalThreshold, radius);
    return readTexture(out, 1);
}

TEST_F(DiscontinuityGpu, MatchesCpuOnSyntheticGBuffers) {
    DiscontinuityBuffer buffer;
    auto inside = [](int x, int y) { return (x - 20) * (x - 20) + (y - 12) * (y - 12) <= 81; };
    SyntheticGBuffer g(41, 27, [&](int x, int y) { return !inside(x, y) && x > 30 ? 0.0f : x < 12 ? 5.0f : 6.5f; },
                       [&](int x, int y) { return inside(x, y) ? tilted(50.0f) : kFacing; });
    for (int r : {0, 2}) {
        Image cpu = g.marks(r), gpu = runGpu(buffer, g.position, g.normal, glm::mat4(1.0f), r);
        for (size_t i = 0; i < cpu.pixelCount(); ++i) ASSERT_EQ(gpu.data[i], cpu.data[i]) << "radius " << r << " pixel " << i;
    }
}

// The defaults on every scene of assets/scenes, through DiscontinuityBuffer::run(PassContext&):
// the GPU equals the CPU mirror (but for pixels whose measure is within 1e-4 of a threshold); the
// outlines between objects are marked; the inside of floors and spheres is not.
TEST_F(DiscontinuityGpu, DefaultsOnTheScenes) {
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(projectRoot()) / "assets/scenes")) {
        if (entry.path().extension() != ".json") continue;
        const std::string name = entry.path().stem().string();
        if (!testing::sceneCanLoad(name)) continue;
        Scene scene = loadScene(name);
        RenderOptions options;
        options.width = 192;
        options.height = 144;
        Renderer renderer(scene, options);
        renderer.renderFrame(0, {"gbuffer"});
        Texture& position = renderer.pool().find("frame/gbuffer.position")->texture;
        Texture& normal = renderer.pool().find("frame/gbuffer.normal")->texture;
        FrameState frame;
        frame.scene = &scene;
        frame.programs = &programCache();
        frame.width = options.width;
        frame.height = options.height;
        frame.camera = renderer.camera();
        frame.gbuffer.width = options.width;
        frame.gbuffer.height = options.height;
        frame.gbuffer.position = &position;
        frame.gbuffer.normal = &normal;
        PassContext ctx(frame, nullptr, renderer.pool(), "test/discontinuities", {"gbuffer", "camera"});
        DiscontinuityBuffer buffer;
        Texture out = Texture::create2D(options.width, options.height, Format::R32F);
        buffer.run(ctx, out);
        Image gpu = readTexture(out, 1);
        const Image p = readTextureLevel(position), n = readTextureLevel(normal);
        Image measures;
        const glm::mat4 view = renderer.camera().viewFromWorld();
        const float dt = DiscontinuityBuffer::kDefaultDepthThreshold, nt = DiscontinuityBuffer::kDefaultNormalThreshold;
        Image cpu = discontinuitiesCpu(p, n, view, dt, nt, 0, &measures);
        int differ = 0;
        for (size_t i = 0; i < cpu.pixelCount(); ++i) {
            if (gpu.data[i] == cpu.data[i]) continue;
            ++differ;
            bool nearThreshold = std::abs(measures.data[i * 2] - dt) < 1e-4f * dt || std::abs(measures.data[i * 2 + 1] - nt) < 1e-4f * nt;
            EXPECT_TRUE(nearThreshold) << name << " pixel " << i << " measures " << measures.data[i * 2] << ", " << measures.data[i * 2 + 1];
        }
        EXPECT_LE(differ, 3) << name;
        // widened on the GPU as on the CPU
        buffer.run(ctx, out, dt, nt, 3);
        Image gpu3 = readTexture(out, 1), cpu3 = discontinuitiesCpu(p, n, view, dt, nt, 3);
        int differ3 = 0;
        for (size_t i = 0; i < cpu3.pixelCount(); ++i) differ3 += gpu3.data[i] != cpu3.data[i];
        EXPECT_LE(differ3, 49 * differ) << name;

        // Object outlines (a 3x3 holding two object ids) and the inside of floors and spheres (a 7x7 of
        // one such object): ids are the material's alpha.
        Image ids = renderer.ids();  // top first, as readTextureLevel
        std::map<int, std::string> source;
        for (const Object& o : scene.objects) source[o.id] = o.source;
        int outline = 0, outlineMarked = 0, smooth = 0, smoothMarked = 0;
        const int w = ids.width, h = ids.height;
        for (int y = 3; y < h - 3; ++y)
            for (int x = 3; x < w - 3; ++x) {
                float id = ids.at(x, y);
                bool two = false, same7 = true;
                for (int j = -3; j <= 3; ++j)
                    for (int i = -3; i <= 3; ++i) {
                        bool differs = ids.at(x + i, y + j) != id;
                        same7 &= !differs;
                        if (std::abs(i) <= 1 && std::abs(j) <= 1) two |= differs;
                    }
                if (two && id >= 0.0f) {
                    ++outline;
                    bool near = false;  // the line is found on this side or the other
                    for (int j = -1; j <= 1; ++j)
                        for (int i = -1; i <= 1; ++i) near |= cpu.at(x + i, y + j) != 0.0f;
                    outlineMarked += near;
                }
                const std::string& s = id >= 0.0f ? source[int(id)] : "";
                if (same7 && (s == "plane" || s == "quad" || s == "sphere")) {
                    ++smooth;
                    smoothMarked += cpu.at(x, y) != 0.0f;
                }
            }
        double outlineFraction = outline ? double(outlineMarked) / outline : 1.0;
        double smoothFraction = smooth ? double(smoothMarked) / smooth : 0.0;
        std::printf("%-22s outlines marked %5.1f%% of %5d, floors/spheres inside marked %5.2f%% of %5d, GPU != CPU %d\n",
                    name.c_str(), 100.0 * outlineFraction, outline, 100.0 * smoothFraction, smooth, differ);
        EXPECT_GE(outlineFraction, 0.9) << name;
        EXPECT_LE(smoothFraction, 0.005) << name;
    }
}

}  // namespace
}  // namespace shadowlab
