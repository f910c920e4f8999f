// The screen-space multi-resolution of ssm-contour and ssm-gbp06 (guennebaud2007 sec. 5.2 and 6):
// the shared selection math (eq. 4-6, the dither pattern, the block classification) on the CPU,
// and end to end on the GPU: the selection codes, the sparse v-buffer, the packing, evaluated
// pixels equal to the full evaluation, skipped ones filled by pull-push, the error it costs, and
// the discontinuity buffer's job (Fig. 8) in a band around the discontinuities.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

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
using Sets = std::vector<std::pair<std::string, std::string>>;

TEST(ScreenSelection, DitherRanksFillEveryWindowOnce) {
    // The 2 x 2 pattern is the classic [[0, 2], [3, 1]] plus one (rows are j).
    EXPECT_EQ(ditherRank(0, 0, 2), 1);
    EXPECT_EQ(ditherRank(1, 0, 2), 3);
    EXPECT_EQ(ditherRank(0, 1, 2), 4);
    EXPECT_EQ(ditherRank(1, 1, 2), 2);
    // Fig. 9's 4 x 4 (Bayer): first row 1, 9, 3, 11.
    EXPECT_EQ(ditherRank(0, 0, 4), 1);
    EXPECT_EQ(ditherRank(1, 0, 4), 9);
    EXPECT_EQ(ditherRank(2, 0, 4), 3);
    EXPECT_EQ(ditherRank(3, 0, 4), 11);
    for (int h : {2, 4, 8, 16}) {
        // Any h x h window, aligned or not, holds each rank 1 .. h^2 once.
        for (int ox : {0, 3}) {
            std::set<int> ranks;
            for (int j = 0; j < h; ++j)
                for (int i = 0; i < h; ++i) ranks.insert(ditherRank(i + ox, j + 2 * ox, h));
            EXPECT_EQ(int(ranks.size()), h * h) << "h " << h;
            EXPECT_EQ(*ranks.begin(), 1);
            EXPECT_EQ(*ranks.rbegin(), h * h);
        }
        // The pixels of the lowest quarter of the ranks are spread: one in each (h/2)^2 sub-window.
        if (h >= 4) {
            for (int sj = 0; sj < 2; ++sj)
                for (int si = 0; si < 2; ++si) {
                    int low = 0;
                    for (int j = 0; j < h / 2; ++j)
                        for (int i = 0; i < h / 2; ++i) low += ditherRank(si * h / 2 + i, sj * h / 2 + j, h) <= h * h / 4;
                    EXPECT_EQ(low, h * h / 16) << "h " << h;
                }
        }
    }
}

TEST(ScreenSelection, EquationsFourToSix) {
    // Eq. 4: w_l (p_z - z_occ) / z_occ; nothing where lit (z_occ 0) or behind.
    EXPECT_FLOAT_EQ(penumbraObjectSize(2.0f, 6.0f, 4.0f), 1.0f);
    EXPECT_EQ(penumbraObjectSize(2.0f, 6.0f, 0.0f), 0.0f);
    EXPECT_EQ(penumbraObjectSize(2.0f, 3.0f, 4.0f), 0.0f);
    // Eq. 5: eta s_obj / z_pe n.v: a 1-unit penumbra at depth 5 seen head-on with eta 500 spans 100
    // pixels, 50 at 60 degrees.
    EXPECT_FLOAT_EQ(penumbraScreenSize(1.0f, 500.0f, 5.0f, 1.0f), 100.0f);
    EXPECT_NEAR(penumbraScreenSize(1.0f, 500.0f, 5.0f, std::cos(glm::radians(60.0f))), 50.0f, 1e-3f);
    // Eq. 6 with s_min 16, h 4: under s_min everything; the density falls as s_scr grows, to the one
    // pixel of rank h^2 per window past s_min h.
    auto density = [](float s) {
        int n = 0;
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) n += screenSelected(s, 16.0f, ditherRank(i, j, 4), 4);
        return n;
    };
    EXPECT_EQ(density(0.0f), 16);
    EXPECT_EQ(density(15.9f), 16);
    EXPECT_EQ(density(16.0f * 2.0f), 12);  // sqrt(rank) > 2: ranks 5 .. 16
    EXPECT_EQ(density(16.0f * 4.0f), 1);
    EXPECT_EQ(density(1e9f), 1);
    for (float s = 0.0f; s < 80.0f; s += 0.5f) EXPECT_LE(density(s + 0.5f), density(s));
    // Codes and blocks.
    EXPECT_EQ(penumbraSelectionCode(true, true), SEL_SELECTED);
    EXPECT_EQ(penumbraSelectionCode(false, true), SEL_FORCED);
    EXPECT_EQ(penumbraSelectionCode(false, false), SEL_SKIPPED);
    EXPECT_TRUE(selectionEvaluated(SEL_BLOCK));
    EXPECT_FALSE(selectionEvaluated(SEL_SKIPPED));
    EXPECT_FALSE(selectionEvaluated(SEL_LIT));
    EXPECT_EQ(blockClass(0, 256), 0);
    EXPECT_EQ(blockClass(204, 256), 1);  // 79.7%
    EXPECT_EQ(blockClass(205, 256), 2);  // 80.1%
    EXPECT_EQ(blockClass(3, 3), 2);      // a block cut by the frame's border counts its own pixels
}

