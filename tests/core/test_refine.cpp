// The frame in slices (Renderer::refineFrame, PassGraph::executeSliced): what the window runs when a
// technique's frame does not fit its frame budget (issue 18, "never frozen"). The graph resumes
// where it stopped, starts over what a changed input invalidated, and the refined frame equals the
// frame run whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "gl/texture.h"
#include "graph/renderer.h"
#include "scene/scene.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

using testing::GLTest;

// A fake clock: every run "costs" what the pass says, so budgets are exact.
struct FakeGraph {
    PassGraph graph;
    int mapRuns = 0, lookups = 0, shades = 0;
    std::vector<std::pair<int, int>> pieces;  // the lookup's (from, to)
    double costPerPiece = 1.0;                // ms per unit of "lookup"
    double lastCost = 0.0;
    PassGraph::Slicing slicing;
    PassGraph::Timer timer;

    FakeGraph() {
        graph.setSource("light", 1);
        graph.setSource("camera", 1);
        graph.addPass("map", "L0", "hard", {"light"}, {"map"}, {}, [this] { ++mapRuns; lastCost = 2.0; });
        graph.addPass("lookup", "L0", "hard", {"map", "camera"}, {"vis"}, {}, [this] { ++lookups; lastCost = 100.0; });
        graph.addPass("shade", "frame", "", {"vis"}, {"image"}, {}, [this] { ++shades; lastCost = 1.0; });
        slicing.units = [](const std::string& pass) { return pass == "lookup" ? 100 : 0; };
        slicing.runUnits = [this](const std::string&, int from, int to, const std::function<void()>&) {
            pieces.emplace_back(from, to);
            lastCost = costPerPiece * (to - from);
        };
        timer = [this](const std::function<void()>& f) {
            lastCost = 0.0;
            f();
            return lastCost;
        };
    }
};

TEST(PassGraphSliced, RunsAFrameOverSeveralCallsWithinTheBudget) {
    FakeGraph g;
    // 100 pieces of 1 ms each, a 10 ms budget: the map (2 ms) and 8 pieces, then 10 per call.
    std::vector<double> progress;
    for (int call = 0; call < 30; ++call) {
        progress.push_back(g.graph.executeSliced({"image"}, 0, g.timer, 10.0, g.slicing));
        if (progress.back() >= 1.0) break;
    }
    ASSERT_EQ(progress.back(), 1.0);
    EXPECT_GE(progress.size(), 10u);  // 2 + 100 + 1 ms of work in 10 ms slices
    EXPECT_LE(progress.size(), 13u);
    EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));  // the HUD's "refining, k%" only grows
    EXPECT_EQ(g.mapRuns, 1);
    EXPECT_EQ(g.lookups, 0);  // the banded pass runs only as pieces
    EXPECT_EQ(g.shades, 1);
    // The pieces tile [0, 100), none twice; with no forecast yet they come in a scattered order
    // (bands over the whole frame first), so they are not all in order.
    std::vector<std::pair<int, int>> sorted = g.pieces;
    std::sort(sorted.begin(), sorted.end());
    int next = 0;
    for (auto [from, to] : sorted) {
        EXPECT_EQ(from, next);
        EXPECT_GT(to, from);
        next = to;
    }
    EXPECT_EQ(next, 100);
    EXPECT_FALSE(std::is_sorted(g.pieces.begin(), g.pieces.end()));
    // The next refinement of the pass has a forecast (what each unit cost): contiguous pieces.
    g.graph.setSource("camera", 7);
    g.pieces.clear();
    double p = 0.0;
    for (int call = 0; call < 30 && p < 1.0; ++call) p = g.graph.executeSliced({"image"}, 1, g.timer, 10.0, g.slicing);
    ASSERT_EQ(p, 1.0);
    EXPECT_TRUE(std::is_sorted(g.pieces.begin(), g.pieces.end()));
    EXPECT_EQ(g.pieces.front().first, 0);
    EXPECT_EQ(g.pieces.back().second, 100);
    EXPECT_LE(g.pieces.size(), 12u);  // about 10 units per 10 ms call, not one unit per call
    // The lookup counts one run a frame, its time the sum of its pieces (what a whole frame costs).
    const PassRecord& lookup = g.graph.records()[1];
    EXPECT_EQ(lookup.runs, 2);
    ASSERT_EQ(lookup.times.size(), 2u);
    EXPECT_NEAR(lookup.times.front().second, 100.0, 1e-9);
    EXPECT_NEAR(lookup.times.back().second, 100.0, 1e-9);
    // A complete frame is reused: nothing runs on the next call.
    g.pieces.clear();
    EXPECT_EQ(g.graph.executeSliced({"image"}, 2, g.timer, 10.0, g.slicing), 1.0);
    EXPECT_TRUE(g.pieces.empty());
    EXPECT_EQ(g.shades, 2);
}

