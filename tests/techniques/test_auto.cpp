// `auto` (issue 25): the features against the closed form of square-occluder, the choice on
// synthetic calibrations (the facts first, then the cheapest setting within the budgets), the
// calibration file's validation, generated scenes, and renders whose stats show what ran.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "auto/auto.h"
#include "auto/trial.h"
#include "error.h"
#include "graph/renderer.h"
#include "image/metrics.h"
#include "scene/scene.h"
#include "support/gl_fixture.h"

namespace fs = std::filesystem;

namespace shadowlab {
namespace {

LightFeatures softFeatures(double pixels, double texels = 40.0, double triangles = 100.0) {
    LightFeatures f;
    f.lightExtent = 1.0;
    f.penumbraPixels = pixels;
    f.penumbraTexels = texels;
    f.casterTriangles = triangles;
    return f;
}

// Three settings: hard (cheap, wrong in a penumbra), pcss (middling), ssv (accurate, costly), on
// two cases; the second with wider penumbrae, where every error is larger.
Calibration syntheticCalibration() {
    Calibration cal;
    cal.probeMs = 10.0;
    cal.settings = {{"hard", {}}, {"pcss", {}}, {"ssv", {}}};
    CalibrationCase narrow;
    narrow.scene = "narrow";
    narrow.lightSize = 0.5;
    narrow.width = narrow.height = 100;
    narrow.features = softFeatures(10.0);
    narrow.results = {{0.05, 0.2, 1.0, 1.0}, {0.015, 0.05, 0.5, 5.0}, {0.004, 0.01, 0.0, 20.0}};
    CalibrationCase wide = narrow;
    wide.scene = "wide";
    wide.features = softFeatures(40.0);
    wide.results = {{0.09, 0.3, 1.0, 1.0}, {0.03, 0.08, 0.5, 5.0}, {0.006, 0.015, 0.0, 20.0}};
    cal.cases = {narrow, wide};
    return cal;
}

TEST(AutoChoice, APointLightTakesHardWithoutACalibration) {
    LightFeatures f;
    f.point = true;
    const TechniqueChoice c = chooseTechnique(Calibration{}, f, AutoBudget{}, 512 * 512, 1.0);
    ASSERT_NE(c.desc, nullptr);
    EXPECT_EQ(c.desc->id, "hard");
    EXPECT_EQ(c.report["rule"], "point light");
}

TEST(AutoChoice, APenumbraUnderAPixelTakesHard) {
    const TechniqueChoice c = chooseTechnique(syntheticCalibration(), softFeatures(0.6), AutoBudget{}, 512 * 512, 1.0);
    ASSERT_NE(c.desc, nullptr);
    EXPECT_EQ(c.desc->id, "hard");
    EXPECT_EQ(c.report["rule"], "penumbra under a pixel");
    // One pixel and more: the calibration decides.
    EXPECT_NE(chooseTechnique(syntheticCalibration(), softFeatures(1.5), AutoBudget{}, 512 * 512, 1.0).report["rule"],
              "penumbra under a pixel");
}

TEST(AutoChoice, AShadowOnNoVisiblePixelRunsNothing) {
    LightFeatures f = softFeatures(20.0);
    f.shadowOnScreen = false;
    const TechniqueChoice c = chooseTechnique(syntheticCalibration(), f, AutoBudget{}, 512 * 512, 1.0);
    EXPECT_EQ(c.desc, nullptr);
    EXPECT_EQ(c.report["rule"], "no visible shadow");
}

TEST(AutoChoice, TheCheapestSettingWithinTheBudgetAndWhyTheOthersWereRejected) {
    const Calibration cal = syntheticCalibration();
    const int pixels = 100 * 100;  // the calibration's size: times as measured
    AutoBudget b;
    // Between the two cases: the prediction takes the larger error of the two nearest (conservative).
    b.error = 0.05;
    TechniqueChoice c = chooseTechnique(cal, softFeatures(20.0), b, pixels, 1.0);
    EXPECT_EQ(c.desc->id, "pcss");  // hard's 0.09 > 0.05; pcss 0.03 in 5.5 ms; ssv 0.006 in 20 ms
    EXPECT_EQ(c.report["rule"], "calibration");
    EXPECT_NEAR(c.report["predicted"]["error"].get<double>(), 0.03, 1e-12);
    EXPECT_NEAR(c.report["predicted"]["ms"].get<double>(), 5.5, 1e-9);
    bool hardRejected = false;
    for (const auto& a : c.report["alternatives"])
        if (a["setting"] == "hard defaults") {
            hardRejected = a["rejected"].get<std::string>().find("predicted RMSE 0.0900 > budget 0.0500") != std::string::npos;
        }
    EXPECT_TRUE(hardRejected) << c.report.dump(1);
    // A tighter budget: the accurate setting.
    b.error = 0.01;
    EXPECT_EQ(chooseTechnique(cal, softFeatures(20.0), b, pixels, 1.0).desc->id, "ssv");
    // A loose one: the cheapest of all.
    b.error = 0.2;
    EXPECT_EQ(chooseTechnique(cal, softFeatures(20.0), b, pixels, 1.0).desc->id, "hard");
    // Over the penumbra, errors are larger: the same budget needs more.
    b.error = 0.05;
    b.penumbra = true;
    EXPECT_EQ(chooseTechnique(cal, softFeatures(20.0), b, pixels, 1.0).desc->id, "ssv");
}

TEST(AutoChoice, TimesScaleWithThePixelsAndTheMachine) {
    const Calibration cal = syntheticCalibration();
    AutoBudget b;
    b.error = 0.05;
    // 4x the pixels: pcss's per-pixel 5 ms becomes 20, its fixed 0.5 stays.
    TechniqueChoice c = chooseTechnique(cal, softFeatures(20.0), b, 4 * 100 * 100, 1.0);
    EXPECT_NEAR(c.report["predicted"]["ms"].get<double>(), 20.5, 1e-9);
    // A machine twice as slow.
    c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 2.0);
    EXPECT_NEAR(c.report["predicted"]["ms"].get<double>(), 11.0, 1e-9);
}

TEST(AutoChoice, NothingWithinBothBudgetsTakesTheMostAccurateWithinTheTime) {
    const Calibration cal = syntheticCalibration();
    AutoBudget b;
    b.error = 0.001;  // nothing is that accurate
    TechniqueChoice c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0);
    EXPECT_EQ(c.desc->id, "ssv");
    EXPECT_EQ(c.report["rule"], "nothing meets the budget");
    b.timeMs = 10.0;  // ssv's 20 ms is over the time budget: pcss is the most accurate within it
    c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0);
    EXPECT_EQ(c.desc->id, "pcss");
    // Within the error budget but over the time budget: rejected for its time.
    b.error = 0.01;
    c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0);
    EXPECT_EQ(c.desc->id, "pcss");
    bool ssvRejectedForTime = false;
    for (const auto& a : c.report["alternatives"])
        if (a["setting"] == "ssv defaults") ssvRejectedForTime = a["rejected"].get<std::string>().find("time budget") != std::string::npos;
    EXPECT_TRUE(ssvRejectedForTime) << c.report.dump(1);
}

