// The command line end to end (DESIGN.md section 6): outputs, stats, determinism, and bad input —
// exit code 2, a message naming the file/field/flag and what was expected, and no output file.
#include <gtest/gtest.h>

#include <chrono>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "image/image.h"
#include "scene/scene.h"
#include "support/cli_run.h"
#include "support/real_meshes.h"

namespace fs = std::filesystem;

namespace {

using shadowlab::test::Result;
using shadowlab::test::run;

std::string tmp(const std::string& name) { return shadowlab::test::testPath("cli", name); }

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string writeFile(const std::string& name, const std::string& text) {
    std::string path = tmp(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

// Every bad input: exit code 2, the message mentions each of `mentions`, and `output` not written.
void expectBadInput(const std::string& arguments, const std::vector<std::string>& mentions,
                    const std::string& output = "") {
    if (!output.empty()) fs::remove(output);
    Result r = run(arguments);
    EXPECT_EQ(r.code, 2) << arguments << "\n" << r.output;
    for (const std::string& m : mentions) EXPECT_NE(r.output.find(m), std::string::npos) << "'" << m << "' not in: " << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    if (!output.empty()) {
        EXPECT_FALSE(fs::exists(output)) << "partial output " << output;
        for (const auto& entry : fs::directory_iterator(fs::path(output).parent_path()))
            EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
    }
}

const std::string kRender = "render --scene square-occluder --size 32x32 ";

TEST(Cli, RenderWritesEveryOutput) {
    std::string png = tmp("r.png"), vis = tmp("r.pfm"), pos = tmp("p.pfm"), ids = tmp("i.pfm"), stats = tmp("s.json");
    Result r = run(kRender + "--technique pcf --out " + png + " --visibility " + vis + " --positions " + pos +
                   " --ids " + ids + " --stats " + stats);
    ASSERT_EQ(r.code, 0) << r.output;
    shadowlab::Image v = shadowlab::readPFM(vis);
    EXPECT_EQ(v.width, 32);
    EXPECT_EQ(v.channels, 1);
    EXPECT_EQ(shadowlab::readPFM(pos).channels, 3);
    shadowlab::Image id = shadowlab::readPFM(ids);
    EXPECT_EQ(id.channels, 1);
    EXPECT_EQ(readFile(png).substr(1, 3), "PNG");
    nlohmann::json s = nlohmann::json::parse(readFile(stats));
    for (const char* key : {"frame_ms", "cost_ms", "shadow_ms", "fixed_ms"}) EXPECT_TRUE(s.contains(key)) << key;
    EXPECT_EQ(s["clock"], "cpu-finish");  // llvmpipe: timer queries time one tile
    EXPECT_FALSE(s["passes"].empty());
    EXPECT_GT(s["memory_bytes"].get<double>(), 0.0);
}

TEST(Cli, StatsShowShadowMapRenderedOnceOverThreeFrames) {
    std::string stats = tmp("frames.json");
    Result r = run(kRender + "--technique hard --frames 3 --stats " + stats);
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json s = nlohmann::json::parse(readFile(stats));
    EXPECT_EQ(s["frames"], 3);
    bool found = false;
    for (const auto& p : s["passes"]) {
        if (p["name"] != "L0/hard/shadow_map") continue;
        found = true;
        EXPECT_EQ(p["runs"], 1);
        EXPECT_EQ(p["reuses"], 3);  // the warm-up frame rendered it; three timed frames reused it
        EXPECT_NE(p["reason"].get<std::string>().find("unchanged"), std::string::npos);
    }
    EXPECT_TRUE(found);
}

TEST(Cli, NoReuseRunsEveryPassEveryFrame) {
    std::string stats = tmp("no-reuse.json");
    Result r = run(kRender + "--technique pcf --frames 3 --no-reuse --stats " + stats);
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json s = nlohmann::json::parse(readFile(stats));
    EXPECT_EQ(s["reuse"], false);
    for (const auto& p : s["passes"]) {
        EXPECT_EQ(p["runs"], 4) << p.dump();
        EXPECT_EQ(p["reuses"], 0) << p.dump();
    }
}

TEST(Cli, SameCommandTwiceIsBitIdentical) {
    for (const char* t : {"pcf", "reference --set samples=16", "raytraced --set rays=16"}) {
        std::string a = tmp("det-a.pfm"), b = tmp("det-b.pfm");
        ASSERT_EQ(run(kRender + "--technique " + t + " --visibility " + a).code, 0);
        ASSERT_EQ(run(kRender + "--technique " + t + " --visibility " + b).code, 0);
        EXPECT_EQ(readFile(a), readFile(b)) << t;
    }
}

TEST(Cli, OSMesaRendersLikeEgl) {
    std::string a = tmp("egl.pfm"), b = tmp("osmesa.pfm");
    ASSERT_EQ(run(kRender + "--technique pcf --visibility " + a).code, 0);
    Result r = run(kRender + "--technique pcf --gl osmesa --visibility " + b);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(readFile(a), readFile(b));
}

TEST(Cli, ReferenceCommandAndCompare) {
    std::string ref = tmp("ref.pfm"), ray = tmp("ray.pfm"), heat = tmp("heat.png");
    ASSERT_EQ(run("reference --scene square-occluder --size 48x48 --samples 64 --out " + ref).code, 0);
    ASSERT_EQ(run("reference --scene square-occluder --size 48x48 --rays 64 --out " + ray).code, 0);
    Result c = run("compare " + ref + " " + ray + " --json --heatmap " + heat);
    ASSERT_EQ(c.code, 0) << c.output;
    nlohmann::json j = nlohmann::json::parse(c.output);
    EXPECT_LT(j["all"]["rmse"].get<double>(), 0.05);
    EXPECT_GT(j["penumbra"]["pixels"].get<int>(), 0);
    EXPECT_TRUE(fs::exists(heat));
    Result p = run("compare " + ref + " " + ray + " --mask penumbra --json");
    ASSERT_EQ(p.code, 0);
    nlohmann::json pj = nlohmann::json::parse(p.output);
    EXPECT_EQ(pj["pixels"], j["penumbra"]["pixels"]);
}

TEST(Cli, ListJsonDescribesTechniquesAndScenes) {
    Result r = run("list --json");
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json j = nlohmann::json::parse(r.output);
    std::set<std::string> ids;
    for (const auto& t : j["techniques"]) {
        ids.insert(t["id"]);
        for (const auto& p : t["parameters"]) {
            EXPECT_FALSE(p["doc"].get<std::string>().empty());
            if (p["type"] == "enum") {  // the default is a choice's name
                EXPECT_NE(std::find(p["choices"].begin(), p["choices"].end(), p["default"]), p["choices"].end());
                continue;
            }
            EXPECT_GE(p["default"].get<double>(), p["min"].get<double>());
            EXPECT_LE(p["default"].get<double>(), p["max"].get<double>());
        }
    }
    EXPECT_EQ(ids, (std::set<std::string>{"hard", "pcf", "pcss", "sssm", "ssm-gbp06", "ssm-contour", "ssv", "pvm", "pvmf", "spsm", "auto",
                                    "reference", "raytraced"}));
    EXPECT_GE(j["scenes"].size(), 9u);
    for (const auto& s : j["scenes"])  // a real-mesh scene whose glTF was not fetched fails to load, and says so
        EXPECT_EQ(s.contains("error"), !shadowlab::testing::sceneCanLoad(s["name"])) << s.dump();
    EXPECT_EQ(run("list").code, 0);
}

TEST(Cli, SceneDumpTriangles) {
    std::string obj = tmp("scene.obj");
    ASSERT_EQ(run("scene --scene square-occluder --dump-triangles " + obj).code, 0);
    std::string text = readFile(obj);
    size_t faces = 0;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) faces += line.rfind("f ", 0) == 0;
    EXPECT_EQ(faces, 2u + 12u);  // floor quad + closed box
}

TEST(Cli, InternalsAndPixel) {
    std::string dir = tmp("internals");
    fs::remove_all(dir);
    Result r = run(kRender + "--technique hard --internals " + dir + " --pixel 16,16");
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json index = nlohmann::json::parse(readFile(dir + "/index.json"));
    std::set<std::string> names;
    for (const auto& f : index["files"]) {
        names.insert(f["name"]);
        EXPECT_TRUE(fs::exists(dir + "/" + f["file"].get<std::string>())) << f.dump();
        EXPECT_FALSE(f["description"].get<std::string>().empty());
    }
    EXPECT_TRUE(names.count("shadow_map"));
    EXPECT_TRUE(names.count("pixel"));
    nlohmann::json pixel = nlohmann::json::parse(readFile(dir + "/pixel.json"));
    EXPECT_EQ(pixel["pixel"], nlohmann::json({16, 16}));
    // The light looks straight down from y = 4: the receiver's light-view depth is 4 - y.
    ASSERT_TRUE(pixel["position"].is_array()) << pixel.dump();
    EXPECT_NEAR(pixel["lights"][0]["receiver_depth"].get<double>(), 4.0 - pixel["position"][1].get<double>(), 1e-4);
}

// ---- bad input: each its own test -------------------------------------------------------------------
TEST(CliBadInput, MissingSceneFile) {
    expectBadInput("render --scene /nonexistent/nope.json --out " + tmp("x.png"), {"/nonexistent/nope.json"}, tmp("x.png"));
    expectBadInput("render --scene no-such-scene", {"no-such-scene"});
}

TEST(CliBadInput, MalformedJsonNamesLineAndColumn) {
    std::string path = writeFile("malformed.json", "{\n  \"camera\": {\n    \"fov_deg\": 45,,\n  }\n}\n");
    expectBadInput("render --scene " + path + " --out " + tmp("x.png"), {"malformed.json:3:", "malformed JSON"}, tmp("x.png"));
}

TEST(CliBadInput, UnknownSceneField) {
    std::string path = writeFile("unknown-field.json", R"({"lights": [], "objects": [], "colour": 1})");
    expectBadInput("render --scene " + path, {"unknown-field.json", "colour"});
}

TEST(CliBadInput, UnknownTechnique) {
    expectBadInput(kRender + "--technique pcss-typo --out " + tmp("x.png"), {"--technique", "pcss-typo", "pcf"}, tmp("x.png"));
}

TEST(CliBadInput, UnknownSetKey) {
    expectBadInput(kRender + "--technique pcf --set kernel=3 --out " + tmp("x.png"), {"kernel", "pcf_kernel"}, tmp("x.png"));
}

TEST(CliBadInput, OutOfRangeAndNaNParameterValues) {
    expectBadInput(kRender + "--technique pcf --set pcf_kernel=1000 --out " + tmp("x.png"), {"pcf_kernel", "[1, 63]"}, tmp("x.png"));
    expectBadInput(kRender + "--technique pcf --set sm_size=nan --out " + tmp("x.png"), {"sm_size", "finite"}, tmp("x.png"));
    expectBadInput(kRender + "--technique pcf --set sm_size=0 --out " + tmp("x.png"), {"sm_size"}, tmp("x.png"));
    expectBadInput(kRender + "--technique pcf --set pcf_kernel=2.5", {"pcf_kernel", "whole number"});
    expectBadInput(kRender + "--light-size nan", {"--light-size"});
    expectBadInput(kRender + "--light-size -1", {"--light-size"});
}

TEST(CliBadInput, NaNInSceneFile) {
    std::string path = writeFile("nan.json", "{\n  \"ambient\": NaN,\n  \"lights\": [], \"objects\": []\n}\n");
    expectBadInput("render --scene " + path, {"nan.json:2:"});
    std::string inf = writeFile("inf.json", R"({"ambient": 1e999, "lights": [], "objects": []})");
    expectBadInput("render --scene " + inf, {"inf.json", "ambient"});
}

TEST(CliBadInput, GltfThatFailsToParse) {
    writeFile("broken.gltf", "{ this is not glTF");
    std::string path = writeFile("uses-broken-gltf.json",
                                 R"({"camera": {"position": [0, 5, 5], "target": [0, 0, 0]},
                                     "lights": [{"type": "point", "position": [0, 4, 0]}],
                                     "objects": [{"name": "m", "type": "gltf", "file": "broken.gltf"}]})");
    expectBadInput("render --scene " + path + " --out " + tmp("x.png"), {"broken.gltf"}, tmp("x.png"));
}

TEST(CliBadInput, ZeroOrAbsurdSize) {
    expectBadInput("render --scene square-occluder --size 0x0 --out " + tmp("x.png"), {"--size", "1..8192"}, tmp("x.png"));
    expectBadInput("render --scene square-occluder --size 100000x100000", {"--size"});
    expectBadInput("render --scene square-occluder --size 64", {"--size", "WxH"});
    expectBadInput("render --scene square-occluder --size -5x10", {"--size"});
}

TEST(CliBadInput, UnknownCommandAndOptions) {
    expectBadInput("rendr --scene square-occluder", {"rendr"});
    expectBadInput("render --scene square-occluder --sise 64x64", {"--sise"});
    expectBadInput("render --scene square-occluder --out " + tmp("x.jpg"), {"--out", ".png"});
    expectBadInput("render --scene square-occluder --out /nonexistent-dir/x.png", {"--out", "/nonexistent-dir"});
    expectBadInput("render --scene square-occluder --frames 0", {"--frames"});
    expectBadInput("render --scene square-occluder --pixel 99999,0", {"--pixel"});
}

// Issue 24: a valued flag followed by another option has no value (it used to swallow the option
// and call the option's own value an unexpected argument), and --pixel's numbers are read without
// wrapping (99999999999 was reported as 1215752191).
TEST(CliBadInput, AValuedFlagWithoutItsValueAndAPixelPastAnInt) {
    expectBadInput("render --scene square-occluder --set --out " + tmp("swallow.png"),
                   {"render: --set expects a value, got the option --out"}, tmp("swallow.png"));
    expectBadInput("render --scene square-occluder --size --stats " + tmp("s.json"), {"--size expects a value, got the option --stats"},
                   tmp("s.json"));
    expectBadInput("render --scene square-occluder --pixel 99999999999,1", {"got '99999999999,1'"});
    expectBadInput("render --scene square-occluder --pixel 3,-1", {"got '3,-1'"});
    expectBadInput("render --scene square-occluder --pixel 3,4,5", {"got '3,4,5'"});
}

// Issue 24: every reader's file comes through one gate (scene/input_file.h). A folder, a FIFO and
// /dev/zero in each input position are refused at once with exit 2 naming the path; before, a FIFO
// blocked forever, /dev/zero grew without bound, and a folder was "the file is empty" or
// "basic_filebuf::underflow" (exit 1).
TEST(CliBadInput, EveryReaderRefusesAFolderAFifoAndADevice) {
    const std::string good = tmp("good.pfm"), folder = tmp("a-folder"), fifo = tmp("a-fifo");
    ASSERT_EQ(run("render --scene square-occluder --size 8x8 --visibility " + good).code, 0);
    fs::create_directories(folder);
    fs::remove(fifo);
    ASSERT_EQ(std::system(("mkfifo " + fifo).c_str()), 0);
    const std::vector<std::pair<std::string, std::string>> commands = {
        {"compare BAD " + good, "PFM file"},
        {"compare " + good + " BAD", "PFM file"},
        {"bench --spec BAD", "bench spec"},
        {"figure --spec BAD --out " + tmp("fig.png"), "figure spec"},
        {"figure --remake BAD", "figure sidecar"},
        {"lesson BAD --headless --out " + tmp("handout"), "lesson file"},
    };
    for (const std::string& bad : {folder, fifo, std::string("/dev/zero")})
        for (const auto& [pattern, what] : commands) {
            std::string command = pattern;
            command.replace(command.find("BAD"), 3, bad);
            SCOPED_TRACE(command);
            const auto t0 = std::chrono::steady_clock::now();
            expectBadInput(command, {bad + ": cannot read the " + what + ": it is "});
            EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
        }
    EXPECT_FALSE(fs::exists(tmp("handout")));
    fs::remove(fifo);
}

TEST(CliBadInput, CompareFiles) {
    std::string a = tmp("cmp-a.pfm"), b = tmp("cmp-b.pfm");
    ASSERT_EQ(run("render --scene square-occluder --size 16x16 --visibility " + a).code, 0);
    ASSERT_EQ(run("render --scene square-occluder --size 16x32 --visibility " + b).code, 0);
    expectBadInput("compare " + a + " " + b, {"differ in size", "16x16", "16x32"});
    expectBadInput("compare " + a + " " + tmp("missing.pfm"), {"missing.pfm"});
    std::string junk = writeFile("junk.pfm", "P6\n1 1\n255\nabc");
    expectBadInput("compare " + a + " " + junk, {"junk.pfm"});
    expectBadInput("compare " + a + " " + a + " --mask umbra", {"--mask", "penumbra"});
}

// The window opens under a virtual X server, renders and takes a screenshot that is not blank.
TEST(Window, ScreenshotUnderXvfb) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run is not installed";
    std::string shot = tmp("window.png");
    fs::remove(shot);
    std::string command = "xvfb-run -a -s '-screen 0 640x480x24' " + std::string(SHADOWLAB_BINARY) +
                          " window --scene square-occluder --technique pcf --size 256x256 --screenshot " + shot +
                          " --frames 3 2>&1";
    int status = std::system(command.c_str());
    ASSERT_EQ(WEXITSTATUS(status), 0);
    ASSERT_TRUE(fs::exists(shot));
    EXPECT_GT(fs::file_size(shot), 1000u);  // a uniform image compresses to a few hundred bytes
}

}  // namespace

