// Core stage two: parameter tables with enum/odd/power-of-two/step constraints and conditions, the
// pass graph's versions per write, live setters that re-run exactly what they change, resources
// owned by the pool, checked pass contexts (--check-reuse), typed internals and cost statistics.
// Small sizes throughout (32x32..96x96, reference samples 1..16, raytraced rays 4), so the suite
// runs in seconds.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>
#include <type_traits>

#include "error.h"
#include "graph/frame.h"
#include "graph/pass_graph.h"
#include "graph/renderer.h"
#include "graph/resources.h"
#include "graph/technique.h"
#include "image/image.h"
#include "scene/scene.h"
#include "support/cli_run.h"
#include "support/gl_fixture.h"
#include "support/real_meshes.h"

namespace fs = std::filesystem;

namespace shadowlab {
namespace {

using testing::GLTest;

// ---- helpers --------------------------------------------------------------------------------------
using CliResult = test::Result;
CliResult runCli(const std::string& arguments) { return test::run(arguments); }

// Runs the commands two at a time (the machine has two cores); results in order.
std::vector<CliResult> runCliParallel(const std::vector<std::string>& commands) {
    std::vector<CliResult> results(commands.size());
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t i; (i = next++) < commands.size();) results[i] = runCli(commands[i]);
    };
    std::thread a(worker), b(worker);
    a.join();
    b.join();
    return results;
}

// A folder of this test's own (ctest runs tests in parallel).
std::string tmpDir() {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / "stage2" / (std::string(test->test_suite_name()) + "." + test->name());
    fs::create_directories(dir);
    return dir.string();
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const std::set<std::string> kImageAndVisibility = {"image", "visibility"};

std::set<std::string> ranInLastFrame(const nlohmann::json& stats) {
    std::set<std::string> out;
    for (const auto& p : stats["passes"])
        if (p["status"] == "ran") out.insert(p["name"].get<std::string>());
    return out;
}

const nlohmann::json& passStats(const nlohmann::json& stats, const std::string& name) {
    for (const auto& p : stats["passes"])
        if (p["name"] == name) return p;
    static const nlohmann::json none;
    ADD_FAILURE() << "no pass " << name << " in " << stats["passes"].dump();
    return none;
}

std::string describeSet(const std::set<std::string>& s) {
    std::string out = "{";
    for (const std::string& x : s) out += (out.size() > 1 ? ", " : "") + x;
    return out + "}";
}

// Bit-identical float data (memcmp), with the first difference for the message.
void expectBitIdentical(const Image& a, const Image& b, const std::string& what) {
    ASSERT_EQ(a.width, b.width) << what;
    ASSERT_EQ(a.height, b.height) << what;
    ASSERT_EQ(a.channels, b.channels) << what;
    if (std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0) return;
    size_t differ = 0, first = 0;
    float maxDiff = 0.0f;
    for (size_t i = 0; i < a.data.size(); ++i) {
        if (std::memcmp(&a.data[i], &b.data[i], sizeof(float)) == 0) continue;
        if (differ++ == 0) first = i;
        maxDiff = std::max(maxDiff, std::abs(a.data[i] - b.data[i]));
    }
    ADD_FAILURE() << what << ": " << differ << " of " << a.data.size() << " floats differ; first at " << first << " ("
                  << a.data[first] << " vs " << b.data[first] << "), max |diff| " << maxDiff;
}

void expectSameResult(const Renderer& live, const Renderer& fresh, const std::string& what) {
    expectBitIdentical(live.visibility(), fresh.visibility(), what + ": visibility()");
    expectBitIdentical(live.image(), fresh.image(), what + ": image()");
}

// Every value of the frame's visibility and of each light's own visibility in [0,1], none NaN.
void expectVisibilityInUnitRange(const Renderer& r, const std::string& what) {
    Image v = r.visibility();
    ASSERT_GT(v.data.size(), 0u) << what;
    for (size_t i = 0; i < v.data.size(); ++i)
        ASSERT_TRUE(v.data[i] >= 0.0f && v.data[i] <= 1.0f) << what << ": frame visibility[" << i << "] = " << v.data[i];
    for (const LightState* l : r.lights()) {
        const Resource* res = r.pool().find(l->group + "/visibility");
        if (!res) continue;
        Image lv = readTexture(res->texture, 1);
        for (size_t i = 0; i < lv.data.size(); ++i)
            ASSERT_TRUE(lv.data[i] >= 0.0f && lv.data[i] <= 1.0f)
                << what << ": " << l->group << " visibility[" << i << "] = " << lv.data[i];
    }
}

std::string numberText(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

// ==== 1. parameter extremes: pcf_kernel even refused; every value renders visibility in [0,1] =========
TEST(Stage2Params, EvenPcfKernelRefusedByCli) {
    std::string dir = tmpDir();
    for (const char* k : {"4", "2"}) {
        std::string out = dir + "/k" + k + ".png";
        fs::remove(out);
        CliResult r = runCli("render --scene square-occluder --size 32x32 --technique pcf --set pcf_kernel=" +
                             std::string(k) + " --out " + out);
        EXPECT_EQ(r.code, 2) << "pcf_kernel=" << k << ": " << r.output;
        EXPECT_NE(r.output.find("pcf_kernel"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("odd"), std::string::npos) << "message does not say odd: " << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(out)) << out;
    }
    // Odd values pass.
    CliResult ok = runCli("render --scene square-occluder --size 32x32 --technique pcf --set pcf_kernel=3 --out " +
                          dir + "/k3.png");
    EXPECT_EQ(ok.code, 0) << ok.output;
}

// The values worth trying for one parameter: min, max, default, and for an Int a middle value
// that passes the step and constraint; every enum choice; both bools. Capped where a value would
// take minutes on llvmpipe (see the comments at the caps).
std::vector<std::string> valuesToTry(const TechniqueDesc& desc, const ParamDesc& p) {
    std::vector<std::string> out;
    switch (p.type) {
        case ParamDesc::Type::Enum:
            return p.choices;
        case ParamDesc::Type::Bool:
            return {"0", "1"};
        case ParamDesc::Type::Float:
            return {numberText(p.minValue), numberText(p.maxValue), numberText(p.defaultValue),
                    numberText(0.5 * (p.minValue + p.maxValue))};
        case ParamDesc::Type::Int: {
            double step = p.step > 1 ? p.step : 1;
            double mid = p.minValue + step * std::floor((p.maxValue - p.minValue) / step / 2);
            if (p.constraint == ParamDesc::Constraint::Odd && std::fmod(mid, 2.0) == 0.0) mid += step;  // stays on the grid only if step is odd
            if (p.constraint == ParamDesc::Constraint::PowerOfTwo) mid = std::exp2(std::round(std::log2(mid)));
            double lo = p.minValue, hi = p.maxValue, def = p.defaultValue;
            // Light samples and rays multiply the cost: reference with 65536 samples renders 65536
            // shadow maps, raytraced with 65536 rays traces 67M rays even at 32x32. Both are capped
            // at 64 here (the range check itself is covered by ParamValues::set tests); the default
            // (1024 samples, 256 rays) is still rendered.
            if (desc.id == "reference" && p.key == "samples") hi = 64, mid = 16;
            if (desc.id == "raytraced" && p.key == "rays") hi = 64, mid = 16;
            for (double v : {lo, hi, def, mid}) out.push_back(std::to_string((long long)v));
            return out;
        }
    }
    return out;
}

class Stage2Render : public GLTest {};

TEST_F(Stage2Render, EveryParameterValueGivesVisibilityInUnitRange) {
    Scene scene = loadScene("square-occluder");
    size_t renders = 0;
    double slowestMs = 0.0;
    std::string slowest;
    for (const TechniqueDesc* desc : allTechniques()) {
        for (const ParamDesc& p : desc->params) {
            std::vector<std::string> values = valuesToTry(*desc, p);
            std::set<std::string> unique(values.begin(), values.end());
            for (const std::string& value : unique) {
                RenderOptions options;
                options.width = options.height = 32;
                options.technique = desc->id;
                // Small sample counts for the references (the swept key overrides them).
                if (desc->id == "reference" && p.key != "samples") options.sets.push_back({"samples", "4"});
                if (desc->id == "raytraced" && p.key != "rays") options.sets.push_back({"rays", "4"});
                // 1024 light samples of a 1024^2 map would take seconds: the samples sweep uses 64^2 maps.
                if (desc->id == "reference" && p.key == "samples") options.sets.push_back({"sm_size", "64"});
                // sm_size 8192 with 4 samples would render four 8192^2 maps: one sample there.
                if (desc->id == "reference" && p.key == "sm_size") options.sets[0].second = "1";
                // Back-projection at sm_size 8192 walks kernels of max_kernel^2 texels per pixel: a
                // small cap there (the sweep checks the range of v, not its accuracy).
                if (desc->findParam("max_kernel") && p.key == "sm_size") options.sets.push_back({"max_kernel", "32"});
                options.sets.push_back({p.key, value});
                std::string what = desc->id + " " + p.key + "=" + value;
                SCOPED_TRACE(what);
                auto t0 = std::chrono::steady_clock::now();
                Renderer r(scene, options);
                r.renderFrame(0, kImageAndVisibility);
                glFinish();
                double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                if (ms > slowestMs) slowestMs = ms, slowest = what;
                ++renders;
                expectVisibilityInUnitRange(r, what);
                // The value reached the technique.
                nlohmann::json stats = r.stats({}, 0);
                const nlohmann::json& params = stats["lights"][0]["parameters"];
                if (desc->choose) {
                    // `auto`: the stats list the parameters of what it picked; its own hold the value.
                    const ParamValues& own = r.lights()[0]->requestedParams;
                    if (p.type == ParamDesc::Type::Enum)
                        EXPECT_EQ(own.getChoice(p.key), value);
                    else
                        EXPECT_DOUBLE_EQ(own.get(p.key), std::stod(value));
                    EXPECT_EQ(stats["lights"][0]["technique_requested"], desc->id);
                } else if (p.type == ParamDesc::Type::Enum)
                    EXPECT_EQ(params[p.key], value);
                else
                    EXPECT_DOUBLE_EQ(params[p.key].get<double>(), std::stod(value));
            }
        }
    }
    RecordProperty("renders", std::to_string(renders));
    std::printf("[ sweep    ] %zu renders; slowest %s: %.0f ms\n", renders, slowest.c_str(), slowestMs);
}

// ==== 2. live setters: exactly the expected passes re-run, and the result equals a fresh renderer ====
static_assert(std::is_const_v<std::remove_reference_t<decltype(*std::declval<Renderer&>().lights()[0])>>,
              "Renderer::lights() must expose lights read-only: changes go through setLight()");

constexpr int kLiveSize = 48;

RenderOptions pcfOptions(int size = kLiveSize) {
    RenderOptions o;
    o.width = o.height = size;
    o.technique = "pcf";
    return o;
}

// Renders frame 0, applies `change`, renders frame 1; returns the passes that ran in frame 1. The
// change must show in the visibility or the image (else a stale frame could pass as correct).
std::set<std::string> changeBetweenFrames(Renderer& r, const std::function<void(Renderer&)>& change,
                                          bool mustShow = true) {
    r.renderFrame(0, kImageAndVisibility);
    Image v0 = r.visibility(), i0 = r.image();
    change(r);
    r.renderFrame(1, kImageAndVisibility);
    if (mustShow) {
        Image v1 = r.visibility(), i1 = r.image();
        bool shows = v0.data.size() != v1.data.size() || i0.data.size() != i1.data.size() ||
                     std::memcmp(v0.data.data(), v1.data.data(), v0.data.size() * 4) != 0 ||
                     std::memcmp(i0.data.data(), i1.data.data(), i0.data.size() * 4) != 0;
        EXPECT_TRUE(shows) << "the change does not show in visibility() or image(): the test could not tell a stale frame";
    }
    return ranInLastFrame(r.stats({}, 0));
}

const std::string kGbuffer = "gbuffer", kShade = "shade", kMap = "L0/pcf/shadow_map", kFilter = "L0/pcf/filter";

class Stage2Live : public GLTest {};

TEST_F(Stage2Live, SetParamBiasRerunsOnlyFilterAndShade) {
    Scene scene = loadScene("square-occluder");
    // A 64^2 map, so that the largest bias (100 texels) lifts the plate's shadow off the floor:
    // the change shows.
    RenderOptions base = pcfOptions();
    base.sets = {{"sm_size", "64"}};
    Renderer live(scene, base);
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setParam("bias_const", "100"); });
    EXPECT_EQ(ran, (std::set<std::string>{kFilter, kShade})) << describeSet(ran);
    RenderOptions o = base;
    o.sets.push_back({"bias_const", "100"});
    Renderer fresh(scene, o);
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "bias_const=100");
}