// Measured errors decide (issue 25's "measured, not trusted"): every setting within the time budget
// is measured, by predicted time; only those within the budget are timed; the prediction's errors
// play no part.
TEST(AutoChoice, MeasuredErrorsDecideAndOnlyTheSettingsWithinTheBudgetAreTimed) {
    const Calibration cal = syntheticCalibration();
    AutoBudget b;
    b.error = 0.05;
    // What the trials measure, unlike the prediction: hard 0.08, pcss 0.07 (predicted 0.03), ssv 0.01.
    const std::vector<double> truth = {0.08, 0.07, 0.01};
    std::vector<size_t> asked, timed;
    SettingTrials measure;
    measure.error = [&](size_t s) -> std::optional<MeasuredError> {
        asked.push_back(s);
        return MeasuredError{truth[s], 2.0 * truth[s]};
    };
    measure.time = [&](const std::vector<size_t>& settings) {
        timed.insert(timed.end(), settings.begin(), settings.end());
        return std::vector<double>(settings.size(), 1.0);
    };
    TechniqueChoice c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0, &measure);
    EXPECT_EQ(c.desc->id, "ssv");  // the prediction alone takes pcss (its 0.03 <= 0.05): over the budget
    EXPECT_EQ(c.report["rule"], "measured");
    EXPECT_EQ(asked, (std::vector<size_t>{0, 1, 2}));  // by predicted time: hard 2, pcss 5.5, ssv 20 ms
    EXPECT_EQ(timed, (std::vector<size_t>{2}));          // only what meets the budget is timed
    EXPECT_NEAR(c.report["measured_error"].get<double>(), 0.01, 1e-12);
    bool pcssRejected = false;
    for (const auto& a : c.report["alternatives"])
        if (a["setting"] == "pcss defaults")
            pcssRejected = a["rejected"].get<std::string>().find("measured RMSE 0.0700 > budget 0.0500") != std::string::npos;
    EXPECT_TRUE(pcssRejected) << c.report.dump(1);
    // A loose budget: all three meet it and are timed; equal times keep the first by predicted time.
    asked.clear();
    timed.clear();
    b.error = 0.1;
    c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0, &measure);
    EXPECT_EQ(c.desc->id, "hard");
    EXPECT_EQ(timed, (std::vector<size_t>{0, 1, 2}));
    for (const auto& a : c.report["alternatives"])
        if (a["setting"] != "hard defaults")
            EXPECT_NE(a["rejected"].get<std::string>().find("slower than the chosen one"), std::string::npos) << a.dump();
    // Over the penumbra: the penumbra's measured error (2x here) meets 0.05 with ssv only.
    b.error = 0.05;
    b.penumbra = true;
    EXPECT_EQ(chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0, &measure).desc->id, "ssv");
    // Nothing within: the most accurate measured, said so; a time budget skips what it cannot afford.
    b.penumbra = false;
    b.error = 0.001;
    c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0, &measure);
    EXPECT_EQ(c.desc->id, "ssv");
    EXPECT_EQ(c.report["rule"], "nothing meets the budget");
    asked.clear();
    b.timeMs = 10.0;
    c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0, &measure);
    EXPECT_EQ(c.desc->id, "pcss");
    EXPECT_EQ(asked, (std::vector<size_t>{0, 1}));  // ssv's predicted 20 ms is never rendered
}