TEST(PassGraphSliced, AChangedInputStartsThePassOver) {
    FakeGraph g;
    for (int call = 0; call < 3; ++call) g.graph.executeSliced({"image"}, 0, g.timer, 10.0, g.slicing);
    ASSERT_FALSE(g.pieces.empty());
    const int reached = g.pieces.back().second;
    ASSERT_LT(reached, 100);
    g.graph.setSource("camera", 2);  // the user moved the camera mid-refinement
    g.pieces.clear();
    g.graph.executeSliced({"image"}, 1, g.timer, 10.0, g.slicing);
    ASSERT_FALSE(g.pieces.empty());
    EXPECT_EQ(g.pieces.front().first, 0);  // from the first row again, not from `reached`
    EXPECT_EQ(g.mapRuns, 1);               // the light did not move: the map is reused
    // Back to the old camera before the lookup finished: its half-rewritten output is never reused.
    g.graph.setSource("camera", 1);
    g.pieces.clear();
    double p = 0.0;
    for (int call = 0; call < 30 && p < 1.0; ++call) p = g.graph.executeSliced({"image"}, 2, g.timer, 10.0, g.slicing);
    ASSERT_EQ(p, 1.0);
    ASSERT_FALSE(g.pieces.empty());
    EXPECT_EQ(g.pieces.front().first, 0);
    // Every unit again (in scattered bands: the abandoned refinements knew only a few units' cost).
    std::vector<std::pair<int, int>> sorted = g.pieces;
    std::sort(sorted.begin(), sorted.end());
    int next = 0;
    for (auto [from, to] : sorted) {
        EXPECT_EQ(from, next);
        next = to;
    }
    EXPECT_EQ(next, 100);
}

TEST(PassGraphSliced, ARunWholeDropsTheHalfDoneFrame) {
    FakeGraph g;
    g.graph.executeSliced({"image"}, 0, g.timer, 10.0, g.slicing);
    g.graph.execute({"image"}, 1, g.timer);  // e.g. a screenshot renders whole
    EXPECT_EQ(g.lookups, 1);
    EXPECT_EQ(g.shades, 1);
    g.pieces.clear();
    EXPECT_EQ(g.graph.executeSliced({"image"}, 2, g.timer, 10.0, g.slicing), 1.0);  // current: reused
    EXPECT_TRUE(g.pieces.empty());
}

class RefineFrameTest : public GLTest {};

// Every technique the window runs: refined in small slices, the frame equals the frame run whole.
// Tolerance 1e-5: the same shaders on the same pixels, only the scissor differs (a float sum in a
// different order could differ in the last bits; nothing here sums across pixels).
TEST_F(RefineFrameTest, EqualsTheFrameRunWholeForEveryTechnique) {
    Scene scene = loadScene("plant");
    for (const char* technique : {"hard", "pcf", "pcss", "sssm", "ssm-gbp06", "ssm-contour", "ssv", "spsm"}) {
        SCOPED_TRACE(technique);
        RenderOptions options;
        options.width = 96;
        options.height = 72;
        options.technique = technique;
        Renderer whole(scene, options), refined(scene, options);
        whole.renderFrame(0, {"image", "visibility"});
        int calls = 0;
        double progress = 0.0;
        while (progress < 1.0 && calls < 2000) {
            progress = refined.refineFrame(0, {"image", "visibility"}, 0.001);  // one piece per call
            ++calls;
        }
        ASSERT_EQ(progress, 1.0);
        EXPECT_GT(calls, 36);  // at least the G-buffer's 36 row pairs one by one
        EXPECT_TRUE(refined.bandedPasses().count("gbuffer"));
        EXPECT_TRUE(refined.bandedPasses().count("shade"));
        const std::string prefix = std::string("L0/") + technique + "/";
        EXPECT_GE(std::count_if(refined.bandedPasses().begin(), refined.bandedPasses().end(),
                                [&](const std::string& p) { return p.rfind(prefix, 0) == 0; }),
                  1);  // the technique's screen passes run in bands too
        Image a = whole.visibility(), b = refined.visibility();
        ASSERT_EQ(a.data.size(), b.data.size());
        double worst = 0.0;
        for (size_t i = 0; i < a.data.size(); ++i) worst = std::max(worst, double(std::abs(a.data[i] - b.data[i])));
        EXPECT_LE(worst, 1e-5);
        Image ia = whole.image(), ib = refined.image();
        double worstImage = 0.0;
        for (size_t i = 0; i < ia.data.size(); ++i)
            worstImage = std::max(worstImage, double(std::abs(ia.data[i] - ib.data[i])));
        EXPECT_LE(worstImage, 1e-5);
        // Moving the light mid-refinement and finishing gives the frame of the new light.
        Light moved = scene.lights[0];
        moved.position += glm::vec3(0.4f, 0.0f, -0.3f);
        for (int k = 0; k < 5; ++k) refined.refineFrame(1, {"image", "visibility"}, 0.001);
        refined.setLight(0, moved);
        whole.setLight(0, moved);
        whole.renderFrame(1, {"image", "visibility"});
        progress = 0.0;
        for (calls = 0; progress < 1.0 && calls < 4000; ++calls)
            progress = refined.refineFrame(1, {"image", "visibility"}, 2.0);
        ASSERT_EQ(progress, 1.0);
        a = whole.visibility();
        b = refined.visibility();
        worst = 0.0;
        for (size_t i = 0; i < a.data.size(); ++i) worst = std::max(worst, double(std::abs(a.data[i] - b.data[i])));
        EXPECT_LE(worst, 1e-5);
    }
}