TEST_F(Stage2Live, SetParamKernelRerunsOnlyFilterAndShade) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setParam("pcf_kernel", "9"); });
    EXPECT_EQ(ran, (std::set<std::string>{kFilter, kShade})) << describeSet(ran);
    EXPECT_THROW(live.setParam("pcf_kernel", "4"), InputError);
    RenderOptions o = pcfOptions();
    o.sets = {{"pcf_kernel", "9"}};
    Renderer fresh(scene, o);
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "pcf_kernel=9");
}

TEST_F(Stage2Live, SetParamShadowMapSizeRerunsMapFilterShade) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setParam("sm_size", "256"); });
    EXPECT_EQ(ran, (std::set<std::string>{kMap, kFilter, kShade})) << describeSet(ran);
    RenderOptions o = pcfOptions();
    o.sets = {{"sm_size", "256"}};
    Renderer fresh(scene, o);
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "sm_size=256");
}

TEST_F(Stage2Live, SetLightColourOrIntensityRerunsOnlyShade) {
    Scene scene = loadScene("square-occluder");
    for (int which = 0; which < 2; ++which) {
        Renderer live(scene, pcfOptions());
        Light changed = scene.lights[0];
        if (which == 0)
            changed.color = glm::vec3(1.0f, 0.5f, 0.25f);
        else
            changed.intensity = 2.0f;
        auto ran = changeBetweenFrames(live, [&](Renderer& r) { r.setLight(0, changed); });
        EXPECT_EQ(ran, (std::set<std::string>{kShade})) << (which ? "intensity " : "colour ") << describeSet(ran);
        Scene copy = scene;
        copy.lights[0] = changed;
        Renderer fresh(copy, pcfOptions());
        fresh.renderFrame(1, kImageAndVisibility);
        expectSameResult(live, fresh, which ? "intensity 2" : "colour (1, .5, .25)");
        EXPECT_EQ(live.lightAt(0).color, changed.color);
    }
}

TEST_F(Stage2Live, SetLightPositionRerunsShadowPassesNotGbuffer) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    Light moved = scene.lights[0];
    moved.position = glm::vec3(0.3f, 4.0f, 0.2f);
    auto ran = changeBetweenFrames(live, [&](Renderer& r) { r.setLight(0, moved); });
    EXPECT_EQ(ran, (std::set<std::string>{kMap, kFilter, kShade})) << describeSet(ran);
    Scene copy = scene;
    copy.lights[0] = moved;
    Renderer fresh(copy, pcfOptions());
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "light moved");
}

TEST_F(Stage2Live, SetCameraRerunsGbufferFilterShadeNotShadowMap) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    Camera camera = scene.camera;
    camera.position = glm::vec3(0.5f, 5.0f, 6.0f);
    auto ran = changeBetweenFrames(live, [&](Renderer& r) { r.setCamera(camera); });
    EXPECT_EQ(ran, (std::set<std::string>{kGbuffer, kFilter, kShade})) << describeSet(ran);
    Scene copy = scene;
    copy.camera = camera;
    Renderer fresh(copy, pcfOptions());
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "camera moved");
}

