// The window's docked layout (app/window/layout.cpp, issue 18): at the five window sizes a lecture
// meets, UI scales 1 to 2, with and without a lesson and views, in normal and presentation mode,
// no two regions intersect, every region lies inside the window, and the technique view keeps at
// least 40% of the window without views and 25% with a lesson and two views; then the same on the
// window itself, from its --report.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli_run.h"
#include "window/layout.h"

namespace shadowlab {
namespace {

struct Config {
    const char* name;
    bool lesson, present;
    std::vector<float> cells;
    float minTechnique;  // fraction of the window's area
    bool panel = true;
};

TEST(WindowLayout, NothingOverlapsAndTheTechniqueViewKeepsItsShare) {
    const glm::vec2 sizes[] = {{1024, 768}, {1280, 720}, {1366, 768}, {1920, 1080}, {3840, 2160}};
    const std::vector<Config> configs = {
        {"nothing open", false, false, {}, 0.40f},
        {"a lesson", true, false, {}, 0.40f},
        {"a lesson and two views", true, false, {4.0f / 3.0f, 4.0f / 3.0f}, 0.25f},
        {"two views", false, false, {4.0f / 3.0f, 1.0f}, 0.25f},
        {"a lesson, four views and the chart", true, false, {4.0f / 3.0f, 4.0f / 3.0f, 2.0f, 1.0f, 1.6f}, 0.20f},
        {"presentation, a lesson", true, true, {}, 0.40f},
        {"panel hidden, two views", false, false, {4.0f / 3.0f, 1.0f}, 0.40f, false},
        {"panel hidden, nothing open", false, false, {}, 0.55f, false},
        {"presentation, a lesson and two views", true, true, {4.0f / 3.0f, 4.0f / 3.0f}, 0.25f},
    };
    for (const glm::vec2 size : sizes)
        for (float scale : {1.0f, 1.5f, 2.0f})
            for (const Config& c : configs) {
                LayoutInput in;
                in.window = size;
                in.uiScale = c.present ? presentationUiScale(size.y) : scale;
                in.lesson = c.lesson;
                in.present = c.present;
                in.panel = c.panel;
                in.cellAspects = c.cells;
                const WindowLayout layout = computeWindowLayout(in);
                SCOPED_TRACE(std::string(c.name) + " at " + std::to_string(int(size.x)) + "x" + std::to_string(int(size.y)) +
                             " scale " + std::to_string(in.uiScale) + ": " + layout.toJson().dump());
                const auto regions = layout.regions();
                for (size_t i = 0; i < regions.size(); ++i) {
                    EXPECT_TRUE(regions[i].second.inside(size)) << regions[i].first;
                    for (size_t j = i + 1; j < regions.size(); ++j)
                        EXPECT_FALSE(regions[i].second.intersects(regions[j].second))
                            << regions[i].first << " and " << regions[j].first;
                }
                EXPECT_GE(layout.technique.area(), c.minTechnique * size.x * size.y);
                EXPECT_EQ(layout.lesson.empty(), !c.lesson);
                // Every view gets a cell at its own aspect (the image above a caption band).
                ASSERT_EQ(layout.cells.size(), c.cells.size());
                if (c.cells.size() <= 2)
                    for (size_t k = 0; k < c.cells.size(); ++k) {
                        EXPECT_FALSE(layout.cells[k].empty()) << "cell " << k;
                        EXPECT_GT(layout.cells[k].h, 0.2f * size.y) << "cell " << k << " is too small to read";
                    }
                if (c.present) EXPECT_NEAR(layout.lesson.w, size.x / 3.0f, 1.0f);
            }
}

TEST(WindowLayout, ViewsTakeMoreRowsWhenTheyDoNotFitInOne) {
    LayoutInput in;
    in.window = {1024, 768};
    in.lesson = true;
    in.cellAspects = {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};
    const WindowLayout layout = computeWindowLayout(in);
    EXPECT_GE(layout.stripRows, 1);
    for (const LayoutRect& c : layout.cells) {
        EXPECT_FALSE(c.empty());
        EXPECT_GE(c.x, layout.strip.x - 1e-3f);
        EXPECT_LE(c.right(), layout.strip.right() + 1e-3f);  // never cut off at the window's edge
    }
    // Wide views in a narrow window: two rows beat one row of slivers.
    in.window = {1024, 1400};
    in.cellAspects = {2.0f, 2.0f, 2.0f, 2.0f};
    EXPECT_GE(computeWindowLayout(in).stripRows, 2);
}

TEST(WindowLayout, PresentationTextIsReadableFromTheBack) {
    for (float h : {720.0f, 768.0f, 1080.0f, 2160.0f}) EXPECT_GE(13.0f * presentationUiScale(h), h / 40.0f) << h;
}

}  // namespace
}  // namespace shadowlab