// The calibration's times order; measured times decide: a setting predicted far slower (ssv, 20 ms)
// but measured faster (8 ms) than one predicted cheap (pcss, 5.5 predicted, 30 measured) is taken.
TEST(AutoChoice, MeasuredTimesPickTheFastestOfTheSettingsWithinTheBudget) {
    const Calibration cal = syntheticCalibration();
    AutoBudget b;
    b.error = 0.05;
    const std::vector<double> error = {0.08, 0.03, 0.01}, ms = {2.0, 30.0, 8.0};  // pcss really slow here
    int timings = 0;
    SettingTrials measure;
    measure.error = [&](size_t s) -> std::optional<MeasuredError> { return MeasuredError{error[s], error[s]}; };
    measure.time = [&](const std::vector<size_t>& settings) {  // all within the budget, in one call
        ++timings;
        std::vector<double> out;
        for (size_t s : settings) out.push_back(ms[s]);
        return out;
    };
    TechniqueChoice c = chooseTechnique(cal, softFeatures(20.0), b, 100 * 100, 1.0, &measure);
    EXPECT_EQ(c.desc->id, "ssv") << c.report.dump(1);
    EXPECT_EQ(timings, 1);  // side by side: pcss and ssv timed together, never one alone
    EXPECT_NEAR(c.report["measured_ms"].get<double>(), 8.0, 1e-12);
    for (const auto& a : c.report["alternatives"])
        if (a["setting"] == "pcss defaults")
            EXPECT_NE(a["rejected"].get<std::string>().find("in 30.00 ms, slower than the chosen one"), std::string::npos) << a.dump();
}