TEST_F(Stage2Live, SetAmbientRerunsOnlyShade) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setAmbient(0.4f); });
    EXPECT_EQ(ran, (std::set<std::string>{kShade})) << describeSet(ran);
    EXPECT_THROW(live.setAmbient(-1.0f), InputError);
    Scene copy = scene;
    copy.ambient = 0.4f;
    Renderer fresh(copy, pcfOptions());
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "ambient 0.4");
}

TEST_F(Stage2Live, SetTechniqueRunsNewPassesAndKeepsGbuffer) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setTechnique("hard"); });
    EXPECT_EQ(ran, (std::set<std::string>{"L0/hard/shadow_map", "L0/hard/visibility", kShade})) << describeSet(ran);
    nlohmann::json stats = live.stats({}, 0);
    EXPECT_EQ(passStats(stats, kGbuffer)["runs"], 1);
    EXPECT_EQ(passStats(stats, kGbuffer)["reuses"], 1);
    EXPECT_EQ(stats["lights"][0]["technique"], "hard");
    RenderOptions o = pcfOptions();
    o.technique = "hard";
    Renderer fresh(scene, o);
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "setTechnique(hard)");
}

TEST_F(Stage2Live, SetTimeOnMovingSceneRerunsShadowMap) {
    Scene scene = loadScene("cube-popping");
    ASSERT_TRUE(scene.hasMotion());
    Renderer live(scene, pcfOptions());
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setTime(0.5); });
    EXPECT_TRUE(ran.count(kMap)) << describeSet(ran);
    EXPECT_EQ(ran, (std::set<std::string>{kGbuffer, kMap, kFilter, kShade})) << describeSet(ran);
    EXPECT_DOUBLE_EQ(live.time(), 0.5);
    Renderer fresh(scene, pcfOptions());
    fresh.setTime(0.5);
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "setTime(0.5)");
}

TEST_F(Stage2Live, ResizeRerunsFrameSizedPasses) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions(kLiveSize));
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.resize(64, 40); });
    EXPECT_EQ(ran, (std::set<std::string>{kGbuffer, kFilter, kShade})) << describeSet(ran);
    EXPECT_EQ(live.pool().find("L0/visibility")->width, 64);
    EXPECT_EQ(live.pool().find("L0/visibility")->height, 40);
    RenderOptions o = pcfOptions();
    o.width = 64;
    o.height = 40;
    Renderer fresh(scene, o);
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "resize 64x40");
}

// A size and back with no frame between gives the first size's versions again while the G-buffer
// and the shaded image were reallocated: the frame after it still renders them (the window's paused
// ray tracer is resized with the view and read back later).
TEST_F(Stage2Live, ResizeAndBackWithoutAFrameStillRendersTheGBuffer) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions(kLiveSize));
    live.renderFrame(1, kImageAndVisibility);
    live.resize(64, 40);
    live.resize(kLiveSize, kLiveSize);
    live.renderFrame(2, kImageAndVisibility);
    Renderer fresh(scene, pcfOptions(kLiveSize));
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "resize and back");
    size_t onGeometry = 0;
    for (float v : live.positions().data) onGeometry += std::isfinite(v);
    EXPECT_GT(onGeometry, 0u);
}

TEST_F(Stage2Live, LightSizeZeroTurnsSoftIntoHardAndBack) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    Light point = scene.lights[0];
    point.size = 0.0f;
    auto ran = changeBetweenFrames(live, [&](Renderer& r) { r.setLight(0, point); });
    nlohmann::json stats = live.stats({}, 0);
    EXPECT_EQ(stats["lights"][0]["technique"], "hard");
    EXPECT_EQ(stats["lights"][0]["technique_requested"], "pcf");
    EXPECT_EQ(ran, (std::set<std::string>{"L0/hard/shadow_map", "L0/hard/visibility", kShade})) << describeSet(ran);
    EXPECT_EQ(passStats(stats, kFilter)["status"], "skipped");
    {
        Scene copy = scene;
        copy.lights[0] = point;
        Renderer fresh(copy, pcfOptions());
        fresh.renderFrame(1, kImageAndVisibility);
        expectSameResult(live, fresh, "light size 0");
    }
    // And back to a square light of width 1: pcf again.
    live.setLight(0, scene.lights[0]);
    live.renderFrame(2, kImageAndVisibility);
    stats = live.stats({}, 0);
    EXPECT_EQ(stats["lights"][0]["technique"], "pcf");
    ran = ranInLastFrame(stats);
    EXPECT_EQ(ran, (std::set<std::string>{kMap, kFilter, kShade})) << describeSet(ran);
    Renderer fresh(scene, pcfOptions());
    fresh.renderFrame(2, kImageAndVisibility);
    expectSameResult(live, fresh, "light size back to 1");
}

TEST_F(Stage2Live, SetParamSecondDepthRerunsMapFilterShade) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    auto ran = changeBetweenFrames(
        live, [](Renderer& r) {
            r.setParam("second_depth", "1");
            r.setParam("bias_const", "0");
            r.setParam("bias_slope", "0");
        },
        false);  // second depth without bias is meant to look like the biased first depth: no visible change
    EXPECT_NE(live.pool().find("L0/shadow_map_second_depth"), nullptr);
    EXPECT_EQ(ran, (std::set<std::string>{kMap, kFilter, kShade})) << describeSet(ran);
    RenderOptions o = pcfOptions();
    o.sets = {{"second_depth", "1"}, {"bias_const", "0"}, {"bias_slope", "0"}};
    Renderer fresh(scene, o);
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "second_depth=1");
}

TEST_F(Stage2Live, SetTimeOnStaticSceneRerunsNothing) {
    Scene scene = loadScene("square-occluder");
    ASSERT_FALSE(scene.hasMotion());
    Renderer live(scene, pcfOptions());
    auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setTime(0.5); }, false);
    EXPECT_EQ(ran, std::set<std::string>{}) << describeSet(ran);
}

TEST_F(Stage2Live, SetLightCastsNoShadowsRerunsOnlyShade) {
    Scene scene = loadScene("square-occluder");
    Renderer live(scene, pcfOptions());
    Light noShadow = scene.lights[0];
    noShadow.castsShadows = false;
    auto ran = changeBetweenFrames(live, [&](Renderer& r) { r.setLight(0, noShadow); });
    EXPECT_EQ(ran, (std::set<std::string>{kShade})) << describeSet(ran);
    Scene copy = scene;
    copy.lights[0] = noShadow;
    Renderer fresh(copy, pcfOptions());
    fresh.renderFrame(1, kImageAndVisibility);
    expectSameResult(live, fresh, "casts_shadows false");
    for (float v : live.visibility().data) ASSERT_EQ(v, 1.0f);
}

// Two shadow-casting lights: a setter aimed at one light re-runs only that light's passes.
TEST_F(Stage2Live, PerLightSettersTouchOnlyThatLight) {
    Scene scene = loadScene("complex");
    ASSERT_EQ(scene.lights.size(), 2u);
    {
        Renderer live(scene, pcfOptions());
        auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setParam("pcf_kernel", "15", 1); });
        EXPECT_EQ(ran, (std::set<std::string>{"L1/pcf/filter", kShade})) << describeSet(ran);
        // Against a renderer given the same per-light value before its first frame.
        Renderer fresh(scene, pcfOptions());
        fresh.setParam("pcf_kernel", "15", 1);
        fresh.renderFrame(1, kImageAndVisibility);
        expectSameResult(live, fresh, "L1 pcf_kernel=15");
        nlohmann::json stats = live.stats({}, 0);
        EXPECT_EQ(stats["lights"][0]["parameters"]["pcf_kernel"], 5);
        EXPECT_EQ(stats["lights"][1]["parameters"]["pcf_kernel"], 15);
    }
    {
        Renderer live(scene, pcfOptions());
        auto ran = changeBetweenFrames(live, [](Renderer& r) { r.setTechnique("hard", 1); });
        EXPECT_EQ(ran, (std::set<std::string>{"L1/hard/shadow_map", "L1/hard/visibility", kShade})) << describeSet(ran);
        nlohmann::json stats = live.stats({}, 0);
        EXPECT_EQ(stats["lights"][0]["technique"], "pcf");
        EXPECT_EQ(stats["lights"][1]["technique"], "hard");
        Renderer fresh(scene, pcfOptions());
        fresh.setTechnique("hard", 1);
        fresh.renderFrame(1, kImageAndVisibility);
        expectSameResult(live, fresh, "L1 technique hard");
    }
}