// The same checks on the window itself (under a virtual X server): its --report gives each frame's
// layout, here with a lesson and two views open, at the five sizes and in presentation mode.
namespace shadowlab {
namespace {

test::Result runXvfbLarge(const std::string& arguments) {
    test::Result r;
    const std::string command = "xvfb-run -a -s '-screen 0 3840x2160x24' " + std::string(SHADOWLAB_BINARY) + " " +
                                arguments + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    const int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

TEST(WindowLayout, TheWindowsReportedRegionsNeverOverlap) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run is not installed";
    struct Run {
        int w, h;
        bool present, lesson;
    };
    for (const Run run : {Run{1024, 768, false, true}, Run{1280, 720, false, true}, Run{1366, 768, false, false},
                          Run{1920, 1080, false, true}, Run{3840, 2160, false, true}, Run{1024, 768, true, true},
                          Run{1920, 1080, true, true}}) {
        const std::string name = std::to_string(run.w) + "x" + std::to_string(run.h) + (run.present ? "-present" : "") +
                                 (run.lesson ? "-lesson" : "");
        SCOPED_TRACE(name);
        const std::string script = test::testPath("window-layout", name + ".txt");
        const std::string report = test::testPath("window-layout", name + ".json");
        std::filesystem::remove(report);
        std::ofstream(script) << "background off\nview scene3d\nview shadow-map\nviews on\nwait 3\n";
        auto r = runXvfbLarge(std::string("window --scene square-occluder --technique pcf --size ") + std::to_string(run.w) +
                              "x" + std::to_string(run.h) + (run.present ? " --present" : "") +
                              (run.lesson ? " --lesson intro" : "") + " --script " + script + " --report " + report);
        ASSERT_EQ(r.code, 0) << r.output;
        std::ifstream in(report);
        ASSERT_TRUE(in) << r.output;
        const nlohmann::json frames = nlohmann::json::parse(in)["frames"];
        ASSERT_FALSE(frames.empty());
        const nlohmann::json& last = frames.back();
        const glm::vec2 window(last["window"][0].get<float>(), last["window"][1].get<float>());
        EXPECT_EQ(window, glm::vec2(run.w, run.h)) << "the window did not open at its size";
        std::vector<std::pair<std::string, LayoutRect>> regions;
        for (const auto& [key, v] : last["layout"].items()) {
            if (!v.is_array()) continue;
            regions.push_back({key, LayoutRect{v[0].get<float>(), v[1].get<float>(), v[2].get<float>(), v[3].get<float>()}});
        }
        size_t cells = 0;
        for (size_t i = 0; i < regions.size(); ++i) {
            cells += regions[i].first.rfind("cell", 0) == 0;
            EXPECT_TRUE(regions[i].second.inside(window)) << regions[i].first;
            for (size_t j = i + 1; j < regions.size(); ++j)
                EXPECT_FALSE(regions[i].second.intersects(regions[j].second)) << regions[i].first << " and " << regions[j].first;
        }
        EXPECT_EQ(cells, 2u) << last["layout"].dump();
        const nlohmann::json& t = last["layout"]["technique"];
        EXPECT_GE(t[2].get<float>() * t[3].get<float>(), 0.25f * window.x * window.y) << last["layout"].dump();
        // The renderer renders at the technique view's size.
        EXPECT_NEAR(last["render_size"][0].get<float>(), t[2].get<float>(), 1.0f);
        EXPECT_NEAR(last["render_size"][1].get<float>(), t[3].get<float>(), 1.0f);
    }
}

}  // namespace
}  // namespace shadowlab
