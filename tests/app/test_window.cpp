// The window under a virtual X server (xvfb-run), driven by --script: every technique and scene
// selected through the panel's actions and by keys, the camera and the light moved with mouse
// drags, a resize, screenshots compared; the progressive reference against `shadowlab reference`;
// bad scripts; `shadowlab` with no display.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "graph/technique.h"
#include "image/image.h"
#include "image/metrics.h"
#include "scene/scene.h"
#include "support/cli_run.h"
#include "support/real_meshes.h"
#include "window/window.h"

namespace {

namespace fs = std::filesystem;
using shadowlab::Image;
using shadowlab::test::run;

std::string tmp(const std::string& name) { return shadowlab::test::testPath("window", name); }

bool haveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

shadowlab::test::Result runWindow(const std::string& arguments) {
    return run("window " + arguments);  // the binary under xvfb-run: see xvfb() below
}

std::string xvfb(const std::string& arguments) {
    return "xvfb-run -a -s '-screen 0 800x600x24' " + std::string(SHADOWLAB_BINARY) + " " + arguments;
}

shadowlab::test::Result runXvfb(const std::string& arguments) {
    shadowlab::test::Result r;
    FILE* pipe = popen((xvfb(arguments) + " 2>&1").c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// Mean absolute difference over the view, leaving out the bottom rows (the status line).
double meanDiff(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return 1.0;
    double sum = 0.0;
    size_t n = 0;
    int rows = a.height * 85 / 100;
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 3; ++c, ++n) sum += std::abs(a.at(x, y, c) - b.at(x, y, c));
    return sum / double(n);
}

// One session: every technique and scene through the panel's actions and by keys, camera and light
// dragged, reset, resized. Each screenshot must differ from the one before (a change of state that
// shows), except after the camera reset, which must give back the first picture.
TEST(Window, EveryTechniqueSceneCameraLightAndResize) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::vector<std::string> techniques;
    for (const shadowlab::TechniqueDesc* d : shadowlab::allTechniques())
        if (d->id != "raytraced") techniques.push_back(d->id);  // progressive on a thread (tested below)
    std::vector<std::string> scenes = shadowlab::testing::loadableScenes();
    ASSERT_GE(techniques.size(), 3u);
    ASSERT_GE(scenes.size(), 2u);

    std::ofstream script(tmp("session.txt"));
    std::vector<std::pair<std::string, std::string>> shots;  // (file, what changed)
    auto shot = [&](const std::string& what) {
        std::string file = tmp("shot" + std::to_string(shots.size()) + ".pfm");
        fs::remove(file);
        script << "screenshot " << file << "\n";
        shots.push_back({file, what});
    };
    script << "panel off\nkey h\nbackground off\nreference-samples 16\n";
    shot("start: square-occluder, pcf");
    for (const std::string& t : techniques) {
        if (t == "pcf") continue;
        script << "technique " << t << "\n";
        if (t == "reference") script << "wait-reference 400\n";
        shot("panel: technique " + t);
    }
    script << "technique pcf\n";
    shot("panel: technique pcf");
    for (size_t i = 0; i < techniques.size(); ++i) {  // T cycles through every technique back to pcf
        script << "key t\n";
        if (techniques[(i + 2) % techniques.size()] == "reference") script << "wait-reference 400\n";
        shot("key T -> " + techniques[(i + 2) % techniques.size()]);
    }
    for (const std::string& s : scenes) {
        if (s == "square-occluder") continue;
        script << "scene " << s << "\n";
        shot("panel: scene " + s);
    }
    script << "scene square-occluder\n";
    shot("panel: scene square-occluder");
    script << "key s\n";
    shot("key S");
    script << "key s shift\n";
    shot("key Shift+S (back to square-occluder)");
    script << "drag left none 100 100 160 110 4\n";
    shot("orbit drag");
    script << "drag right none 100 100 130 120 3\n";
    shot("pan drag");
    script << "scroll 2\n";
    shot("wheel zoom");
    script << "key r\n";
    shot("key R: camera reset");
    script << "scroll -4\n";
    shot("zoom out: the light's outline in view");
    script << "drag left shift 120 120 170 120 4\n";
    shot("light drag (Shift)");
    script << "key ]\n";
    shot("light larger");
    script << "resize 300 200\n";
    shot("resize 300x200");
    script.close();

    auto r = runXvfb("window --scene square-occluder --technique pcf --size 240x180 --script " + tmp("session.txt"));
    ASSERT_EQ(r.code, 0) << r.output;  // 1 = a GL error was raised
    std::vector<Image> images;
    for (const auto& [file, what] : shots) {
        ASSERT_TRUE(fs::exists(file)) << what << "\n" << r.output;
        images.push_back(shadowlab::readPFM(file));
    }
    // 0.0005: about one pixel in 2000 changing fully; a changed technique, scene or pose changes far more.
    for (size_t i = 1; i < images.size(); ++i) {
        const std::string& what = shots[i].second;
        double d = meanDiff(images[i], images[i - 1]);
        if (what == "key T -> pcf" && techniques.size() == 3) {
            EXPECT_GT(d, 0.0005) << what;
        } else if (what.rfind("key R", 0) == 0) {
            // The reset gives back the starting camera: the picture of the scene's first shot.
            size_t first = 0;
            for (size_t k = 0; k < shots.size(); ++k)
                if (shots[k].second == "key Shift+S (back to square-occluder)") first = k;
            EXPECT_LT(meanDiff(images[i], images[first]), 1e-6) << what;
            EXPECT_GT(d, 0.0005) << what;
        } else if ((what.find("ssm-contour") != std::string::npos && shots[i - 1].second.find("ssm-gbp06") != std::string::npos) ||
                   (what.find("ssv") != std::string::npos && shots[i - 1].second.find("ssm-contour") != std::string::npos)) {
            // Both back-projections are exact on square-occluder's plate parallel to the light (its
            // samples tile it: RMSE 0.0045 over the penumbra for both, test_backprojection_render.cpp),
            // and so are the penumbra wedges (a planar polygon: RMSE 0.0001, test_ssv.cpp): the same
            // picture to rounding; with the light-space multi-resolution (sec. 5.1) GBP06's coarse
            // levels fatten the plate's border by up to a coarse texel where the contour's shrink it
            // back (t = 1, Fig. 7c): 0.0009 measured at 240 x 180, bounded by 0.002.
            EXPECT_LT(d, 0.002) << what;
        } else {
            EXPECT_GT(d, 0.0005) << what << " (shot " << i << ")";
        }
    }
    EXPECT_EQ(images.front().width, 240);
    EXPECT_EQ(images.back().width, 300);
    EXPECT_EQ(images.back().height, 200);
}

// The progressive reference, run a few samples per frame, is the `reference` technique's result:
// the same stratified light samples, summed in another order (float rounding only).
TEST(Window, ProgressiveReferenceEqualsTheReferenceCommand) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::ofstream(tmp("ref.txt")) << "reference-samples 32\nwait-reference 400\nsave-reference " << tmp("window.pfm")
                                  << "\nsave-visibility " << tmp("pcf.pfm") << "\n";
    auto r = runXvfb("window --scene square-occluder --technique pcf --size 200x150 --script " + tmp("ref.txt"));
    ASSERT_EQ(r.code, 0) << r.output;
    // The technique view is the window less its status line (window/layout.h): the commands render
    // at the size the window rendered.
    const Image shown = shadowlab::readPFM(tmp("pcf.pfm"));
    const std::string size = std::to_string(shown.width) + "x" + std::to_string(shown.height);
    EXPECT_GT(shown.width, 100);
    EXPECT_GT(shown.height, 100);
    auto c = run("reference --scene square-occluder --samples 32 --size " + size + " --out " + tmp("cli.pfm"));
    ASSERT_EQ(c.code, 0) << c.output;
    auto p = run("render --scene square-occluder --technique pcf --size " + size + " --visibility " + tmp("cli-pcf.pfm"));
    ASSERT_EQ(p.code, 0) << p.output;
    Image w = shadowlab::readPFM(tmp("window.pfm")), ref = shadowlab::readPFM(tmp("cli.pfm"));
    Image wp = shadowlab::readPFM(tmp("pcf.pfm")), cp = shadowlab::readPFM(tmp("cli-pcf.pfm"));
    ASSERT_EQ(w.data.size(), ref.data.size());
    double maxDiff = 0.0, penumbra = 0.0;
    for (size_t i = 0; i < w.data.size(); ++i) {
        maxDiff = std::max(maxDiff, double(std::abs(w.data[i] - ref.data[i])));
        if (ref.data[i] > 0.01f && ref.data[i] < 0.99f) ++penumbra;
    }
    EXPECT_LT(maxDiff, 1e-5);  // 32 weights of 1/32 summed in float: rounding is ~1e-7
    EXPECT_GT(penumbra, 100);  // the reference has a penumbra: not a trivially equal pair
    ASSERT_EQ(wp.data.size(), cp.data.size());
    for (size_t i = 0; i < wp.data.size(); ++i) ASSERT_EQ(wp.data[i], cp.data[i]) << "pixel " << i;
}