namespace {

// Papercuts of issue 18: every command opens a glTF file as the window does (a scene around the
// model), and `list` names an enum's choices.
TEST(CliPapercuts, RenderOpensAGltfFileAsTheWindowDoes) {
    const std::string out = shadowlab::test::testPath("cli", "torus.pfm");
    fs::remove(out);
    shadowlab::test::Result r =
        shadowlab::test::run("render --scene " + shadowlab::projectRoot() + "/assets/models/torus.gltf --size 48x48 --visibility " + out);
    ASSERT_EQ(r.code, 0) << r.output;
    const shadowlab::Image v = shadowlab::readPFM(out);
    size_t shadowed = 0;
    for (float x : v.data) shadowed += x < 0.5f;
    EXPECT_GT(shadowed, 10u) << "the torus casts a shadow on the ground";
    EXPECT_EQ(shadowlab::test::run("render --scene missing.gltf --size 16x16").code, 2);
}

TEST(CliPapercuts, ListNamesEnumChoices) {
    shadowlab::test::Result r = shadowlab::test::run("list");
    ASSERT_EQ(r.code, 0);
    EXPECT_NE(r.output.find("choices regular | poisson"), std::string::npos) << r.output.substr(0, 2000);
    EXPECT_NE(r.output.find("choices gaussian | mean"), std::string::npos);
}

}  // namespace