// ==== 3. cost statistics on a static scene ==========================================================
TEST(Stage2Stats, StaticSceneReportsCostSeparatelyFromFrameTime) {
    std::string stats = tmpDir() + "/s.json";
    CliResult r = runCli("render --scene square-occluder --size 64x64 --technique pcf --frames 10 --stats " + stats);
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json s = nlohmann::json::parse(readFile(stats));
    double frame = s["frame_ms"], cost = s["cost_ms"], shadow = s["shadow_ms"], fixed = s["fixed_ms"];
    EXPECT_GT(cost, 0.0);
    EXPECT_GT(shadow, 0.0);
    EXPECT_GT(fixed, 0.0);
    EXPECT_NEAR(cost, shadow + fixed, 1e-9);
    EXPECT_LT(frame, cost) << "frames of a static scene reuse every pass";
    double shadowSum = 0.0, fixedSum = 0.0;
    for (const auto& p : s["passes"]) {
        if (!p["needed"].get<bool>()) continue;
        (p["cost"] == "shadow" ? shadowSum : fixedSum) += p["median_ms"].get<double>();
        EXPECT_GT(p["median_ms"].get<double>(), 0.0) << p.dump();
    }
    EXPECT_NEAR(shadow, shadowSum, 1e-9);
    EXPECT_NEAR(fixed, fixedSum, 1e-9);
    const auto& sm = passStats(s, "L0/pcf/shadow_map");
    EXPECT_EQ(sm["runs"], 1) << "cost measurement must not count as runs";
    EXPECT_EQ(sm["reuses"], 10);
    EXPECT_EQ(sm["cost"], "shadow");
    EXPECT_EQ(passStats(s, "gbuffer")["cost"], "fixed");
    EXPECT_EQ(passStats(s, "gbuffer")["runs"], 1);
    RecordProperty("frame_ms", numberText(frame));
    RecordProperty("cost_ms", numberText(cost));
    RecordProperty("shadow_ms", numberText(shadow));
    RecordProperty("fixed_ms", numberText(fixed));
    std::printf("[ stats    ] pcf 64x64 static: frame_ms %.4f cost_ms %.4f shadow_ms %.4f fixed_ms %.4f\n", frame, cost,
                shadow, fixed);
}

// frameCost (frame_stats.h) is what --stats and the bench report: a hand-made graph with known
// times per frame gives known medians and the shadow/fixed split by technique.
TEST(Stage2Stats, FrameCostSplitsNeededPassesByTechnique) {
    EXPECT_DOUBLE_EQ(medianMs({}), 0.0);
    EXPECT_DOUBLE_EQ(medianMs({3.0, 1.0, 2.0}), 2.0);
    EXPECT_DOUBLE_EQ(medianMs({4.0, 1.0, 2.0, 3.0}), 2.5);
    PassGraph graph;
    graph.setSource("camera", 1);
    graph.setSource("light", 1);
    std::string current;
    auto pass = [&](const std::string& name) { return [&current, name] { current = name; }; };
    graph.addPass("gbuffer", "frame", "", {"camera"}, {"gbuffer"}, {}, pass("gbuffer"));
    graph.addPass("L0/pcf/shadow_map", "L0", "pcf", {"light"}, {"L0/pcf/depth"}, {}, pass("L0/pcf/shadow_map"));
    graph.addPass("L0/pcf/filter", "L0", "pcf", {"gbuffer", "L0/pcf/depth"}, {"L0/visibility"}, {}, pass("L0/pcf/filter"));
    graph.addPass("unused", "L0", "pcf", {"light"}, {"L0/other"}, {}, pass("unused"));
    // Scripted times per frame (frame 0 is the warm-up the cost leaves out).
    std::map<std::string, std::vector<double>> ms{{"gbuffer", {9.0, 1.0, 2.0, 3.0}},
                                                  {"L0/pcf/shadow_map", {50.0, 4.0, 4.0, 3.0}},
                                                  {"L0/pcf/filter", {70.0, 7.0, 5.0, 6.0}},
                                                  {"unused", {100.0, 100.0, 100.0, 100.0}}};
    for (int frame = 0; frame < 4; ++frame) {
        graph.measureCost({"L0/visibility"}, frame, [&](const std::function<void()>& run) {
            run();
            return ms.at(current)[size_t(frame)];
        });
    }
    FrameCost c = frameCost(graph, {"gbuffer", "L0/pcf/shadow_map", "L0/pcf/filter"}, 1);
    EXPECT_DOUBLE_EQ(c.fixedMs, 2.0);
    EXPECT_DOUBLE_EQ(c.shadowMs, 4.0 + 6.0);
    EXPECT_DOUBLE_EQ(c.costMs(), 12.0);
    EXPECT_DOUBLE_EQ(c.passMs("L0/pcf/filter"), 6.0);
    EXPECT_DOUBLE_EQ(c.passMs("unused"), 0.0) << "a pass that never ran costs nothing";
    EXPECT_DOUBLE_EQ(c.passMs("absent"), 0.0);
    ASSERT_EQ(c.passes.size(), 4u);
    EXPECT_FALSE(c.passes[0].isShadow());
    EXPECT_TRUE(c.passes[1].isShadow());
    EXPECT_FALSE(c.passes[3].needed);
}

// ==== 4. reuse checks ===============================================================================
TEST(Stage2Reuse, CheckReusePassesOnEveryTechniqueAndScene) {
    std::string dir = tmpDir();
    std::vector<std::string> commands, labels;
    for (const std::string& scene : testing::loadableScenes()) {
        for (const TechniqueDesc* d : allTechniques()) {
            std::string sets = d->id == "reference" ? " --set samples=4" : d->id == "raytraced" ? " --set rays=2" : "";
            if (d->findParam("sm_size")) sets += " --set sm_size=256";
            std::string stats = dir + "/" + scene + "-" + d->id + ".json";
            fs::remove(stats);
            commands.push_back("render --scene " + scene + " --size 32x32 --technique " + d->id + sets +
                               " --check-reuse --frames 2 --stats " + stats);
            labels.push_back(stats);
        }
    }
    ASSERT_GE(commands.size(), 4u * 9u);
    std::vector<CliResult> results = runCliParallel(commands);
    for (size_t i = 0; i < commands.size(); ++i) {
        EXPECT_EQ(results[i].code, 0) << commands[i] << "\n" << results[i].output;
        if (results[i].code != 0) continue;
        nlohmann::json s = nlohmann::json::parse(readFile(labels[i]));
        EXPECT_EQ(s["check_reuse"], "passed") << commands[i];
    }
}

TEST_F(Stage2Render, CheckReuseInProcessIsEmpty) {
    Scene scene = loadScene("square-occluder");
    Renderer r(scene, pcfOptions());
    r.renderFrame(0, kImageAndVisibility);
    r.renderFrame(1, kImageAndVisibility);
    EXPECT_EQ(r.checkReuse(), std::vector<std::string>{});
    // checkReuse re-runs passes but does not count them.
    nlohmann::json stats = r.stats({}, 0);
    EXPECT_EQ(passStats(stats, kMap)["runs"], 1);
    EXPECT_EQ(passStats(stats, kMap)["reuses"], 1);
}

// A technique (never registered) whose pass reads something it did not declare.
class ReadsParamPass : public Pass {
public:
    void execute(PassContext& ctx) override { (void)ctx.param("x"); }
};
class ReadsLightPass : public Pass {
public:
    void execute(PassContext& ctx) override { (void)ctx.light(); }
};