// The views panel: VTK views rendered into the window's context; picking another pixel re-renders
// them (the screenshot changes); no GL error (exit code 0).
TEST(Window, ViewsPanelFollowsThePickedPixel) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::ofstream(tmp("views.txt")) << "panel off\nkey h\nbackground off\nview scene3d\nview shadow-map\n"
                                    << "pick 100 150\nwait 4\nscreenshot " << tmp("a.pfm") << "\n"
                                    << "pick 200 130\nwait 4\nscreenshot " << tmp("b.pfm") << "\n"
                                    << "close-view scene3d\nclose-view shadow-map\nwait 1\nscreenshot " << tmp("c.pfm")
                                    << "\n";
    auto r = runXvfb("window --scene square-occluder --technique pcf --size 640x480 --script " + tmp("views.txt"));
    ASSERT_EQ(r.code, 0) << r.output;
    Image a = shadowlab::readPFM(tmp("a.pfm")), b = shadowlab::readPFM(tmp("b.pfm")), c = shadowlab::readPFM(tmp("c.pfm"));
    // The views occupy the bottom of the window: compare the bottom half, where they are.
    auto bottomDiff = [](const Image& x, const Image& y) {
        double sum = 0.0;
        size_t n = 0;
        for (int row = x.height / 2; row < x.height; ++row)
            for (int col = 0; col < x.width; ++col)
                for (int k = 0; k < 3; ++k, ++n) sum += std::abs(x.at(col, row, k) - y.at(col, row, k));
        return sum / double(n);
    };
    EXPECT_GT(bottomDiff(a, b), 0.0005);  // the picked point, its rays and texels moved
    EXPECT_GT(bottomDiff(b, c), 0.01);    // closing the views uncovers the technique view
}