struct SelectionCase {
    glm::vec4 sizes, screen;
    glm::ivec4 ints;
    glm::uvec4 bits;
};
struct SelectionResult {
    glm::vec4 values;
    glm::ivec4 codes;
    glm::uvec4 bits;
};

class ScreenSelectionGpu : public testing::GLTest {};

// The same functions on the GPU (shaders/tests/visibility/screen_selection_math.comp) and on the
// CPU: equal results (the codes, ranks, bits and classes exactly; the sizes within float rounding;
// selections within 1e-4 of the threshold are not compared).
TEST_F(ScreenSelectionGpu, SharedMathAgreesWithCpu) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<SelectionCase> cases;
    for (int k = 0; k < 1024; ++k) {
        SelectionCase c{};
        const float zOcc = k % 11 == 0 ? 0.0f : 0.5f + 5.0f * u(rng);
        c.sizes = glm::vec4(0.1f + 2.0f * u(rng), 0.5f + 6.0f * u(rng), zOcc, 1.0f + 40.0f * u(rng));
        c.screen = glm::vec4(100.0f + 900.0f * u(rng), 0.5f + 10.0f * u(rng), u(rng), 0.0f);
        const int h = 1 << (1 + k % 4);
        c.ints = glm::ivec4(int(rng() % 4096), int(rng() % 4096), h, int(rng() % 257));
        const uint blocks = 1u + uint(rng() % 31u);
        c.bits = glm::uvec4(uint(rng()), uint(rng()), blocks, uint(rng() % blocks));
        cases.push_back(c);
    }
    Buffer in(cases.size() * sizeof(SelectionCase), cases.data()), out(cases.size() * sizeof(SelectionResult));
    const ShaderProgram& program = programCache().compute("tests/visibility/screen_selection_math.comp");
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.set("count", unsigned(cases.size()));
    program.dispatch(GLuint((cases.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<SelectionResult> gpu = out.read<SelectionResult>();
    size_t selectedCompared = 0;
    for (size_t k = 0; k < cases.size(); ++k) {
        const SelectionCase& c = cases[k];
        const SelectionResult& g = gpu[k];
        const float sObj = penumbraObjectSize(c.sizes.x, c.sizes.y, c.sizes.z);
        const float sScr = penumbraScreenSize(sObj, c.screen.x, c.screen.y, c.screen.z);
        const int rank = ditherRank(c.ints.x, c.ints.y, c.ints.z);
        EXPECT_NEAR(g.values.x, sObj, 1e-5f * std::max(1.0f, sObj)) << k;
        EXPECT_NEAR(g.values.y, sScr, 1e-5f * std::max(1.0f, sScr)) << k;
        EXPECT_EQ(int(g.values.z), rank) << k;
        const float threshold = c.sizes.w * std::sqrt(float(rank));
        const bool selected = screenSelected(sScr, c.sizes.w, rank, c.ints.z);
        if (std::abs(sScr - threshold) > 1e-4f * threshold) {
            EXPECT_EQ(g.values.w != 0.0f, selected) << k;
            EXPECT_EQ(g.codes.x, penumbraSelectionCode(selected, k % 3 == 0)) << k;
            ++selectedCompared;
        }
        EXPECT_EQ(g.codes.y != 0, selectionEvaluated(int(k % 7))) << k;
        EXPECT_EQ(g.codes.z, blockClass(c.ints.w, 256)) << k;
        EXPECT_EQ(g.codes.w, contourBlockMask(c.bits.x, c.bits.y, int(c.bits.w))) << k;
        EXPECT_EQ(g.bits.x, contourBlockBits(c.bits.x, c.bits.y, int(c.bits.z))) << k;
    }
    EXPECT_GT(selectedCompared, 1000u);
}

class ScreenAdaptiveRender : public testing::GLTest {};

struct Frame {
    Image visibility, selection, sparse, occupancy, counts, positions;
};

Frame renderFrame(const Scene& scene, const std::string& technique, Sets sets, int size, std::optional<float> lightSize) {
    RenderOptions options;
    options.width = options.height = size;
    options.technique = technique;
    options.sets = std::move(sets);
    options.lightSize = lightSize;
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"visibility", "gbuffer"});
    Frame f;
    f.visibility = renderer.visibility();
    f.positions = renderer.positions();
    auto read = [&](const char* name, int channels) {
        const Resource* r = renderer.pool().find(std::string("L0/") + name);
        return r ? readTexture(r->texture, channels) : Image();
    };
    f.selection = read("selection", 1);
    f.sparse = read("visibility_sparse", 2);
    f.occupancy = read("block_occupancy", 1);
    if (const Resource* c = renderer.pool().find("L0/pack.counts")) {
        f.counts = Image(12, 1, 1);
        std::vector<uint32_t> u(12);
        glGetNamedBufferSubData(c->buffer, 0, GLsizeiptr(u.size() * 4), u.data());
        for (int i = 0; i < 12; ++i) f.counts.data[size_t(i)] = float(u[size_t(i)]);
    }
    return f;
}