TechniqueDesc undeclaredReadTechnique(bool light) {
    TechniqueDesc d;
    d.id = "sneaky";
    d.name = "Sneaky";
    d.citation = "test";
    d.params = {{"x", "", ParamDesc::Type::Float, "", 0.5, 0, 1, 0.1, "a parameter the pass forgets to declare", ""}};
    PassDesc p;
    p.name = "sneak";
    p.doc = "reads param:x / light without declaring them";
    p.reads = {"gbuffer"};
    p.creates = {visibilityResource()};
    if (light)
        p.create = [] { return std::make_unique<ReadsLightPass>(); };
    else
        p.create = [] { return std::make_unique<ReadsParamPass>(); };
    d.passes = {p};
    return d;
}

void expectUndeclared(const std::function<void()>& f, const std::string& what) {
    try {
        f();
        ADD_FAILURE() << what << ": no exception";
    } catch (const InternalError& e) {
        EXPECT_NE(std::string(e.what()).find("without declaring"), std::string::npos) << what << ": " << e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": wrong exception type: " << e.what();
    }
}

TEST_F(Stage2Render, PassContextRefusesUndeclaredUse) {
    Scene scene = loadScene("square-occluder");
    GpuScene gpu(scene);
    ProgramCache programs;
    FrameState frame;
    frame.scene = &scene;
    frame.gpu = &gpu;
    frame.programs = &programs;
    frame.width = frame.height = 8;
    frame.camera = scene.camera;
    ResourcePool pool;

    for (bool light : {false, true}) {
        TechniqueDesc desc = undeclaredReadTechnique(light);
        EXPECT_EQ(validateTechnique(desc), std::vector<std::string>{});  // the declaration itself is sound
        LightState state;
        state.group = "L0";
        state.light = scene.lights[0];
        state.requested = state.desc = &desc;
        state.requestedParams = state.params = ParamValues(desc);
        // As the renderer runs a pass: declared = reads and writes.
        const PassDesc& pass = desc.passes[0];
        std::set<std::string> declared(pass.reads.begin(), pass.reads.end());
        for (const std::string& w : pass.writes()) declared.insert(w);
        PassContext ctx(frame, &state, pool, "L0/sneaky/sneak", declared);
        std::unique_ptr<Pass> object = pass.create();
        expectUndeclared([&] { object->execute(ctx); }, light ? "pass calling light()" : "pass calling param(x)");
    }

    // Every accessor, undeclared and declared.
    TechniqueDesc desc = undeclaredReadTechnique(false);
    LightState state;
    state.group = "L0";
    state.light = scene.lights[0];
    state.requested = state.desc = &desc;
    state.requestedParams = state.params = ParamValues(desc);
    pool.ensure("L0/tex", ResourceDesc::texture("tex", Format::R32F, SizeRule::fixed(8, 8), "test texture"), 8, 8);
    const ShaderProgram& program = programs.get("common/shadow_depth.vert", "common/shadow_depth.frag");

    PassContext bare(frame, &state, pool, "bare", {"gbuffer"});
    expectUndeclared([&] { bare.texture("tex"); }, "texture(tex)");
    expectUndeclared([&] { bare.param("x"); }, "param(x)");
    expectUndeclared([&] { bare.paramInt("x"); }, "paramInt(x)");
    expectUndeclared([&] { bare.light(); }, "light()");
    expectUndeclared([&] { bare.lightView(); }, "lightView()");
    expectUndeclared([&] { bare.lightRadiance(); }, "lightRadiance()");
    expectUndeclared([&] { bare.sceneBounds(); }, "sceneBounds()");
    expectUndeclared([&] { bare.drawScene(program, true); }, "drawScene(casters)");
    expectUndeclared([&] { bare.drawScene(program, false); }, "drawScene(objects)");
    expectUndeclared([&] { bare.camera(); }, "camera()");
    expectUndeclared([&] { bare.ambient(); }, "ambient()");
    expectUndeclared([&] { bare.applies("x > 0.2"); }, "applies(x > 0.2)");
    EXPECT_NO_THROW(bare.gbuffer());

    PassContext full(frame, &state, pool, "full",
                     {"tex", "param:x", "light", "light.radiance", "scene.casters", "camera", "ambient"});
    EXPECT_NO_THROW(full.texture("tex"));
    EXPECT_EQ(full.texture("tex").width(), 8);
    EXPECT_DOUBLE_EQ(full.param("x"), 0.5);
    EXPECT_TRUE(full.applies("x > 0.2"));
    EXPECT_NO_THROW(full.light());
    EXPECT_NO_THROW(full.lightRadiance());
    EXPECT_NO_THROW(full.camera());
    EXPECT_NO_THROW(full.ambient());
    EXPECT_NO_THROW(full.sceneTime(true));
    expectUndeclared([&] { full.sceneTime(false); }, "sceneTime(objects) with only casters declared");
    expectUndeclared([&] { full.gbuffer(); }, "gbuffer() undeclared");
    {
        // Draw the casters into a small target: declared, so no throw (and no GL error).
        Texture color(8, 8, GL_R32F);
        Texture depth(8, 8, GL_DEPTH_COMPONENT32F);
        Framebuffer fbo({&color}, &depth);
        fbo.bind(8, 8);
        program.use();
        EXPECT_NO_THROW(full.drawScene(program, true));
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

    // A frame pass (no light) asking for a light or a parameter.
    PassContext framePass(frame, nullptr, pool, "framepass", {"gbuffer", "light", "param:x"});
    EXPECT_THROW(framePass.light(), InternalError);
    EXPECT_THROW(framePass.param("x"), InternalError);
}

// ==== 5. internals ==================================================================================
TEST(Stage2Internals, IndexListsExactlyTheApplicableInternals) {
    struct Case {
        std::string technique;
        std::vector<std::pair<std::string, std::string>> sets;
    };
    std::vector<Case> cases;
    for (const TechniqueDesc* d : allTechniques()) {
        // `auto` writes the internals of the technique it picked, whose own case here covers them.
        if (d->choose) continue;
        std::vector<std::pair<std::string, std::string>> sets;
        if (d->findParam("sm_size")) sets.push_back({"sm_size", "64"});
        if (d->id == "reference") sets.push_back({"samples", "4"});
        if (d->id == "raytraced") sets.push_back({"rays", "4"});
        cases.push_back({d->id, sets});
        if (d->id == "hard" || d->id == "pcf") {
            sets.push_back({"second_depth", "1"});
            cases.push_back({d->id, sets});
        }
    }
    std::string root = tmpDir();
    std::vector<std::string> commands, dirs;
    for (size_t c = 0; c < cases.size(); ++c) {
        std::string dir = root + "/case" + std::to_string(c) + "-" + cases[c].technique;
        fs::remove_all(dir);
        std::string cmd = "render --scene square-occluder --size 32x32 --technique " + cases[c].technique +
                          " --internals " + dir + " --pixel 16,16";
        for (const auto& [k, v] : cases[c].sets) cmd += " --set " + k + "=" + v;
        commands.push_back(cmd);
        dirs.push_back(dir);
    }
    std::vector<CliResult> results = runCliParallel(commands);
    for (size_t c = 0; c < cases.size(); ++c) {
        const Case& tc = cases[c];
        SCOPED_TRACE(commands[c]);
        ASSERT_EQ(results[c].code, 0) << results[c].output;
        const TechniqueDesc& desc = requireTechnique(tc.technique, "test");
        ParamValues values(desc);
        for (const auto& [k, v] : tc.sets) values.set(desc, k, v, "test");
        std::set<std::string> expected = {"visibility", "pixel"};
        for (const InternalDesc& i : desc.internals) {
            if (i.kind == InternalDesc::Kind::Record) continue;
            if (!i.appliesWhen.empty() && !Condition(i.appliesWhen, desc, "test").holds(values)) continue;
            expected.insert(i.name);
        }
        nlohmann::json index = nlohmann::json::parse(readFile(dirs[c] + "/index.json"));
        std::set<std::string> names;
        for (const auto& e : index["files"]) {
            names.insert(e["name"].get<std::string>());
            std::string file = dirs[c] + "/" + e["file"].get<std::string>();
            EXPECT_TRUE(fs::exists(file)) << file;
            if (file.size() > 4 && file.substr(file.size() - 4) == ".pfm") {
                Image img = readPFM(file);
                EXPECT_EQ(img.width, e["size"][0].get<int>()) << file;
                EXPECT_EQ(img.height, e["size"][1].get<int>()) << file;
                std::string name = e["name"];
                if (name == "visibility") {
                    EXPECT_EQ(img.width, 32);
                    EXPECT_EQ(img.height, 32);
                } else if (name.find("shadow_map") != std::string::npos) {
                    EXPECT_EQ(img.width, 64) << name;
                    EXPECT_EQ(img.height, 64) << name;
                }
            }
        }
        EXPECT_EQ(names, expected) << "index " << describeSet(names) << " expected " << describeSet(expected);

        // pixel.json: lights[0] carries the record schema's fields.
        nlohmann::json pixel = nlohmann::json::parse(readFile(dirs[c] + "/pixel.json"));
        ASSERT_TRUE(pixel.contains("lights")) << pixel.dump();
        const nlohmann::json& l0 = pixel["lights"][0];
        EXPECT_EQ(l0["technique"], tc.technique);
        nlohmann::json described = describeTechnique(desc);
        std::set<std::string> schemaFields;
        for (const auto& i : described["internals"])
            if (i["kind"] == "record" && i.contains("schema"))
                for (const auto& field : i["schema"].items()) schemaFields.insert(field.key());
        ASSERT_FALSE(schemaFields.empty());
        bool background = l0.value("background", false);
        EXPECT_FALSE(background) << "pixel 16,16 of square-occluder is on the floor";
        for (const std::string& f : schemaFields) {
            if (f == "background") continue;  // only on background pixels
            EXPECT_TRUE(l0.contains(f)) << "pixel.json lights[0] lacks '" << f << "': " << l0.dump();
        }
        for (const auto& item : l0.items())
            EXPECT_TRUE(schemaFields.count(item.key()) || item.key() == "light" || item.key() == "technique")
                << "pixel.json field '" << item.key() << "' is not in the schema";
    }
}

// ==== 6. resources and the pool =====================================================================
TEST_F(Stage2Render, PoolHoldsDeclaredResourcesAndCountsMemory) {
    Scene scene = loadScene("square-occluder");
    RenderOptions o = pcfOptions(40);
    o.sets = {{"sm_size", "128"}};
    Renderer r(scene, o);
    r.renderFrame(0, kImageAndVisibility);
    nlohmann::json stats = r.stats({}, 0);
    auto resource = [&](const nlohmann::json& s, const std::string& name) -> nlohmann::json {
        for (const auto& res : s["resources"])
            if (res["name"] == name) return res;
        ADD_FAILURE() << "no resource " << name << " in " << s["resources"].dump();
        return nlohmann::json::object();
    };
    auto sm = resource(stats, "L0/shadow_map");
    EXPECT_EQ(sm["format"], "R32F");
    EXPECT_EQ(sm["width"], 128);
    EXPECT_EQ(sm["height"], 128);
    auto vis = resource(stats, "frame/visibility");
    EXPECT_EQ(vis["width"], 40);
    EXPECT_EQ(vis["height"], 40);
    auto lvis = resource(stats, "L0/visibility");
    EXPECT_EQ(lvis["width"], 40);
    EXPECT_EQ(lvis["format"], "R32F");
    auto memoryAdds = [&](const nlohmann::json& s) {
        size_t sum = 0;
        for (const auto& res : s["resources"]) sum += res["bytes"].get<size_t>();
        EXPECT_EQ(s["memory_bytes"].get<size_t>(), sum + s["scene_bytes"].get<size_t>());
        EXPECT_EQ(sm["bytes"].get<size_t>() > 0, true);
    };
    memoryAdds(stats);
    EXPECT_EQ(r.pool().find("L0/shadow_map_second_depth"), nullptr) << "second_depth=0 allocates no second depth";

    r.setParam("sm_size", "256");
    r.renderFrame(1, kImageAndVisibility);
    ASSERT_NE(r.pool().find("L0/shadow_map"), nullptr);
    EXPECT_EQ(r.pool().find("L0/shadow_map")->width, 256);
    EXPECT_EQ(r.pool().find("L0/shadow_map_zbuffer")->width, 256);
    memoryAdds(r.stats({}, 0));

    r.setParam("second_depth", "1");
    r.renderFrame(2, kImageAndVisibility);
    ASSERT_NE(r.pool().find("L0/shadow_map_second_depth"), nullptr) << "second_depth=1 allocates it";
    EXPECT_EQ(r.pool().find("L0/shadow_map_second_depth")->width, 256);
    r.setParam("second_depth", "0");
    r.renderFrame(3, kImageAndVisibility);
    EXPECT_EQ(r.pool().find("L0/shadow_map_second_depth"), nullptr) << "freed when it no longer applies";

    r.setTechnique("raytraced");
    r.setParam("rays", "4");
    r.renderFrame(4, kImageAndVisibility);
    for (const auto& [name, res] : r.pool().all()) {
        EXPECT_EQ(name.find("shadow_map"), std::string::npos) << name << " left in the pool after raytraced";
    }
    EXPECT_NE(r.pool().find("L0/visibility"), nullptr);
    memoryAdds(r.stats({}, 0));
    expectVisibilityInUnitRange(r, "raytraced after pcf");
}

// The pool frees what no pass declares any more, whichever setter made it so: a point light runs
// `hard` instead of `reference` (no light-sample maps), a light that casts no shadows runs nothing.
// PRODUCTION BUG (disabled until fixed): Renderer::setLight() rebuilds the graph when the light
// becomes a point light or stops casting shadows, but unlike setTechnique() it never releases the
// resources no pass declares any more, so they stay allocated and counted in memory_bytes:
//   after setLight(size 0):            L0/sample_shadow_map, L0/sample_shadow_map_zbuffer remain
//   after setLight(casts_shadows no):  L0/sample_shadow_map(_zbuffer), L0/shadow_map(_zbuffer),
//                                      L0/visibility remain
std::string leftovers(const Renderer& r, const std::function<bool(const std::string&)>& stale) {
    std::string out;
    for (const auto& entry : r.pool().all())
        if (stale(entry.first)) out += " " + entry.first + " (" + std::to_string(entry.second->bytes()) + " B)";
    return out;
}

TEST_F(Stage2Render, PoolFreesResourcesOfPassesThatNoLongerRun) {
    Scene scene = loadScene("square-occluder");
    RenderOptions o = pcfOptions(32);
    o.technique = "reference";
    o.sets = {{"samples", "4"}, {"sm_size", "64"}};
    Renderer r(scene, o);
    r.renderFrame(0, kImageAndVisibility);
    ASSERT_NE(r.pool().find("L0/sample_shadow_map"), nullptr);
    Light point = scene.lights[0];
    point.size = 0.0f;
    r.setLight(0, point);
    r.renderFrame(1, kImageAndVisibility);
    EXPECT_EQ(r.stats({}, 0)["lights"][0]["technique"], "hard");
    EXPECT_EQ(leftovers(r, [](const std::string& n) { return n.find("sample_shadow_map") != std::string::npos; }), "")
        << "left in the pool after the light became a point light (`reference` no longer runs)";
    Light dark = scene.lights[0];
    dark.castsShadows = false;
    r.setLight(0, dark);
    r.renderFrame(2, kImageAndVisibility);
    EXPECT_EQ(leftovers(r, [](const std::string& n) { return n.rfind("L0/", 0) == 0; }), "")
        << "left in the pool after the light stopped casting shadows";
}

TEST(Stage2Resources, MeshToPlyParsesBack) {
    MeshData mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5f}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.primitiveAttributes = {{"weight", {0.25f, 1.5f}}};
    ASSERT_EQ(mesh.primitiveCount(), 2u);
    std::istringstream in(meshToPLY(mesh));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "ply");
    size_t vertices = 0, faces = 0;
    std::vector<std::string> faceProperties;
    bool inFace = false;
    while (std::getline(in, line) && line != "end_header") {
        std::istringstream l(line);
        std::string word, kind;
        l >> word;
        if (word == "element") {
            size_t n;
            l >> kind >> n;
            inFace = kind == "face";
            (kind == "vertex" ? vertices : faces) = n;
        } else if (word == "property" && inFace) {
            faceProperties.push_back(line);
        }
    }
    ASSERT_EQ(line, "end_header");
    EXPECT_EQ(vertices, 4u);
    EXPECT_EQ(faces, 2u);
    ASSERT_EQ(faceProperties.size(), 2u);
    EXPECT_EQ(faceProperties[1], "property float weight");
    for (size_t v = 0; v < 4; ++v) {
        float x, y, z;
        in >> x >> y >> z;
        EXPECT_EQ(glm::vec3(x, y, z), mesh.positions[v]) << v;
    }
    for (size_t f = 0; f < 2; ++f) {
        int count;
        uint32_t a, b, c;
        float w;
        in >> count >> a >> b >> c >> w;
        EXPECT_EQ(count, 3);
        EXPECT_EQ(a, mesh.indices[f * 3]);
        EXPECT_EQ(b, mesh.indices[f * 3 + 1]);
        EXPECT_EQ(c, mesh.indices[f * 3 + 2]);
        EXPECT_EQ(w, mesh.primitiveAttributes[0].second[f]);
    }
    EXPECT_TRUE(bool(in));
    EXPECT_EQ(mesh.bytes(), 4 * sizeof(glm::vec3) + 6 * sizeof(uint32_t) + 2 * sizeof(float));

    // Lines: "edge" elements with two vertex properties.
    MeshData lines;
    lines.verticesPerPrimitive = 2;
    lines.positions = {{0, 0, 0}, {1, 0, 0}};
    lines.indices = {0, 1};
    std::string ply = meshToPLY(lines);
    EXPECT_NE(ply.find("element edge 1"), std::string::npos) << ply;
    EXPECT_NE(ply.find("\n0 1\n"), std::string::npos) << ply;

    // An attribute with the wrong count is a programming error.
    mesh.primitiveAttributes[0].second.push_back(3.0f);
    EXPECT_THROW(meshToPLY(mesh), InternalError);
}