// `raytraced` in the window is the progressive ray tracer: rays per pixel traced in batches on a
// worker thread, each batch shown as it lands. Complete, it is `render --technique raytraced`'s
// visibility (the same rays and weights, summed in another order: float rounding only). Selected as
// the technique and as the split's reference of another technique.
TEST(Window, ProgressiveRaytracedEqualsTheRaytracedCommand) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::ofstream(tmp("rt.txt")) << "panel off\ntechnique raytraced\nparam rays 24\nwait-reference 3000\nsave-visibility "
                                 << tmp("rt-window.pfm") << "\ntechnique pcf\nreference raytraced\nreference-rays 12\n"
                                 << "split reference\nwait-reference 3000\nsave-reference " << tmp("rt-split.pfm")
                                 << "\nsave-visibility " << tmp("rt-pcf.pfm") << "\n";
    auto r = runXvfb("window --scene square-occluder --technique hard --size 200x150 --report " + tmp("rt.json") +
                     " --script " + tmp("rt.txt"));
    ASSERT_EQ(r.code, 0) << r.output;
    const Image shown = shadowlab::readPFM(tmp("rt-pcf.pfm"));
    const std::string size = std::to_string(shown.width) + "x" + std::to_string(shown.height);
    for (const auto& [file, rays] : {std::pair<std::string, int>{"rt-window.pfm", 24}, {"rt-split.pfm", 12}}) {
        auto c = run("render --scene square-occluder --technique raytraced --set rays=" + std::to_string(rays) +
                     " --size " + size + " --visibility " + tmp("rt-cli.pfm"));
        ASSERT_EQ(c.code, 0) << c.output;
        Image w = shadowlab::readPFM(tmp(file)), cli = shadowlab::readPFM(tmp("rt-cli.pfm"));
        ASSERT_EQ(w.data.size(), cli.data.size()) << file;
        double maxDiff = 0.0;
        size_t penumbra = 0;
        for (size_t i = 0; i < w.data.size(); ++i) {
            maxDiff = std::max(maxDiff, double(std::abs(w.data[i] - cli.data[i])));
            if (cli.data[i] > 0.01f && cli.data[i] < 0.99f) ++penumbra;
        }
        EXPECT_LT(maxDiff, 1e-5) << file;  // M weights summed in double in two orders, then rounded to float
        EXPECT_GT(penumbra, 100u) << file;  // a real penumbra: not a trivially equal pair
    }
    // The report says what each side accumulated. (Which batches a frame shows depends on the
    // threads' timing: at this size the worker traces all 24 rays in a few ms. The batches' sums are
    // tested in RayTracer.BatchesOfSpreadSamplesSumToTheWholeTrace.)
    const nlohmann::json frames = nlohmann::json::parse(std::ifstream(tmp("rt.json")))["frames"];
    bool completeShown = false, splitComplete = false;
    for (const auto& f : frames) {
        if (f["technique"] == "raytraced") {  // the view shows the ray tracer; the reference stays `reference`
            EXPECT_EQ(f["reference_technique"], "reference");
            completeShown |= f["shown_samples"] == 24 && f["shown_total"] == 24;
        } else if (f["reference_technique"] == "raytraced") {  // pcf against the ray tracer
            splitComplete |= f["reference_samples"] == 12 && f["reference_total"] == 12;
        }
    }
    EXPECT_TRUE(completeShown);
    EXPECT_TRUE(splitComplete);
}