TEST(AutoChoice, FeaturesOutsideTheCalibrationTakeTheMostAccurateAndSaySo) {
    const Calibration cal = syntheticCalibration();
    AutoBudget b;
    b.error = 0.2;  // hard would do inside the range
    const TechniqueChoice c = chooseTechnique(cal, softFeatures(400.0), b, 100 * 100, 1.0);
    EXPECT_EQ(c.report["rule"], "outside the calibration");
    EXPECT_EQ(c.desc->id, "ssv");
}

// ---- features --------------------------------------------------------------------------------------
// square-occluder (DESIGN.md section 5): w_l = 1, occluder at depth 2 below the light, floor at 4.
// The true largest penumbra is w_l (z_r - z_o) / z_o = 1 world unit along an axis; the estimate takes
// the light's diagonal (sqrt 2), so it is at least 1 and at most 1.5.
TEST(AutoFeatures, SquareOccluderPenumbraIsBoundedFromAbove) {
    const Scene scene = loadScene("square-occluder");
    const LightFeatures f = measureLightFeatures(scene, scene.lights[0], scene.camera, 512, 512);
    EXPECT_FALSE(f.point);
    EXPECT_NEAR(f.casterNear, 2.0 - 0.0005, 1e-3);
    EXPECT_NEAR(f.receiverFar, 4.0, 1e-3);
    EXPECT_GE(f.penumbraWorld, 1.0);
    EXPECT_LE(f.penumbraWorld, 1.5);
    EXPECT_TRUE(f.shadowOnScreen);
    // Pixels: linear in the frame's height; texels: independent of it.
    const LightFeatures half = measureLightFeatures(scene, scene.lights[0], scene.camera, 256, 256);
    EXPECT_NEAR(half.penumbraPixels * 2.0, f.penumbraPixels, 1e-6 * f.penumbraPixels);
    EXPECT_DOUBLE_EQ(half.penumbraTexels, f.penumbraTexels);
    // The penumbra as drawn: at least what the camera's nearest floor point under the shadow shows.
    EXPECT_GT(f.penumbraPixels, 30.0);
    // A smaller light: a proportionally smaller penumbra.
    Light small = scene.lights[0];
    small.size = 0.01f;
    EXPECT_NEAR(measureLightFeatures(scene, small, scene.camera, 512, 512).penumbraWorld, 0.01 * f.penumbraWorld, 1e-6);
}

TEST(AutoFeatures, AShadowBehindTheCameraIsNotOnScreen) {
    const Scene scene = loadScene("square-occluder");
    Camera away = scene.camera;
    away.target = away.position + (away.position - scene.camera.target);  // looking away from the floor
    EXPECT_FALSE(measureLightFeatures(scene, scene.lights[0], away, 512, 512).shadowOnScreen);
    // A light that casts no shadow has none anywhere.
    Light off = scene.lights[0];
    off.castsShadows = false;
    EXPECT_FALSE(measureLightFeatures(scene, off, scene.camera, 512, 512).shadowOnScreen);
}

// ---- the calibration file ----------------------------------------------------------------------------
std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = (fs::temp_directory_path() / name).string();
    std::ofstream(path) << text;
    return path;
}