// ==== 7. pass graph: versions per write ================================================================
TEST(Stage2Graph, VersionsPerWrite) {
    std::map<std::string, int> runs;
    auto counter = [&](const std::string& n) { return [&runs, n] { ++runs[n]; }; };
    auto timer = [](const std::function<void()>& f) {
        f();
        return 0.01;
    };
    PassGraph graph;
    graph.setSource("src.a", 1);
    graph.setSource("src.b", 1);
    auto addAll = [&] {
        graph.addPass("a", "L0", "t", {"src.a"}, {"X"}, {}, counter("a"));
        graph.addPass("d", "L0", "t", {"X"}, {"D"}, {}, counter("d"));  // reads X#0, before b
        graph.addPass("b", "L0", "t", {"src.b"}, {}, {"X"}, counter("b"));
        graph.addPass("c", "L0", "t", {"X"}, {"C"}, {}, counter("c"));  // reads X#1
    };
    addAll();
    EXPECT_EQ(graph.neededPasses({"X"}), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(graph.neededPasses({"D"}), (std::vector<std::string>{"a", "d"}));
    EXPECT_EQ(graph.neededPasses({"C"}), (std::vector<std::string>{"a", "b", "c"}));

    graph.execute({"C", "D"}, 0, timer);
    EXPECT_EQ(runs, (std::map<std::string, int>{{"a", 1}, {"b", 1}, {"c", 1}, {"d", 1}}));

    // A source only b reads: b and c (after b) re-run, a and d (before b) do not.
    graph.setSource("src.b", 2);
    graph.execute({"C", "D"}, 1, timer);
    EXPECT_EQ(runs, (std::map<std::string, int>{{"a", 1}, {"b", 2}, {"c", 2}, {"d", 1}}));

    // A source a reads: everything downstream of X#0 re-runs.
    graph.setSource("src.a", 2);
    graph.execute({"C", "D"}, 2, timer);
    EXPECT_EQ(runs, (std::map<std::string, int>{{"a", 2}, {"b", 3}, {"c", 3}, {"d", 2}}));

    // rebuild() and the same passes again: their cached state is kept, nothing re-runs.
    graph.rebuild();
    addAll();
    graph.execute({"C", "D"}, 3, timer);
    EXPECT_EQ(runs, (std::map<std::string, int>{{"a", 2}, {"b", 3}, {"c", 3}, {"d", 2}}));
    for (const PassRecord& r : graph.records()) EXPECT_EQ(r.history.back(), "reused") << r.name;

    // Requesting X alone after b's source changed: b re-runs, a is reused, c and d are not needed.
    graph.setSource("src.b", 3);
    graph.execute({"X"}, 4, timer);
    EXPECT_EQ(runs, (std::map<std::string, int>{{"a", 2}, {"b", 4}, {"c", 3}, {"d", 2}}));
    for (const PassRecord& r : graph.records())
        if (r.name == "c" || r.name == "d") EXPECT_EQ(r.history.back(), "not needed") << r.name;

    // A fresh graph asked only for X runs a and b.
    {
        std::map<std::string, int> fresh;
        PassGraph g;
        g.setSource("src.a", 1);
        g.setSource("src.b", 1);
        g.addPass("a", "L0", "t", {"src.a"}, {"X"}, {}, [&] { ++fresh["a"]; });
        g.addPass("d", "L0", "t", {"X"}, {"D"}, {}, [&] { ++fresh["d"]; });
        g.addPass("b", "L0", "t", {"src.b"}, {}, {"X"}, [&] { ++fresh["b"]; });
        g.addPass("c", "L0", "t", {"X"}, {"C"}, {}, [&] { ++fresh["c"]; });
        g.execute({"X"}, 0, timer);
        EXPECT_EQ(fresh, (std::map<std::string, int>{{"a", 1}, {"b", 1}}));
        // Declaring a read of something nobody produces is an error.
        EXPECT_THROW(g.addPass("e", "L0", "t", {"nothing"}, {"E"}, {}, [] {}), InternalError);
        EXPECT_THROW(g.addPass("f", "L0", "t", {}, {}, {"src.a"}, [] {}), InternalError);
        EXPECT_THROW(g.addPass("h", "L0", "t", {}, {"X"}, {}, [] {}), InternalError);
    }

    // History and times stay bounded over a long session.
    for (int f = 5; f < 205; ++f) {
        if (f % 3 == 0) graph.setSource("src.a", uint64_t(f));
        graph.execute({"C", "D"}, f, timer);
    }
    graph.measureCost({"C", "D"}, 205, timer);
    for (const PassRecord& r : graph.records()) {
        EXPECT_LE(r.history.size(), PassRecord::kKeptFrames) << r.name;
        EXPECT_LE(r.history.size(), 64u) << r.name;
        EXPECT_LE(r.times.size(), PassRecord::kKeptTimes) << r.name;
    }
}

// ==== 8. parameter tables: enum, odd, power of two, step, conditions, validation =======================
TechniqueDesc toyTechnique() {
    using T = ParamDesc::Type;
    TechniqueDesc d;
    d.id = "toy";
    d.name = "Toy";
    d.citation = "test";
    ParamDesc filter{"filter", "", T::Enum, "", 0, 0, 1, 0, "blur kernel", ""};
    filter.choices = {"gaussian", "mean"};
    ParamDesc n{"n", "n", T::Int, "texels", 5, 1, 15, 1, "kernel width, odd", ""};
    n.constraint = ParamDesc::Constraint::Odd;
    ParamDesc size{"size", "", T::Int, "texels", 256, 1, 4096, 1, "a power-of-two size", ""};
    size.constraint = ParamDesc::Constraint::PowerOfTwo;
    ParamDesc k{"k", "", T::Int, "", 3, 1, 21, 2, "steps of 2 from 1", ""};
    ParamDesc sigma{"sigma", "", T::Float, "", 1.0, 0.1, 10, 0.1, "gaussian width", "filter == gaussian"};
    d.params = {filter, n, size, k, sigma};
    PassDesc blur;
    blur.name = "blur";
    blur.doc = "the toy pass";
    blur.reads = {"gbuffer", "param:filter", "param:n", "param:size", "param:k", "param:sigma"};
    blur.creates = {visibilityResource()};
    blur.create = [] { return std::unique_ptr<Pass>(); };
    d.passes = {blur};
    InternalDesc vis;
    vis.name = "vis";
    vis.resource = "visibility";
    vis.doc = "the toy's visibility";
    vis.appliesWhen = "n >= 3";
    d.internals = {vis};
    return d;
}

template <class F>
std::string inputErrorText(F f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

TEST(Stage2ParamTable, EnumOddPowerOfTwoStep) {
    TechniqueDesc d = toyTechnique();
    ParamValues v(d);
    EXPECT_EQ(v.getChoice("filter"), "gaussian");
    EXPECT_EQ(v.get("filter"), 0.0);
    v.set(d, "filter", "mean", "--set");
    EXPECT_EQ(v.getChoice("filter"), "mean");
    EXPECT_EQ(v.get("filter"), 1.0);
    std::string message = inputErrorText([&] { v.set(d, "filter", "box", "--set filter=box"); });
    EXPECT_NE(message.find("gaussian"), std::string::npos) << message;
    EXPECT_NE(message.find("mean"), std::string::npos) << message;
    EXPECT_NE(message.find("box"), std::string::npos) << message;
    EXPECT_NE(message.find("--set filter=box"), std::string::npos) << message;
    EXPECT_EQ(v.getChoice("filter"), "mean") << "a refused value leaves the old one";
    EXPECT_THROW(v.set(d, "filter", "1", "--set"), InputError) << "enums take names, not indices";
    EXPECT_THROW(v.getChoice("n"), InternalError);
    EXPECT_EQ(v.toJson(d)["filter"], "mean");

    // Odd.
    for (const char* even : {"2", "4", "14"}) {
        std::string m = inputErrorText([&] { v.set(d, "n", even, "--set"); });
        EXPECT_NE(m.find("odd"), std::string::npos) << even << ": " << m;
    }
    v.set(d, "n", "7", "--set");
    EXPECT_EQ(v.getInt("n"), 7);
    EXPECT_THROW(v.set(d, "n", "17", "--set"), InputError);

    // Power of two.
    for (const char* bad : {"3", "96", "4095"}) {
        std::string m = inputErrorText([&] { v.set(d, "size", bad, "--set"); });
        EXPECT_NE(m.find("power of two"), std::string::npos) << bad << ": " << m;
    }
    for (const char* good : {"1", "2", "128", "4096"}) EXPECT_NO_THROW(v.set(d, "size", good, "--set")) << good;
    EXPECT_THROW(v.set(d, "size", "8192", "--set"), InputError);
    EXPECT_THROW(v.set(d, "size", "0", "--set"), InputError);

    // Step 2 from 1: 1, 3, 5, ...
    for (const char* good : {"1", "3", "21"}) EXPECT_NO_THROW(v.set(d, "k", good, "--set")) << good;
    for (const char* bad : {"2", "4", "20"}) {
        std::string m = inputErrorText([&] { v.set(d, "k", bad, "--set"); });
        EXPECT_NE(m.find("steps of 2"), std::string::npos) << bad << ": " << m;
    }
    EXPECT_THROW(v.set(d, "k", "2.5", "--set"), InputError);
    EXPECT_EQ(validateTechnique(d), std::vector<std::string>{});
}

TEST(Stage2ParamTable, Conditions) {
    TechniqueDesc d = toyTechnique();
    Condition c("filter == gaussian && n > 3", d, "test");
    EXPECT_FALSE(c.always());
    ParamValues v(d);  // gaussian, n = 5
    EXPECT_TRUE(c.holds(v));
    v.set(d, "n", "3", "--set");
    EXPECT_FALSE(c.holds(v));
    v.set(d, "n", "9", "--set");
    EXPECT_TRUE(c.holds(v));
    v.set(d, "filter", "mean", "--set");
    EXPECT_FALSE(c.holds(v));
    EXPECT_TRUE(Condition("filter != gaussian", d, "test").holds(v));
    EXPECT_TRUE(Condition("n <= 9 && n >= 9 && size == 256", d, "test").holds(v));
    EXPECT_TRUE(Condition().always());
    EXPECT_TRUE(Condition().holds(v));

    for (const char* bad : {"filter gaussian", "nope == 1", "filter == box", "n > three", "n >", "== 3",
                            "filter == gaussian || n > 3"}) {
        EXPECT_THROW(Condition(bad, d, "test"), InternalError) << bad;
    }
    try {
        Condition("nope == 1", d, "toy.where");
    } catch (const InternalError& e) {
        EXPECT_NE(std::string(e.what()).find("toy.where"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos) << e.what();
    }

    // sigma applies only to the gaussian filter.
    ParamValues g(d);
    EXPECT_TRUE(g.inapplicable(d).empty());
    auto out = v.inapplicable(d);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].first, "sigma");
    EXPECT_NE(out[0].second.find("filter == gaussian"), std::string::npos) << out[0].second;
}

TEST(Stage2ParamTable, ValidateTechniqueFindsBrokenDescriptors) {
    for (const TechniqueDesc* d : allTechniques()) EXPECT_EQ(validateTechnique(*d), std::vector<std::string>{}) << d->id;
    EXPECT_EQ(validateTechnique(toyTechnique()), std::vector<std::string>{});

    auto expectProblem = [](const TechniqueDesc& d, const std::string& mention, const std::string& what) {
        std::vector<std::string> problems = validateTechnique(d);
        bool found = false;
        std::string all;
        for (const std::string& p : problems) {
            found |= p.find(mention) != std::string::npos;
            all += "\n  " + p;
        }
        EXPECT_TRUE(found) << what << ": no problem mentions '" << mention << "'; problems:" << all;
    };
    {
        TechniqueDesc d = toyTechnique();
        d.passes[0].reads.push_back("unproduced");
        expectProblem(d, "unproduced", "pass reading an unproduced resource");
    }
    {
        TechniqueDesc d = toyTechnique();
        d.internals[0].resource = "ghost";
        expectProblem(d, "ghost", "internal naming an unknown resource");
    }
    {
        TechniqueDesc d = toyTechnique();
        d.params[1].defaultValue = 4;  // n is Odd
        expectProblem(d, "even default", "even default of an Odd parameter");
    }
    {
        TechniqueDesc d = toyTechnique();
        d.params[2].defaultValue = 100;  // size is PowerOfTwo
        expectProblem(d, "power of two", "default not a power of two");
    }
    {
        TechniqueDesc d = toyTechnique();
        d.params[4].appliesWhen = "filter == box";
        expectProblem(d, "box", "condition naming an unknown choice");
    }
    {
        TechniqueDesc d = toyTechnique();
        d.passes[0].reads.push_back("param:nope");
        expectProblem(d, "param:nope", "pass reading an unknown parameter");
    }
    {
        TechniqueDesc d = toyTechnique();
        d.passes[0].creates[0].name = "not_visibility";
        expectProblem(d, "visibility", "no pass creates visibility");
    }
    {
        TechniqueDesc d = toyTechnique();
        d.params[0].defaultValue = 2;  // enum with two choices
        expectProblem(d, "filter", "enum default outside its choices");
    }
}

}  // namespace
}  // namespace shadowlab