// Bad input is refused before a window opens, naming the file and line (exit code 2).
TEST(Window, BadScriptsAndFlags) {
    std::ofstream(tmp("bad.txt")) << "panel off\n\nkey t\ndrag left none 1 2 3\n";
    auto r = runWindow("--script " + tmp("bad.txt"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("bad.txt:4"), std::string::npos) << r.output;
    std::ofstream(tmp("bad2.txt")) << "technique nosuch\n";
    r = runWindow("--script " + tmp("bad2.txt"));
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("bad2.txt:1: unknown technique 'nosuch'"), std::string::npos) << r.output;
    r = runWindow("--technique nosuch");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("hard"), std::string::npos) << r.output;  // the choices are listed
    r = runWindow("--screenshot " + tmp("no/such/folder/x.png"));
    EXPECT_EQ(r.code, 2);
    r = runWindow("--scene nosuch");
    EXPECT_EQ(r.code, 2);
}

// Issue 24: a script's numbers are checked in the type the window runs them in, and a script is
// a regular file. Each of these was accepted before: "ui-scale nan" then aborted in ImGui,
// "wait 99999999999" exited 1 ("stoi") after the window opened, "pick 1.5 2" picked 1,2, a folder
// was an empty script (exit 0, nothing done) and a FIFO blocked forever.
TEST(Window, ScriptNumbersAreCheckedInTheirTypeAndAScriptIsARegularFile) {
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"ui-scale nan", "ui-scale: expected a UI scale in [0.5, 4], got 'nan'"},
        {"ui-scale 0", "ui-scale: expected a UI scale in [0.5, 4], got '0'"},
        {"wait 99999999999", "wait: expected a whole number of frames in [0, 1e+07], got '99999999999'"},
        {"wait 2.5", "wait: expected a whole number of frames"},
        {"wait-reference -1", "wait-reference: expected a whole number of frames"},
        {"pick 1.5 2", "pick: expected a whole number of a pixel column in [0, 8191], got '1.5'"},
        {"pick 3 inf", "pick: expected a whole number of a pixel row"},
        {"split-at 1.5", "split-at: expected a fraction of the view's width in [0, 1], got '1.5'"},
        {"scroll 1e308", "scroll: expected wheel steps in [-1000, 1000]"},
        {"drag-light 1e30 0 10", "drag-light: expected window units in [-100000, 100000], got '1e30'"},
        {"drag-light 10 0 0", "drag-light: expected a whole number of frames in [1, 1e+07], got '0'"},
        {"drag left none 0 0 nan 1 5", "drag: expected window units"},
        {"resize 640.5 480", "resize: expected a whole number of a window width in [64, 8192]"},
        {"reference-samples 1.5", "reference-samples: expected a whole number of samples in [1, 65536]"},
    };
    for (const auto& [line, message] : bad) {
        SCOPED_TRACE(line);
        std::ofstream(tmp("num.txt")) << "panel off\n" << line << "\n";
        auto r = runWindow("--script " + tmp("num.txt"));
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_NE(r.output.find("num.txt:2: " + message), std::string::npos) << r.output;
    }
    // A folder, a FIFO and a device are no script: exit 2 at once, naming the path.
    fs::create_directories(tmp("a-folder"));
    const std::string fifo = tmp("a-fifo");
    fs::remove(fifo);
    ASSERT_EQ(std::system(("mkfifo " + fifo).c_str()), 0);
    for (const std::string& path : {tmp("a-folder"), fifo, std::string("/dev/zero")}) {
        SCOPED_TRACE(path);
        auto r = runWindow("--script " + path);
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_NE(r.output.find(path + ": cannot read the window script: it is "), std::string::npos) << r.output;
    }
    fs::remove(fifo);
}