TEST(AutoCalibration, RoundTripsThroughItsFile) {
    Calibration cal = syntheticCalibration();
    cal.program = "shadowlab test";
    cal.settings[1].sets = {{"sm_size", "512"}};
    const std::string path = writeFile("shadowlab-auto-roundtrip.json", cal.toJson().dump(1));
    const Calibration back = loadCalibration(path);
    ASSERT_EQ(back.settings.size(), 3u);
    EXPECT_EQ(back.settings[1].describe(), "pcss sm_size=512");
    ASSERT_EQ(back.cases.size(), 2u);
    EXPECT_DOUBLE_EQ(back.cases[1].results[2].rmse, 0.006);
    EXPECT_DOUBLE_EQ(back.cases[1].features.penumbraPixels, 40.0);
    EXPECT_DOUBLE_EQ(back.probeMs, 10.0);
}

TEST(AutoCalibration, BadFilesNameTheFileLineAndField) {
    const nlohmann::json good = syntheticCalibration().toJson();
    auto expectError = [&](nlohmann::json j, const std::string& needle) {
        const std::string path = writeFile("shadowlab-auto-bad.json", j.dump(1));
        try {
            loadCalibration(path);
            ADD_FAILURE() << "accepted: " << needle;
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(path), std::string::npos) << what;
            EXPECT_NE(what.find(needle), std::string::npos) << what;
        }
    };
    nlohmann::json j = good;
    j["version"] = 7;
    expectError(j, "version");
    j = good;
    j["settings"][1]["technique"] = "magic";
    expectError(j, "settings[1].technique");
    j = good;
    j["settings"][1]["technique"] = "auto";  // auto cannot choose itself
    expectError(j, "settings[1].technique");
    j = good;
    j["settings"][0]["set"] = {{"sm_size", "0"}};
    expectError(j, "sm_size");
    j = good;
    j["cases"][0]["results"].erase(0);
    expectError(j, "cases[0].results");
    j = good;
    j["cases"][1]["results"][0]["rmse"] = -1;
    expectError(j, "cases[1].results[0].rmse");
    j = good;
    j["machine"].erase("probe_ms");
    expectError(j, "probe_ms");
}

// The shipped calibration predicts what it did not see: each scene's cases left out in turn and
// predicted from the others' (as a new scene would be). Two measures, with the values measured on
// the shipped file in the note of issue 25:
//  - per (case, setting), the prediction (the largest error of the three nearest cases, scaled by
//    the penumbra fraction) is not below the measured error by more than 0.01 on at least 85% of
//    them (measured: 1332 of 1470, 91%);
//  - at the default budget 0.02, of the cases where some setting meets the budget, auto's choice
//    meets it on at least 85% (measured: 118 of 131, 90%). Cases no setting can meet are counted apart: there
//    auto takes the most accurate setting it predicts, and says so.
TEST(AutoCalibration, ASubsetPredictsTheRest) {
    const Calibration cal = loadCalibration(projectRoot() + "/assets/calibration/default.json");
    ASSERT_GE(cal.cases.size(), 20u);
    size_t pairs = 0, under = 0, feasible = 0, overBudget = 0, infeasible = 0;
    const AutoBudget b;
    for (const CalibrationCase& held : cal.cases) {
        if (held.features.point) continue;
        Calibration rest = cal;
        rest.cases.clear();
        for (const CalibrationCase& c : cal.cases)
            if (c.scene != held.scene) rest.cases.push_back(c);
        bool meetable = false;
        for (size_t s = 0; s < cal.settings.size(); ++s) {
            const Prediction p = predictSetting(rest, s, held.features, false, held.width * held.height, 1.0);
            ++pairs;
            if (p.error + 0.01 < held.results[s].rmse) ++under;
            meetable |= held.results[s].rmse <= b.error;
        }
        if (!meetable) {
            ++infeasible;
            continue;
        }
        const TechniqueChoice c = chooseTechnique(rest, held.features, b, held.width * held.height, 1.0);
        ASSERT_NE(c.desc, nullptr) << held.scene;
        const std::string chosen = c.report["technique"].get<std::string>() + " " + c.report["setting"].get<std::string>();
        for (size_t s = 0; s < cal.settings.size(); ++s)
            if (cal.settings[s].describe() == chosen) {
                ++feasible;
                overBudget += held.results[s].rmse > b.error;
            }
    }
    ASSERT_GT(pairs, 0u);
    ASSERT_GT(feasible, 0u);
    EXPECT_LE(double(under), 0.15 * double(pairs)) << under << " of " << pairs << " predictions under the measured error by > 0.01";
    EXPECT_LE(double(overBudget), 0.15 * double(feasible)) << overBudget << " of " << feasible << " choices over the 0.02 budget";
    std::printf("[ calibration ] left-one-scene-out: %zu of %zu predictions under by > 0.01; %zu of %zu choices over the "
                "0.02 budget where a setting meets it; %zu cases where none does\n",
                under, pairs, overBudget, feasible, infeasible);
}

