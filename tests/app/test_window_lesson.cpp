// The lesson player in the window (app/window/lesson_host.cpp) under a virtual X server: each step
// restores its own state whatever the user changed (the visibility read back from the window is
// bit-identical), a task fails in the step's own state and passes after "show me" through the
// window's own buffers, and a bad lesson is refused before the window opens.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "support/cli_run.h"

namespace {
namespace fs = std::filesystem;
using shadowlab::Image;

std::string tmp(const std::string& name) { return shadowlab::test::testPath("window-lesson", name); }
bool haveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

shadowlab::test::Result runXvfb(const std::string& arguments) {
    shadowlab::test::Result r;
    std::string command = "xvfb-run -a -s '-screen 0 800x600x24' " + std::string(SHADOWLAB_BINARY) + " " + arguments + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

bool identical(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels && a.data == b.data;
}

TEST(WindowLesson, StepsRestoreTheirStateAndTasksCheckBothWays) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::string v1 = tmp("v1.pfm"), v1b = tmp("v1b.pfm"), v2 = tmp("v2.pfm"), v2r = tmp("v2r.pfm"), v2u = tmp("v2u.pfm");
    for (const std::string& f : {v1, v1b, v2, v2r, v2u}) fs::remove(f);
    std::string scriptPath = tmp("lesson.txt");
    std::ofstream script(scriptPath);
    script << "panel off\nbackground off\nwait 1\n"
           << "save-visibility " << v1 << "\n"
           << "lesson next\nwait 1\n"                    // step 2: acne at zero bias (a task)
           << "save-visibility " << v2 << "\n"
           << "lesson check\n"                           // the step's own state: not yet
           << "param bias_const 4\ntechnique pcf\nwait 1\n"  // the student changes things
           << "save-visibility " << v2u << "\n"
           << "lesson restore\nwait 1\n"
           << "save-visibility " << v2r << "\n"
           << "lesson next\nwait 1\nlesson previous\nlesson previous\nwait 1\n"
           << "save-visibility " << v1b << "\n"
           << "lesson next\nlesson show-me\nwait 1\nlesson check\n";  // the answer: passed
    script.close();
    auto r = runXvfb("window --lesson shadow-mapping --size 320x240 --script " + scriptPath);
    ASSERT_EQ(r.code, 0) << r.output;
    Image a1 = shadowlab::readPFM(v1), b1 = shadowlab::readPFM(v1b), a2 = shadowlab::readPFM(v2),
          r2 = shadowlab::readPFM(v2r), u2 = shadowlab::readPFM(v2u);
    EXPECT_TRUE(identical(a2, r2)) << "restore gives back the step's own picture exactly";
    EXPECT_FALSE(identical(a2, u2)) << "the student's change showed";
    EXPECT_TRUE(identical(a1, b1)) << "going back to step 1 restores it exactly";
    EXPECT_FALSE(identical(a1, a2)) << "step 2 differs from step 1";
    size_t notYet = r.output.find("lesson: step 2: not yet");
    size_t passed = r.output.find("lesson: step 2: passed");
    EXPECT_NE(notYet, std::string::npos) << r.output;
    EXPECT_NE(passed, std::string::npos) << r.output;
    EXPECT_LT(notYet, passed);
}

// The classroom's check is the handout's: backprojection's step 3 in the window at 1024x768,
// Show me, the progressive reference complete, Check prints "passed" with the figure the headless
// `lesson --headless` computes at the size the window rendered. Both take the step's reference
// settings (128 samples, sm_size 512, biases 0.5 / 0, the tangent-plane test) and sum the same
// light samples in another order: float rounding of v, so the mean over the penumbra agrees to
// 1e-4 (measured equal to all 4 printed digits, 0.05156; before the window took the step's
// sm_size it gave 0.0468).
// `waitFirst`: the script waits for the reference, then checks; else it checks at once and the
// check waits for the reference (pending, the window never frozen), then prints the same figure.
void checkBackprojectionStep3(bool waitFirst) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const std::string tag = waitFirst ? "bp" : "bp-pending";
    const std::string scriptPath = tmp(tag + ".txt"), report = tmp(tag + "-report.json"), handout = tmp(tag + "-handout");
    std::ofstream(scriptPath) << "lesson next\nlesson next\nlesson show-me\nwait 2\n"
                              << (waitFirst ? "wait-reference 4000\n" : "") << "lesson check\nwait 1\n";
    fs::remove(report);
    shadowlab::test::Result r;
    {
        std::string command = "xvfb-run -a -s '-screen 0 1100x800x24' " + std::string(SHADOWLAB_BINARY) +
                              " window --lesson backprojection --size 1024x768 --script " + scriptPath + " --report " + report +
                              " 2>&1";
        FILE* pipe = popen(command.c_str(), "r");
        ASSERT_TRUE(pipe);
        char buffer[4096];
        size_t n;
        while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
        const int status = pclose(pipe);
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    ASSERT_EQ(r.code, 0) << r.output;
    const std::string key = "lesson: step 3: passed: mean(error in penumbra) < 0.05: ";
    const size_t at = r.output.find(key);
    ASSERT_NE(at, std::string::npos) << r.output;
    const double window = std::stod(r.output.substr(at + key.size()));
    std::ifstream in(report);
    ASSERT_TRUE(in);
    const nlohmann::json frames = nlohmann::json::parse(in)["frames"];
    ASSERT_FALSE(frames.empty());
    const auto& size = frames.back()["render_size"];
    const std::string wh = std::to_string(size[0].get<int>()) + "x" + std::to_string(size[1].get<int>());
    fs::remove_all(handout);
    auto h = shadowlab::test::run("lesson backprojection --headless --size " + wh + " --out " + handout);
    ASSERT_EQ(h.code, 0) << h.output;
    std::ifstream lessonJson(handout + "/lesson.json");
    ASSERT_TRUE(lessonJson);
    const nlohmann::json lesson = nlohmann::json::parse(lessonJson);
    double headless = -1.0;
    for (const auto& step : lesson["steps"])
        if (step.contains("task") && step["task"].contains("answer")) headless = step["task"]["answer"]["values"][0].get<double>();
    ASSERT_GE(headless, 0.0) << lesson.dump().substr(0, 400);
    std::printf("backprojection step 3 at %s: window %.5f, headless %.5f\n", wh.c_str(), window, headless);
    EXPECT_NEAR(window, headless, 1e-4 + 5e-5);  // the window prints 4 significant digits
    if (!waitFirst) {
        // The check waited: the reference accumulated over many frames in the frame budget (the
        // check issued two frames after Show me once completed its 128 samples in one frame, a
        // pause of seconds). The longest frame once it accumulated is the one where it completes
        // and the step's open views re-render with it (VTK, ~0.25 s on llvmpipe), not the check;
        // with the suite's other job busy on the second core it took 1.04 s once (CI, 2026-12-03),
        // so the bound is 2.5 s: what proves the wait is the samples spread over many frames.
        double worst = 0.0;
        int accumulating = 0, jump = 0;
        for (size_t i = 1; i < frames.size(); ++i) {
            const int grew = frames[i]["reference_samples"].get<int>() - frames[i - 1]["reference_samples"].get<int>();
            if (grew > 0) ++accumulating;
            jump = std::max(jump, grew);
            if (frames[i - 1]["reference_samples"].get<int>() > 0) worst = std::max(worst, frames[i]["frame_ms"].get<double>());
        }
        EXPECT_GT(accumulating, 8);
        EXPECT_LE(jump, 32);
        // A frozen window is seconds per frame; under AddressSanitizer (scripts/sanitize.sh, -O1 with
        // every access checked) the same frames run about 2-3 times slower (2.9 s measured there).
#if defined(__SANITIZE_ADDRESS__)
        constexpr double kLongestFrameMs = 2500.0 * 3.0;
#else
        constexpr double kLongestFrameMs = 2500.0;
#endif
        EXPECT_LT(worst, kLongestFrameMs);
        std::printf("the check waited over %d frames of samples (at most %d a frame, the longest frame %.0f ms)\n",
                    accumulating, jump, worst);
    }
}

TEST(WindowLesson, TaskCheckedInTheWindowEqualsTheHeadlessCheck) { checkBackprojectionStep3(true); }
TEST(WindowLesson, ACheckWaitsForTheReferenceWithoutFreezingTheWindow) { checkBackprojectionStep3(false); }

// A step's claims in the window: checked when the step is entered, once the progressive reference
// is complete, printed with their values and kept in the panel; a false one is shown, not fatal
// (the window goes on and exits 0); a variant renders aside, and the window's picture stays the step's.
TEST(WindowLesson, ExpectationsAreCheckedWhenAStepIsEnteredAndAFalseOneIsShownNotFatal) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const std::string lesson = tmp("claims.md"), script = tmp("claims.txt"), before = tmp("claims-a.pfm"),
                      after = tmp("claims-b.pfm");
    for (const std::string& f : {before, after}) fs::remove(f);
    std::ofstream(lesson) << "# Claims\n\n```shadowlab\nscene square-occluder\ntechnique pcf\n"
                             "reference reference samples=16 sm_size=256\n```\n\n"
                             "## One\n\n```shadowlab\nlight size 1\n"
                             "expect mean(visibility) > 0.5\n"                                       // line 13: holds
                             "expect mean(visibility in umbra) > 0.5\n"                              // line 14: false
                             "expect mean(error) < mean(error[pcf_kernel=1]) + 0.5\n```\n\n"         // line 15: a variant
                             "Text.\n\n## Two\n\n```shadowlab\nlight size 2\n```\n\nNo claims.\n";
    std::ofstream(script) << "panel off\nbackground off\nwait 1\nsave-visibility " << before << "\nwait 2\nsave-visibility " << after
                          << "\nlesson next\nwait 1\n";
    auto r = runXvfb("window --lesson " + lesson + " --size 320x240 --script " + script);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("lesson: step 1: " + lesson + ":13: expect mean(visibility) > 0.5: holds"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("lesson: step 1: " + lesson + ":14: expect mean(visibility in umbra) > 0.5: FAILS: "), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("lesson: step 1: " + lesson + ":15: expect mean(error) < mean(error[pcf_kernel=1]) + 0.5: holds"),
              std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("lesson: step 2: "), std::string::npos) << "step 2 has no claims: " << r.output;
    const Image a = shadowlab::readPFM(before), b = shadowlab::readPFM(after);
    EXPECT_TRUE(identical(a, b)) << "the window's visibility stays the step's own after the claims ran";
    EXPECT_GT(a.width, 0);
}