// The whole pipeline on square-occluder under a light of size 2 (penumbrae up to ~40 pixels wide
// at 160 x 160, so the pattern skips): codes, weights, blocks and counts agree with each other;
// every evaluated pixel is exactly the full evaluation's; the computed pixels survive pull-push
// exactly; skipped ones are filled within the error bound.
TEST_F(ScreenAdaptiveRender, EvaluatedPixelsAreTheFullEvaluationAndTheRestIsFilled) {
    const Scene scene = loadScene("square-occluder");
    for (const char* technique : {"ssm-contour", "ssm-gbp06"}) {
        SCOPED_TRACE(technique);
        Frame full = renderFrame(scene, technique, {{"screen_adaptive", "false"}}, 160, 2.0f);
        Frame adaptive = renderFrame(scene, technique, {}, 160, 2.0f);
        ASSERT_EQ(adaptive.selection.width, 160);
        ASSERT_TRUE(full.selection.data.empty()) << "no selection where screen_adaptive is off";
        std::map<int, int> codes;
        double sq = 0.0;
        int filled = 0;
        for (int y = 0; y < 160; ++y)
            for (int x = 0; x < 160; ++x) {
                const int code = int(adaptive.selection.at(x, y));
                ++codes[code];
                const float w = adaptive.sparse.at(x, y, 1), v = adaptive.sparse.at(x, y, 0);
                const float out = adaptive.visibility.at(x, y);
                if (code == SEL_SKIPPED) {
                    EXPECT_EQ(w, 0.0f);
                    const double d = double(out) - double(full.visibility.at(x, y));
                    sq += d * d;
                    ++filled;
                    continue;
                }
                ASSERT_EQ(w, 1.0f) << x << "," << y << " code " << code;
                EXPECT_NEAR(out, v, 2e-6f) << "pull-push changed a computed pixel at " << x << "," << y;
                if (selectionEvaluated(code) || code == SEL_LIT || code == SEL_UMBRA)
                    EXPECT_NEAR(out, full.visibility.at(x, y), 1e-5f) << x << "," << y << " code " << code;
            }
        const int evaluated = codes[SEL_SELECTED] + codes[SEL_FORCED] + codes[SEL_BLOCK];
        EXPECT_GT(codes[SEL_SKIPPED], evaluated / 4) << "wide penumbrae: the pattern skips";
        EXPECT_GT(codes[SEL_SELECTED], 0);
        // Filled pixels: the pull-push's interpolation of a smooth penumbra.
        const double filledRmse = std::sqrt(sq / std::max(filled, 1));
        std::printf("%s: %d evaluated, %d skipped, RMSE of the filled ones against the full evaluation %.4f\n",
                    technique, evaluated, codes[SEL_SKIPPED], filledRmse);
        EXPECT_LT(filledRmse, 0.02) << filled << " filled";
        // Blocks: a block over 80% selected has no skipped pixel left; one at or under has no SEL_BLOCK.
        const int blocksX = adaptive.occupancy.width, blocksY = adaptive.occupancy.height;
        EXPECT_EQ(blocksX, 10);
        int whole = 0, compacted = 0, empty = 0, listed = 0, selected = 0;
        for (int by = 0; by < blocksY; ++by)
            for (int bx = 0; bx < blocksX; ++bx) {
                int sel = 0, skipped = 0, block = 0, pixels = 0;
                for (int y = by * BP_BLOCK; y < std::min(160, (by + 1) * BP_BLOCK); ++y)
                    for (int x = bx * BP_BLOCK; x < std::min(160, (bx + 1) * BP_BLOCK); ++x) {
                        const int code = int(adaptive.selection.at(x, 159 - y));  // blocks count rows from the bottom
                        sel += code == SEL_SELECTED || code == SEL_FORCED;
                        skipped += code == SEL_SKIPPED;
                        block += code == SEL_BLOCK;
                        ++pixels;
                    }
                const float occupancy = adaptive.occupancy.at(bx, blocksY - 1 - by);
                EXPECT_FLOAT_EQ(occupancy, float(sel) / float(pixels)) << "block " << bx << "," << by;
                const int cls = blockClass(sel, pixels);
                if (cls == 2) {
                    EXPECT_EQ(skipped, 0);
                    ++whole;
                    listed += sel + block;  // every penumbra pixel of a block processed whole
                } else {
                    EXPECT_EQ(block, 0);
                    if (cls == 1) {
                        ++compacted;
                        listed += sel;
                    } else {
                        ++empty;
                    }
                }
                selected += sel;
            }
        ASSERT_EQ(adaptive.counts.width, 12);
        EXPECT_EQ(int(adaptive.counts.data[0]), listed);
        EXPECT_EQ(int(adaptive.counts.data[4]), whole);
        EXPECT_EQ(int(adaptive.counts.data[8]), compacted);
        EXPECT_EQ(int(adaptive.counts.data[9]), empty);
        EXPECT_EQ(int(adaptive.counts.data[10]), selected);
        EXPECT_GT(compacted, 0);
        EXPECT_GT(empty, 0);
    }
}