// ---- generated scenes -------------------------------------------------------------------------------
TEST(RandomScene, TheSameSeedGivesTheSameScene) {
    const Scene a = loadScene("random:42"), b = loadScene("random:42"), c = loadScene("random:43");
    ASSERT_EQ(a.objects.size(), b.objects.size());
    EXPECT_EQ(a.lights[0].position, b.lights[0].position);
    EXPECT_EQ(a.camera.position, b.camera.position);
    EXPECT_EQ(a.objects.back().mesh.positions, b.objects.back().mesh.positions);
    EXPECT_NE(a.camera.position, c.camera.position);
    EXPECT_GE(a.objects.size(), 2u);
    EXPECT_NEAR(glm::length(a.lights[0].direction), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(a.lights[0].direction, a.lights[0].up), 0.0f, 1e-5f);
    for (const char* bad : {"random:", "random:x", "random:-1", "random:12345678901234567890"})
        EXPECT_THROW(loadScene(bad), InputError) << bad;
}

// ---- renders ------------------------------------------------------------------------------------------
class AutoRender : public testing::GLTest {};

std::vector<std::string> passesThatRan(const nlohmann::json& stats) {
    std::vector<std::string> out;
    for (const auto& p : stats["passes"])
        if (p["runs"].get<int>() > 0) out.push_back(p["name"].get<std::string>());
    return out;
}

TEST_F(AutoRender, APointLightAndASubPixelPenumbraRunHardsPassesOnly) {
    const Scene scene = loadScene("square-occluder");
    const std::vector<std::string> hardOnly = {"gbuffer", "L0/hard/shadow_map", "L0/hard/visibility", "shade"};
    for (float size : {0.0f, 0.001f}) {
        RenderOptions o;
        o.width = o.height = 128;
        o.technique = "auto";
        o.lightSize = size;
        Renderer r(scene, o);
        r.renderFrame(0, {"visibility"});
        const nlohmann::json stats = r.stats({}, 0);
        EXPECT_EQ(passesThatRan(stats), hardOnly) << "light size " << size;
        const nlohmann::json& light = stats["lights"][0];
        EXPECT_EQ(light["technique_requested"], "auto");
        EXPECT_EQ(light["technique"], "hard");
        EXPECT_EQ(light["auto"]["rule"], size == 0.0f ? "point light" : "penumbra under a pixel") << light["auto"].dump(1);
    }
}

TEST_F(AutoRender, NoVisibleShadowRunsNoShadowPassAndLeavesTheLightUnshadowed) {
    Scene scene = loadScene("square-occluder");
    scene.camera.target = scene.camera.position + (scene.camera.position - scene.camera.target);
    RenderOptions o;
    o.width = o.height = 64;
    o.technique = "auto";
    Renderer r(scene, o);
    r.renderFrame(0, {"visibility"});
    const nlohmann::json stats = r.stats({}, 0);
    EXPECT_EQ(passesThatRan(stats), (std::vector<std::string>{"gbuffer", "shade"}));
    EXPECT_EQ(stats["lights"][0]["auto"]["rule"], "no visible shadow");
}