// Entering a step that changes a parameter and opens one more view renders the views already
// open again, at their new, narrower cells, after the frame's UI recorded their old textures:
// those must stay valid until that UI is drawn (VtkOffscreen::resize keeps the old one until the
// next frame's syncViewList; a deleted texture in ImGui's draw list is a GL error, exit code 1 under
// a script). adaptive-precision's step 5 (discontinuities on, pull-push added to skipped-pixels and
// error) did it at 1024x768, after its first four steps.
TEST(WindowLesson, ViewsResizedAfterTheUiWasBuiltStayDrawable) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const std::string script = tmp("resize.txt");
    std::ofstream out(script);
    out << "wait 3\n";
    for (int step = 2; step <= 5; ++step) out << "lesson next\nwait 2\n";
    out << "wait 4\n";
    out.close();
    shadowlab::test::Result r;
    const std::string command = "xvfb-run -a -s '-screen 0 1088x832x24' " + std::string(SHADOWLAB_BINARY) +
                                " window --lesson adaptive-precision --size 1024x768 --script " + script + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_TRUE(pipe);
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    const int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(r.output.find("GL error"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("lesson: step 5: "), std::string::npos) << "step 5 was reached: " << r.output;
}

// The lesson panel's step buttons stay inside the panel at 1024x768 in every frame, on a step whose
// task prompt wraps to five lines under two claims (backprojection's step 3): the narration above
// them gives way and scrolls. A fixed guess of eight rows for the task cut "Next >" off there.
TEST(WindowLesson, TheStepButtonsStayInsideThePanelUnderALongTask) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const std::string script = tmp("buttons.txt"), report = tmp("buttons.json");
    fs::remove(report);
    std::ofstream(script) << "wait 2\nlesson next\nwait 2\nlesson next\nwait 3\n";
    auto r = runXvfb("window --lesson backprojection --size 1024x768 --script " + script + " --report " + report);
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream in(report);
    ASSERT_TRUE(in) << r.output;
    const nlohmann::json frames = nlohmann::json::parse(in)["frames"];
    ASSERT_FALSE(frames.empty());
    ASSERT_NE(r.output.find("lesson: step 3: "), std::string::npos) << "step 3 (the task) was reached: " << r.output;
    int checked = 0;
    for (const nlohmann::json& f : frames) {
        if (!f.contains("lesson_panel")) continue;
        const nlohmann::json& panel = f["lesson_panel"]["panel"];
        const nlohmann::json& next = f["lesson_panel"]["next_button"];
        if (panel[3].get<float>() <= 0.0f) continue;  // not drawn yet
        ++checked;
        const float panelBottom = panel[1].get<float>() + panel[3].get<float>();
        const float nextBottom = next[1].get<float>() + next[3].get<float>();
        EXPECT_GT(next[3].get<float>(), 0.0f) << f.dump();
        EXPECT_GE(next[1].get<float>(), panel[1].get<float>()) << f.dump();
        EXPECT_LE(nextBottom, panelBottom) << "\"Next >\" ends below the panel: " << f.dump();
        EXPECT_LE(next[0].get<float>() + next[2].get<float>(), panel[0].get<float>() + panel[2].get<float>()) << f.dump();
    }
    EXPECT_GT(checked, 3);
}

TEST(WindowLesson, BadLessonIsRefusedWithFileAndLineBeforeTheWindowOpens) {
    std::string bad = tmp("bad.md");
    std::ofstream(bad) << "# Bad\n\n```shadowlab\nscene square-occluder\ntechnique pcf\nset pcf_kernl 5\n```\n\n## One\n\nText.\n";
    // No X server needed: the lesson is read before the window opens.
    auto r = shadowlab::test::run("window --lesson " + bad);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("bad.md:6"), std::string::npos) << r.output;
}

}  // namespace