// --stats reports the selection per light (counters.screen_selection), the same counts as the
// selection internal and the pack pass; nothing for a technique or setting without it.
TEST_F(ScreenAdaptiveRender, StatsCountTheEvaluatedPixels) {
    const Scene scene = loadScene("square-occluder");
    auto stats = [&](const char* technique, Sets sets, Image* codes) {
        RenderOptions options;
        options.width = options.height = 160;
        options.technique = technique;
        options.sets = std::move(sets);
        options.lightSize = 2.0f;
        Renderer renderer(scene, options);
        renderer.renderFrame(0, {"visibility"});
        if (const Resource* r = renderer.pool().find("L0/selection"); r && codes) *codes = readTexture(r->texture, 1);
        return renderer.stats({}, 0)["lights"][0]["counters"];
    };
    Image codes;
    const nlohmann::json c = stats("ssm-contour", {}, &codes);
    ASSERT_TRUE(c.contains("screen_selection")) << c.dump();
    const nlohmann::json& s = c["screen_selection"];
    std::map<int, int> n;
    for (float v : codes.data) ++n[int(v)];
    EXPECT_EQ(s["skipped_pixels"].get<int>(), n[SEL_SKIPPED]);
    EXPECT_EQ(s["evaluated_pixels"].get<int>(), n[SEL_SELECTED] + n[SEL_FORCED] + n[SEL_BLOCK]);
    EXPECT_EQ(s["listed_pixels"].get<int>(), s["evaluated_pixels"].get<int>()) << "the list holds every evaluated pixel";
    EXPECT_NEAR(s["evaluated_fraction"].get<double>(),
                double(s["evaluated_pixels"].get<int>()) / double(s["penumbra_pixels"].get<int>()), 1e-12);
    EXPECT_GT(s["skipped_pixels"].get<int>(), 0);
    EXPECT_EQ(s["blocks_whole"].get<int>() + s["blocks_compacted"].get<int>() + s["blocks_skipped"].get<int>(), 100);
    EXPECT_TRUE(stats("ssm-gbp06", {{"screen_adaptive", "false"}}, nullptr).empty());
    EXPECT_TRUE(stats("pcss", {}, nullptr).empty());
}