TEST_F(AutoRender, TheBudgetChangesTheChoiceLiveAndSaysWhy) {
    const Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 128;
    o.technique = "auto";
    o.sets = {{"error_budget", "0.5"}, {"measure", "0"}};  // the prediction alone: AutoMeasured tests the trials
    Renderer r(scene, o);
    r.renderFrame(0, {"visibility"});
    const std::string loose = r.lights()[0]->desc->id;
    EXPECT_EQ(r.lights()[0]->choice["rule"], "calibration");
    EXPECT_FALSE(r.lights()[0]->choice["why"].get<std::string>().empty());
    // Within 0.5 every setting fits: the cheapest is a hard-shadow one.
    EXPECT_TRUE(loose == "hard" || loose == "spsm" || loose == "pcf") << loose;
    r.setParam("error_budget", "0.002");
    r.renderFrame(1, {"visibility"});
    const std::string tight = r.lights()[0]->desc->id;
    EXPECT_NE(tight, loose);
    const nlohmann::json stats = r.stats({}, 0);
    bool ranTight = false;
    for (const std::string& p : passesThatRan(stats)) ranTight |= p.rfind("L0/" + tight + "/", 0) == 0;
    EXPECT_TRUE(ranTight);
}

// The window asks for a light's internals (the views, a lesson's conditions); when the budget then
// moves auto to another technique, the stats and cost measurements replay that request: the old
// technique's internals are gone and must not be asked for (it threw "nothing produces requested
// output" in the window, what-accuracy-costs step 3 to 4).
TEST_F(AutoRender, ANewPickDropsTheOldPicksRequestedInternals) {
    const Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 96;
    o.technique = "auto";
    o.sets = {{"error_budget", "0.002"}, {"measure", "0"}};  // (measured, ssv meets both budgets here)
    Renderer r(scene, o);
    const std::string tight = r.lights()[0]->desc->id;
    std::set<std::string> requested = {"image", "visibility"};
    for (const std::string& name : r.internalRequests(false)) requested.insert(name);
    r.renderFrame(0, requested);
    r.setParam("error_budget", "0.5");
    ASSERT_NE(r.lights()[0]->desc->id, tight);
    nlohmann::json stats;
    EXPECT_NO_THROW(stats = r.stats({}, 0));
    EXPECT_NO_THROW(r.measureCost(1, 1));
    r.renderFrame(2, {"image", "visibility"});
}

// The measured choice on a scene where the calibration's neighbours mispredict (random:2002, a thin
// plate: ssm-contour measured 2-3x the error of the cases nearest in features): the pick's RMSE
// against the ray-traced reference (256 rays, as the bench's) is within the budget, and it is the
// error the report says it measured (the frame is at most the trial size: the trial is the frame).
TEST_F(AutoRender, TheMeasuredChoiceMeetsItsBudgetAndReportsTheErrorItMeasured) {
    const Scene scene = loadScene("random:2002");
    RenderOptions ro;
    ro.width = ro.height = 128;
    ro.technique = "raytraced";
    ro.sets = {{"rays", "256"}};
    Renderer exact(scene, ro);
    exact.renderFrame(0, {"visibility"});
    const Image reference = exact.visibility();
    for (const char* budget : {"0.01", "0.02", "0.05"}) {
        RenderOptions o;
        o.width = o.height = 128;
        o.technique = "auto";
        o.sets = {{"error_budget", budget}};
        Renderer r(scene, o);
        r.renderFrame(0, {"visibility"});
        const nlohmann::json& choice = r.lights()[0]->choice;
        ASSERT_TRUE(choice.contains("measured_error")) << choice.dump(1);
        const double rmse = computeMetrics(r.visibility(), reference).rmse;
        EXPECT_NEAR(choice["measured_error"].get<double>(), rmse, 1e-6) << budget;
        if (choice["rule"] == "measured") EXPECT_LE(rmse, std::stod(budget)) << choice.dump(1);
        EXPECT_EQ(choice["trial"]["size"], nlohmann::json::array({128, 128}));
        // Every setting was measured: over the budget, or within it and slower.
        for (const auto& a : choice["alternatives"]) {
            if (a["rejected"] == "chosen") continue;
            ASSERT_TRUE(a.contains("measured_error")) << a.dump();
            if (a["measured_error"].get<double>() <= std::stod(budget))
                EXPECT_GE(a["measured_ms"].get<double>(), choice["measured_ms"].get<double>()) << a.dump();
        }
    }
}