RenderOptions hardAt64x48() {
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    options.technique = "hard";
    return options;
}

// The G-buffer's positions under the scene's camera (before), a moved camera (after), and after
// the first piece of the moved camera's refinement on a renderer that had the first (refined).
struct FirstPiece {
    Image before, after, refined;
};
FirstPiece firstPieceOfAMovedCamera(const Scene& scene, const RenderOptions& options) {
    Renderer a(scene, options), b(scene, options), r(scene, options);
    Camera moved = scene.camera;
    moved.position += glm::vec3(0.7f, -0.4f, 0.2f);
    b.setCamera(moved);
    a.renderFrame(0, {"gbuffer"});
    b.renderFrame(0, {"gbuffer"});
    r.renderFrame(0, {"gbuffer"});
    r.setCamera(moved);
    EXPECT_LT(r.refineFrame(1, {"gbuffer"}, 0.001), 1.0);
    return {a.positions(), b.positions(), r.positions()};
}

// A piece writes its rows only (the scissor bounds the work): after one piece of a new camera's
// G-buffer, the two rows at the bottom hold the new camera's positions and every other row the old.
TEST_F(RefineFrameTest, APieceWritesOnlyItsRows) {
    const FirstPiece p = firstPieceOfAMovedCamera(loadScene("square-occluder"), hardAt64x48());
    const Image &pa = p.before, &pb = p.after, &pr = p.refined;
    int newRows = 0, oldRows = 0, other = 0;
    for (int y = 0; y < pr.height; ++y) {  // Image rows count from the top: GL's rows 0-1 are the last two
        bool isNew = true, isOld = true;
        for (int x = 0; x < pr.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = pr.at(x, y, c), va = pa.at(x, y, c), vb = pb.at(x, y, c);
                const bool nan = std::isnan(v);
                isNew = isNew && (nan ? std::isnan(vb) : v == vb);
                isOld = isOld && (nan ? std::isnan(va) : v == va);
            }
        if (isNew && !isOld) {
            ++newRows;
            EXPECT_GE(y, pr.height - 2);
        } else if (isOld && !isNew) {
            ++oldRows;
        } else if (!isNew && !isOld) {
            ++other;
        }
    }
    EXPECT_EQ(newRows, 2);
    EXPECT_GE(oldRows, pr.height / 2);  // rows the two cameras see alike (background) count as neither
    EXPECT_EQ(other, 0);
}