// Fig. 8: without the discontinuity buffer, pull-push blends penumbrae across two surfaces; with
// it, every pixel near a depth or normal discontinuity is computed. On depth-discontinuities (three
// steps of 0.3 units under a light of size 2, s_min 4 so that the pattern skips at this size), the
// error against the full evaluation in a band of 3 pixels around the discontinuities falls.
TEST_F(ScreenAdaptiveRender, DiscontinuitiesKeepPenumbraeFromCrossingSurfaces) {
    const Scene scene = loadScene("depth-discontinuities");
    const Sets common = {{"s_min", "4"}};
    Frame full = renderFrame(scene, "ssm-contour", {{"screen_adaptive", "false"}}, 192, 2.0f);
    Sets on = common, off = common;
    off.push_back({"discontinuities", "false"});
    Frame with = renderFrame(scene, "ssm-contour", on, 192, 2.0f);
    Frame without = renderFrame(scene, "ssm-contour", off, 192, 2.0f);
    // The band: pixels whose 7x7 neighbourhood holds the forced code or a depth step (from the
    // positions: a jump of the camera distance by more than 3% between neighbours).
    auto distance = [&](int x, int y) {
        const glm::vec3 p(full.positions.at(x, y, 0), full.positions.at(x, y, 1), full.positions.at(x, y, 2));
        return glm::length(p - scene.camera.position);
    };
    Image step(192, 192, 1, 0.0f);
    for (int y = 0; y < 191; ++y)
        for (int x = 0; x < 191; ++x) {
            const float d = distance(x, y), dx = distance(x + 1, y), dy = distance(x, y + 1);
            if (std::isnan(d) || std::isnan(dx) || std::isnan(dy)) continue;
            if (std::abs(dx - d) > 0.03f * d || std::abs(dy - d) > 0.03f * d) step.at(x, y) = 1.0f;
        }
    double sqOn = 0.0, sqOff = 0.0;
    int band = 0, forced = 0, skippedOff = 0;
    for (int y = 3; y < 189; ++y)
        for (int x = 3; x < 189; ++x) {
            bool near = false;
            for (int j = -3; j <= 3 && !near; ++j)
                for (int i = -3; i <= 3 && !near; ++i) near = step.at(x + i, y + j) != 0.0f;
            if (!near || std::isnan(full.positions.at(x, y, 0))) continue;
            ++band;
            forced += int(with.selection.at(x, y)) == SEL_FORCED;
            skippedOff += int(without.selection.at(x, y)) == SEL_SKIPPED;
            const double a = double(with.visibility.at(x, y)) - full.visibility.at(x, y);
            const double b = double(without.visibility.at(x, y)) - full.visibility.at(x, y);
            sqOn += a * a;
            sqOff += b * b;
        }
    ASSERT_GT(band, 300);
    EXPECT_GT(forced, 0) << "the discontinuity buffer forces pixels in the band";
    EXPECT_GT(skippedOff, band / 20) << "without it, the band is skipped like the rest";
    const double rmseOn = std::sqrt(sqOn / band), rmseOff = std::sqrt(sqOff / band);
    std::printf("band of %d pixels: RMSE against the full evaluation %.4f with discontinuities, %.4f without\n", band,
                rmseOn, rmseOff);
    EXPECT_LT(rmseOn, 0.5 * rmseOff);
}