// The window's drag: choices are predicted only while it lasts, measured again at rest; and a
// trial leaves the caller's framebuffer, viewport and program as they were.
TEST_F(AutoRender, ADragPredictsAndRestMeasuresAndATrialRestoresTheCallersGlState) {
    const Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 64;
    o.technique = "auto";
    Renderer r(scene, o);
    EXPECT_EQ(r.lights()[0]->choice["rule"], "measured");
    GLuint fbo = 0;
    glCreateFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(3, 4, 50, 60);
    r.setMeasureChoices(false);
    Camera moved = scene.camera;
    moved.position += glm::vec3(0.3f, 0.0f, 0.0f);
    r.setCamera(moved);
    EXPECT_EQ(r.lights()[0]->choice["rule"], "calibration");
    r.setMeasureChoices(true);  // at rest: measured again (a new view: the trial renders)
    EXPECT_EQ(r.lights()[0]->choice["rule"], "measured");
    EXPECT_TRUE(r.lights()[0]->choice["trial"]["reference_made"].get<bool>());
    GLint bound = 0, viewport[4] = {};
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    glGetIntegerv(GL_VIEWPORT, viewport);
    EXPECT_EQ(GLuint(bound), fbo);
    EXPECT_EQ(std::vector<GLint>(viewport, viewport + 4), (std::vector<GLint>{3, 4, 50, 60}));
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    // The same view again: every error comes from the cache, nothing renders.
    r.setCamera(scene.camera);
    EXPECT_EQ(r.lights()[0]->choice["trial"]["settings_measured"], 0);
    EXPECT_EQ(r.lights()[0]->choice["trial"]["settings_timed"], 0);  // the same list's times, cached
    EXPECT_FALSE(r.lights()[0]->choice["trial"]["reference_made"].get<bool>());
}

// The settings within a budget are timed side by side (trial.h): one time per setting, in the
// order asked, each a frame's shadow passes; the same list again renders nothing and gives the same
// times; another list is timed afresh, together, so no time is compared with one measured at
// another moment (what failed the lesson what-accuracy-costs on a loaded CI run).
TEST_F(AutoRender, SettingsAreTimedSideBySideAndTheirTimesCachedPerList) {
    const Scene scene = loadScene("square-occluder");
    TrialInputs in;
    in.scene = &scene;
    in.lights = scene.lights;
    in.camera = scene.camera;
    in.width = in.height = 48;
    const std::vector<CalibrationSetting> both = {{"hard", {}}, {"pcss", {{"filter_kernel", "9"}}}};
    TrialLog log;
    const std::vector<double> ms = timeSettingsSideBySide(in, both, log);
    ASSERT_EQ(ms.size(), 2u);
    for (double t : ms) EXPECT_TRUE(std::isfinite(t) && t > 0.0) << t;
    EXPECT_EQ(log.timed, 2);
    EXPECT_TRUE(log.referenceMade);  // the view's trial is made when missing
    TrialLog again;
    EXPECT_EQ(timeSettingsSideBySide(in, both, again), ms);
    EXPECT_EQ(again.timed, 0);
    EXPECT_EQ(again.reused, 2);
    EXPECT_FALSE(again.referenceMade);
    TrialLog other;
    const std::vector<double> alone = timeSettingsSideBySide(in, {both[1]}, other);
    ASSERT_EQ(alone.size(), 1u);
    EXPECT_EQ(other.timed, 1);
    EXPECT_TRUE(std::isfinite(alone[0]) && alone[0] > 0.0);
    releaseTrialRenderers();
}

}  // namespace
}  // namespace shadowlab