// What the parser checked is what the runner runs: each number is rewritten in the form its
// conversion (stoi, stof) reads back exactly. Before, "wait 1e3" was checked as 1000 frames and
// waited 1 (stoi), "pick 0x10 2" was checked as 16 and picked 0, and "split-at 1e-50" passed the
// check and then threw out_of_range from stof in the running window (exit 1). Found by fuzz_window_script.
TEST(Window, ScriptNumbersRunAsTheyWereChecked) {
    std::ofstream(tmp("canon.txt")) << "wait 1e3\npick 0x10 2\nsplit-at 1e-50\nui-scale 1.50\ndrag-light 1e2 -0.5 2.0\n";
    const std::deque<shadowlab::ScriptCommand> script = shadowlab::parseScript(tmp("canon.txt"));
    ASSERT_EQ(script.size(), 5u);
    EXPECT_EQ(script[0].args, std::vector<std::string>({"1000"}));
    EXPECT_EQ(script[1].args, std::vector<std::string>({"16", "2"}));
    EXPECT_EQ(script[2].args, std::vector<std::string>({"0"}));
    EXPECT_EQ(script[3].args, std::vector<std::string>({"1.5"}));
    EXPECT_EQ(script[4].args, std::vector<std::string>({"100", "-0.5", "2"}));
    EXPECT_EQ(std::stoi(script[0].args[0]), 1000);
    EXPECT_EQ(std::stof(script[2].args[0]), 0.0f);  // threw std::out_of_range before
}