// A frame wider than a tile (Renderer::kTileColumns) runs in tiles of two rows, several a row: the
// first piece of a new camera's G-buffer is the bottom-left tile only, and the frame refined one tile
// a call equals the frame run whole (tolerance as above).
TEST_F(RefineFrameTest, TilesAcrossARowWriteOnlyTheirPixelsAndAddUpToTheWholeFrame) {
    Scene scene = loadScene("plant");
    RenderOptions options;
    options.width = 300;  // tiles of 128, 128 and 44 columns
    options.height = 40;
    for (const char* technique : {"hard", "pcf", "pcss", "sssm", "ssm-gbp06", "ssm-contour"}) {
        SCOPED_TRACE(technique);
        options.technique = technique;
        Renderer whole(scene, options), refined(scene, options);
        ASSERT_EQ(refined.tileColumns(), 3);
        whole.renderFrame(0, {"image", "visibility"});
        int calls = 0;
        double progress = 0.0;
        while (progress < 1.0 && calls < 4000) {
            progress = refined.refineFrame(0, {"image", "visibility"}, 0.001);
            ++calls;
        }
        ASSERT_EQ(progress, 1.0);
        EXPECT_GT(calls, 60);  // the G-buffer's 3 x 20 tiles one by one
        const Image a = whole.visibility(), b = refined.visibility();
        double worst = 0.0;
        for (size_t i = 0; i < a.data.size(); ++i) worst = std::max(worst, double(std::abs(a.data[i] - b.data[i])));
        EXPECT_LE(worst, 1e-5);
    }
    options.technique = "hard";
    const FirstPiece p = firstPieceOfAMovedCamera(scene, options);
    const Image &pb = p.before, &pa = p.after, &pr = p.refined;
    int newOutside = 0, newInside = 0, oldInside = 0;
    for (int y = 0; y < pr.height; ++y)
        for (int x = 0; x < pr.width; ++x) {
            const bool inside = y >= pr.height - 2 && x < Renderer::kTileColumns;  // GL rows 0-1, the first tile
            const float v = pr.at(x, y, 0), va = pa.at(x, y, 0), vb = pb.at(x, y, 0);
            const bool isNew = std::isnan(v) ? std::isnan(va) : v == va;
            const bool isOld = std::isnan(v) ? std::isnan(vb) : v == vb;
            if (isNew && !isOld) ++(inside ? newInside : newOutside);
            if (inside && isOld && !isNew) ++oldInside;
        }
    EXPECT_EQ(newOutside, 0);
    EXPECT_GT(newInside, 0);
    EXPECT_EQ(oldInside, 0);
}

// A refinement abandoned after a few scattered bands (a drag started) leaves a history that knows
// a few units: the next refinement of the pass is scattered again, not contiguous pieces sized by
// the mean of those few (which under-forecast a penumbra by 10x on plant).
TEST(PassGraphSliced, APartlyKnownHistoryIsNoForecast) {
    FakeGraph g;
    g.graph.executeSliced({"image"}, 0, g.timer, 10.0, g.slicing);  // the map and a few bands
    ASSERT_FALSE(g.pieces.empty());
    ASSERT_LT(g.pieces.size(), 20u);
    g.graph.setSource("camera", 3);  // a change: the half-done lookup is abandoned
    g.pieces.clear();
    double p = 0.0;
    for (int call = 0; call < 40 && p < 1.0; ++call) p = g.graph.executeSliced({"image"}, 1, g.timer, 10.0, g.slicing);
    ASSERT_EQ(p, 1.0);
    EXPECT_FALSE(std::is_sorted(g.pieces.begin(), g.pieces.end()));  // scattered bands again
    // Complete now: the next refinement has a forecast.
    g.graph.setSource("camera", 4);
    g.pieces.clear();
    p = 0.0;
    for (int call = 0; call < 40 && p < 1.0; ++call) p = g.graph.executeSliced({"image"}, 2, g.timer, 10.0, g.slicing);
    EXPECT_TRUE(std::is_sorted(g.pieces.begin(), g.pieces.end()));
}

// With a forecast, a unit is expected to cost what the dearest unit near it cost: rows that were
// cheap next to a dear one are not run in one piece with it (a penumbra that moved a row).
TEST(PassGraphSliced, AForecastTakesTheDearestNeighbour) {
    FakeGraph g;
    // Unit 50 costs 20 ms, the others 0.1 ms: a complete first refinement learns it.
    g.slicing.runUnits = [&g](const std::string&, int from, int to, const std::function<void()>&) {
        g.pieces.emplace_back(from, to);
        g.lastCost = 0.0;
        for (int k = from; k < to; ++k) g.lastCost += k == 50 ? 20.0 : 0.1;
    };
    double p = 0.0;
    for (int call = 0; call < 200 && p < 1.0; ++call) p = g.graph.executeSliced({"image"}, 0, g.timer, 10.0, g.slicing);
    ASSERT_EQ(p, 1.0);
    // The dear unit moves to 53; the forecast of 53 is 50's cost (within kForecastRows rows).
    g.slicing.runUnits = [&g](const std::string&, int from, int to, const std::function<void()>&) {
        g.pieces.emplace_back(from, to);
        g.lastCost = 0.0;
        for (int k = from; k < to; ++k) g.lastCost += k == 53 ? 20.0 : 0.1;
    };
    g.graph.setSource("camera", 9);
    g.pieces.clear();
    p = 0.0;
    double worst = 0.0;
    for (int call = 0; call < 200 && p < 1.0; ++call) {
        const size_t before = g.pieces.size();
        p = g.graph.executeSliced({"image"}, 1, g.timer, 10.0, g.slicing);
        double ms = 0.0;
        for (size_t i = before; i < g.pieces.size(); ++i)
            for (int k = g.pieces[i].first; k < g.pieces[i].second; ++k) ms += k == 53 ? 20.0 : 0.1;
        // A call runs 53 in a piece of its own (or with only a few cheap units): never 53 on top
        // of a budget's worth of cheap ones.
        for (size_t i = before; i < g.pieces.size(); ++i)
            if (g.pieces[i].first <= 53 && 53 < g.pieces[i].second) worst = std::max(worst, ms);
    }
    ASSERT_EQ(p, 1.0);
    EXPECT_LE(worst, 20.0 + 8 * 0.1 + 1e-9);
}