// Fig. 6: without blending (beta = 0) the visibility jumps where the level walked changes, with
// it (beta = 0.05, the paper's) the seams are gone. On square-occluder with its floor tilted by 20
// degrees about the z axis, under a light of size 2, the floor's light depth, so the kernel and the
// level, changes smoothly across the penumbra, and the true visibility is smooth there. The
// smooth truth is the full-resolution walk (light_multires off: the same contour method on the map
// itself, no levels). The jump of a pair of neighbouring floor pixels is the difference of their
// visibility steps, the level walk's against the full walk's, measured on the pairs whose level
// (the light_levels internal) differs and, as the control, on all other pairs.
TEST_F(ScreenAdaptiveRender, BlendingRemovesTheSeamsAtLevelTransitions) {
    Scene scene = loadScene("square-occluder");
    scene.objects[0].worldFromObject = glm::rotate(glm::mat4(1.0f), glm::radians(20.0f), glm::vec3(0, 0, 1)) *
                                       scene.objects[0].worldFromObject;
    auto render = [&](Sets sets, Image* levels) {
        RenderOptions options;
        options.width = options.height = 192;
        options.technique = "ssm-contour";
        options.sets = std::move(sets);
        options.sets.push_back({"screen_adaptive", "false"});
        options.lightSize = 2.0f;
        Renderer renderer(scene, options);
        renderer.renderFrame(0, {"visibility", "gbuffer"});
        if (levels) {
            const Resource* r = renderer.pool().find("L0/light_levels");
            EXPECT_TRUE(r);
            if (r) *levels = readTexture(r->texture, 4);
        }
        return std::make_pair(renderer.visibility(), renderer.ids());
    };
    const auto [truth, ids] = render({{"light_multires", "false"}}, nullptr);
    auto seams = [&](const char* beta, double* elsewhere) {
        Image levels;
        const Image v = render({{"beta", beta}, {"t_k", "8"}}, &levels).first;
        double seam = 0.0, other = 0.0, sum = 0.0;
        int transitions = 0;
        for (int y = 0; y < 192; ++y)
            for (int x = 0; x + 1 < 192; ++x) {
                if (ids.at(x, y) != 0.0f || ids.at(x + 1, y) != 0.0f) continue;  // the floor only
                const float la = levels.at(x, y, 1), lb = levels.at(x + 1, y, 1);
                if (la < 0.0f || lb < 0.0f) continue;  // lit or umbra: nothing walked
                const double jump =
                    std::abs((double(v.at(x + 1, y)) - v.at(x, y)) - (double(truth.at(x + 1, y)) - truth.at(x, y)));
                if (la != lb) {
                    sum += jump;
                    seam = std::max(seam, jump);
                    ++transitions;
                } else {
                    other = std::max(other, jump);
                }
            }
        std::printf("beta %s: %d transitions, mean jump %.4f\n", beta, transitions, sum / std::max(transitions, 1));
        EXPECT_GT(transitions, 20) << "beta " << beta << ": the level changes across the penumbrae";
        *elsewhere = other;
        return seam;
    };
    double otherSharp = 0.0, otherBlended = 0.0;
    const double sharp = seams("0", &otherSharp), blended = seams("0.05", &otherBlended);
    std::printf("largest jump at level transitions: %.4f without blending, %.4f with (elsewhere %.4f, %.4f)\n", sharp,
                blended, otherSharp, otherBlended);
    // Measured at 192 x 192, t_k 8: 0.087 without blending, 0.009 with (mean 0.040 and 0.001), the
    // largest jump elsewhere 0.025 (the level walk's own error against the full walk).
    EXPECT_GT(sharp, 4.0 * blended) << "blending removes the seams";
    EXPECT_LT(blended, otherBlended) << "with blending a transition is no worse than any other pair";
}

}  // namespace
}  // namespace shadowlab