// The window estimates memory as the commands do (issue 24): its first technique at its size
// before it opens (exit 2, no window), and every later technique or parameter as it is asked for
// (refused in the status line, the old one kept running).
TEST(Window, MemoryIsEstimatedBeforeTheWindowOpensAndOnEveryChange) {
    auto r = runWindow("--scene square-occluder --technique ssm-gbp06 --size 640x480 --max-memory-mb 16");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("window: ssm-gbp06 at 640x480: this render would need about"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("over the limit of 16 MB"), std::string::npos) << r.output;
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::ofstream(tmp("memory.txt")) << "wait 2\nparam sm_size 8192\nwait 1\ntechnique ssm-gbp06\nparam sm_size 4096\nwait 1\n";
    r = runXvfb("window --scene square-occluder --technique hard --size 640x480 --max-memory-mb 200 --script " +
                tmp("memory.txt") + " --report " + tmp("memory.json"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("hard with these parameters would need about"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("over the limit of 200 MB (--max-memory-mb N raises it): not applied"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ssm-gbp06 with these parameters would need about"), std::string::npos) << r.output;
}

// `auto` in the window (issue 25): the budget slider (a `param` like any other) changes each light's
// pick live, without restarting anything, and the visibility shown is the headless render's at the
// same budget and size.
TEST(Window, TheAutoBudgetChangesTheChoiceLive) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::ofstream(tmp("auto.txt")) << "technique auto\nparam error_budget 0.5\nwait 1\nsave-visibility " << tmp("auto-loose.pfm")
                                   << "\nparam error_budget 0.002\nwait 1\nsave-visibility " << tmp("auto-tight.pfm")
                                   << "\nscreenshot " << tmp("auto.png") << "\n";
    auto r = runXvfb("window --scene square-occluder --technique hard --size 640x480 --script " + tmp("auto.txt"));
    ASSERT_EQ(r.code, 0) << r.output;
    const Image loose = shadowlab::readPFM(tmp("auto-loose.pfm")), tight = shadowlab::readPFM(tmp("auto-tight.pfm"));
    ASSERT_EQ(loose.width, tight.width);
    // 0.5 takes a hard-shadow setting, 0.002 the most accurate: the penumbra differs.
    EXPECT_GT(shadowlab::computeMetrics(loose, tight).rmse, 0.02);
    const std::string size = std::to_string(tight.width) + "x" + std::to_string(tight.height);
    auto c = run("render --scene square-occluder --technique auto --set error_budget=0.002 --size " + size + " --visibility " +
                 tmp("auto-cli.pfm"));
    ASSERT_EQ(c.code, 0) << c.output;
    EXPECT_LT(shadowlab::computeMetrics(tight, shadowlab::readPFM(tmp("auto-cli.pfm"))).rmse, 0.002);
}

// `shadowlab` with no arguments and no display renders the default scene headless into
// ./shadowlab-output and says so; exit code 0. `shadowlab window` with no display: exit code 2.
TEST(Window, NoDisplayFallsBackToAHeadlessRender) {
    fs::path dir = fs::path(tmp("cwd"));
    fs::create_directories(dir);
    std::string command = "cd " + dir.string() + " && env -u DISPLAY -u WAYLAND_DISPLAY " + SHADOWLAB_BINARY + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string out;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
    int status = pclose(pipe);
    EXPECT_EQ(WEXITSTATUS(status), 0) << out;
    fs::path png = dir / "shadowlab-output" / "square-occluder-pcf.png";
    EXPECT_TRUE(fs::exists(png)) << out;
    EXPECT_NE(out.find(png.string()), std::string::npos) << out;  // it says where the output went
    EXPECT_NE(out.find("no window"), std::string::npos) << out;
    auto r = run("window");  // the tests run without DISPLAY unless under xvfb
    if (!std::getenv("DISPLAY")) {
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_NE(r.output.find("xvfb-run"), std::string::npos) << r.output;
    }
}

}  // namespace

// A view enlarged over the technique view (its "enlarge" button, the script's `enlarge-view`) is
// rendered at that region's size, far larger than its cell, and goes back to its cell with
// `enlarge-view off`; closing it ends the enlargement; an unknown name is refused with its line.
TEST(Window, AViewEnlargedTakesTheTechniqueViewsRegion) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    // The views render one per frame once the frame is complete: each phase waits for that.
    std::ofstream(tmp("enlarge.txt")) << "background off\nview scene3d\nview shadow-map\nwait 12\n"
                                      << "enlarge-view shadow-map\nwait 12\nscreenshot " << tmp("enlarged.pfm") << "\n"
                                      << "enlarge-view off\nwait 12\nscreenshot " << tmp("restored.pfm") << "\n"
                                      << "enlarge-view scene3d\nwait 2\nclose-view scene3d\nwait 2\n";
    const std::string report = tmp("enlarge.json");
    std::filesystem::remove(report);
    auto r = runXvfb("window --scene square-occluder --technique pcf --size 640x480 --script " + tmp("enlarge.txt") +
                     " --report " + report);
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream in(report);
    ASSERT_TRUE(in) << r.output;
    const nlohmann::json frames = nlohmann::json::parse(in)["frames"];
    ASSERT_FALSE(frames.empty());
    // The last frame of each phase: shadow-map enlarged, then restored, then scene3d enlarged and closed.
    const nlohmann::json* enlarged = nullptr;
    const nlohmann::json* restored = nullptr;
    bool scene3dEnlarged = false;
    for (const nlohmann::json& f : frames) {
        const std::string e = f["enlarged_view"];
        if (e == "shadow-map") enlarged = &f;
        if (e == "scene3d") scene3dEnlarged = true;
        if (enlarged && e.empty() && !scene3dEnlarged) restored = &f;
    }
    ASSERT_TRUE(enlarged && restored) << "the report never showed shadow-map enlarged and then restored";
    ASSERT_TRUE((*enlarged)["view_frames"].contains("shadow-map")) << (*enlarged).dump();
    ASSERT_TRUE((*restored)["view_frames"].contains("shadow-map")) << (*restored).dump();
    ASSERT_TRUE((*restored)["layout"].contains("cell 1")) << (*restored).dump();
    EXPECT_TRUE(scene3dEnlarged);
    EXPECT_EQ(frames.back()["enlarged_view"], "") << "closing the enlarged view ends the enlargement";
    const nlohmann::json& technique = (*enlarged)["layout"]["technique"];
    const nlohmann::json& cell = (*restored)["layout"]["cell 1"];
    const float bigW = (*enlarged)["view_frames"]["shadow-map"][0], bigH = (*enlarged)["view_frames"]["shadow-map"][1];
    const float smallW = (*restored)["view_frames"]["shadow-map"][0];
    // Enlarged: the technique view's width less the window padding, its height less the title line.
    EXPECT_NEAR(bigW, technique[2].get<float>(), 8.0f);
    EXPECT_GT(bigH, 0.8f * technique[3].get<float>());
    EXPECT_GT(bigW, 1.5f * cell[2].get<float>());
    EXPECT_LE(smallW, cell[2].get<float>());
    // The enlarged view covers the technique image: the top of the window differs.
    Image a = shadowlab::readPFM(tmp("enlarged.pfm")), b = shadowlab::readPFM(tmp("restored.pfm"));
    EXPECT_GT(meanDiff(a, b), 0.02);

    std::ofstream(tmp("enlarge-bad.txt")) << "wait 1\nenlarge-view nosuch\n";
    auto bad = runXvfb("window --scene square-occluder --technique pcf --size 320x240 --script " + tmp("enlarge-bad.txt"));
    EXPECT_EQ(bad.code, 2) << bad.output;
    EXPECT_NE(bad.output.find("enlarge-bad.txt:2: enlarge-view: expected off or a view"), std::string::npos) << bad.output;
}