// The window's renderers keep what a resize replaced (RenderOptions::spareBytes): a return to a size
// allocates nothing (the same textures come back), and the frame there is the frame of a fresh
// renderer; with no spares allowed, nothing is kept.
TEST_F(RefineFrameTest, AReturnToASizeReusesItsTexturesAndRendersTheSameFrame) {
    Scene scene = loadScene("square-occluder");
    RenderOptions options = hardAt64x48();
    options.spareBytes = size_t(64) << 20;
    Renderer r(scene, options), fresh(scene, hardAt64x48());
    r.renderFrame(0, {"image", "visibility"});
    const GLuint visibilityId = r.pool().find("frame/visibility")->texture.id();
    const GLuint positionId = r.pool().find("frame/gbuffer.position")->texture.id();
    r.resize(32, 24);
    r.renderFrame(1, {"image", "visibility"});
    EXPECT_GT(r.pool().spareBytes(), 0u);
    r.resize(64, 48);
    EXPECT_EQ(r.pool().find("frame/visibility")->texture.id(), visibilityId);
    EXPECT_EQ(r.pool().find("frame/gbuffer.position")->texture.id(), positionId);
    r.renderFrame(2, {"image", "visibility"});
    fresh.renderFrame(2, {"image", "visibility"});
    const Image a = r.visibility(), b = fresh.visibility();
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i) ASSERT_EQ(a.data[i], b.data[i]) << i;
    // The spares stay under their bound, the oldest dropped first; 0 keeps nothing.
    r.pool().setSpareBytes(1);
    EXPECT_EQ(r.pool().spareBytes(), 0u);
    Renderer none(scene, hardAt64x48());
    none.renderFrame(0, {"visibility"});
    none.resize(32, 24);
    none.renderFrame(1, {"visibility"});
    EXPECT_EQ(none.pool().spareBytes(), 0u);
}

}  // namespace
// Renderer::shadeWith in bands of rows (the window's ray tracer shades a batch over frames): a band
// writes its rows only, and the bands together equal one whole shading.
TEST_F(RefineFrameTest, ShadeWithInBandsEqualsTheWholeShading) {
    Scene scene = loadScene("square-occluder");
    const RenderOptions options = hardAt64x48();
    Renderer whole(scene, options), banded(scene, options);
    Image half(64, 48, 1);
    std::fill(half.data.begin(), half.data.end(), 0.25f);
    Texture v = Texture::create2D(64, 48, Format::R32F);
    uploadTexture(v, 0, 0, half);
    whole.shadeWith(0, {&v});
    banded.renderFrame(0, {"visibility"});
    const Image before = banded.visibility();
    banded.shadeWith(0, {&v}, 0, 10);  // GL's rows 0-9: the image's last ten
    const Image w = whole.visibility(), first = banded.visibility();
    int changedOutside = 0, wrongInside = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool inside = y >= 48 - 10;
            if (inside && first.at(x, y, 0) != w.at(x, y, 0)) ++wrongInside;
            if (!inside && first.at(x, y, 0) != before.at(x, y, 0)) ++changedOutside;
        }
    EXPECT_EQ(wrongInside, 0);
    EXPECT_EQ(changedOutside, 0);
    bool differs = false;  // the test can fail: hard's visibility is not 0.25 everywhere
    for (size_t i = 0; i < w.data.size(); ++i) differs = differs || w.data[i] != before.data[i];
    EXPECT_TRUE(differs);
    banded.shadeWith(0, {&v}, 10, 33);
    banded.shadeWith(0, {&v}, 33, -1);
    const Image all = banded.visibility();
    const Image wi = whole.image(), bi = banded.image();
    for (size_t i = 0; i < w.data.size(); ++i) ASSERT_EQ(all.data[i], w.data[i]) << i;
    for (size_t i = 0; i < wi.data.size(); ++i) ASSERT_EQ(bi.data[i], wi.data[i]) << i;
}

}  // namespace shadowlab
