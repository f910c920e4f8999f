// Provenance sidecars of float buffers (DESIGN.md section 6): every PFM gets "<file>.pfm.json";
// `compare` warns when the two sides' scene, lights or size differ and `--strict` refuses.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "error.h"
#include "image/provenance.h"
#include "support/cli_run.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace shadowlab {
namespace {

using test::Result;
using test::run;

std::string tmp(const std::string& name) { return test::testPath("provenance", name); }

json readJson(const std::string& path) {
    std::ifstream in(path);
    return json::parse(in);
}

const std::string kScene = "--scene square-occluder --size 32x32 ";

// A pcf render (A) at --light-size `lightSize` ("" = the scene's) and a 16-sample reference (B).
void renderPair(const std::string& a, const std::string& b, const std::string& lightSize) {
    const std::string size = lightSize.empty() ? "" : " --light-size " + lightSize;
    Result r = run("render " + kScene + "--technique pcf --visibility " + a + size);
    ASSERT_EQ(r.code, 0) << r.output;
    r = run("reference " + kScene + "--samples 16 --out " + b);
    ASSERT_EQ(r.code, 0) << r.output;
}

TEST(Provenance, RenderWritesSidecarsWithTheRenderedLights) {
    const std::string vis = tmp("v.pfm"), pos = tmp("p.pfm"), ids = tmp("i.pfm");
    Result r = run("render " + kScene + "--technique pcf --set pcf_kernel=3 --light-size 0.5 " +
                   "--visibility " + vis + " --positions " + pos + " --ids " + ids);
    ASSERT_EQ(r.code, 0) << r.output;
    for (const auto& [path, meaning] : {std::pair<std::string, std::string>{vis, "visibility"},
                                        {pos, "positions"},
                                        {ids, "ids"}}) {
        ASSERT_TRUE(fs::exists(path + ".json")) << path;
        const json s = readJson(path + ".json");
        EXPECT_EQ(s["buffer"], meaning);
        EXPECT_EQ(s["scene"]["name"], "square-occluder");
        EXPECT_EQ(s["size"]["width"], 32);
        EXPECT_EQ(s["size"]["height"], 32);
        ASSERT_EQ(s["lights"].size(), 1u);
        const json& light = s["lights"][0];
        EXPECT_EQ(light["size"], 0.5);  // after --light-size, not the scene's 1
        EXPECT_EQ(light["shape"], "square");
        EXPECT_EQ(light["technique"], "pcf");
        EXPECT_EQ(light["parameters"]["pcf_kernel"], 3.0);
        EXPECT_EQ(light["casts_shadows"], true);
        EXPECT_EQ(light["position"], json::array({0.0, 4.0, 0.0}));
        EXPECT_GT(s["frame_ms"].get<double>(), 0.0);
        EXPECT_EQ(s["clock"], "cpu-finish");
        EXPECT_EQ(s["program"]["version"], programVersion());
        EXPECT_FALSE(s["gl_renderer"].get<std::string>().empty());
        EXPECT_EQ(s["command_line"][1], "render");
    }
    // --light-size 0 makes a point light: the sidecar says so, and names what ran (hard).
    r = run("render " + kScene + "--technique pcf --light-size 0 --visibility " + vis);
    ASSERT_EQ(r.code, 0) << r.output;
    const json point = readJson(vis + ".json")["lights"][0];
    EXPECT_EQ(point["shape"], "point");
    EXPECT_EQ(point["size"], 0.0);
    EXPECT_EQ(point["technique"], "hard");
}

TEST(Provenance, ReferenceWritesASidecar) {
    const std::string out = tmp("ref.pfm");
    Result r = run("reference " + kScene + "--samples 16 --out " + out);
    ASSERT_EQ(r.code, 0) << r.output;
    const json s = readJson(out + ".json");
    EXPECT_EQ(s["buffer"], "reference");
    EXPECT_EQ(s["lights"][0]["technique"], "reference");
    EXPECT_EQ(s["lights"][0]["parameters"]["samples"], 16.0);
    EXPECT_EQ(s["lights"][0]["size"], 1.0);
}

TEST(Provenance, CompareWarnsWhenTheLightSizeDiffers) {
    const std::string a = tmp("a.pfm"), b = tmp("b.pfm");
    renderPair(a, b, "0.5");
    Result r = run("compare " + a + " " + b);
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("warning"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("light 0 \"key\": size 0.5 vs 1"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("RMSE"), std::string::npos) << r.output;  // and the metrics follow
    // The technique differs too (pcf vs reference): that is what compare is for, never a warning.
    EXPECT_EQ(r.output.find("technique pcf"), std::string::npos) << r.output;

    r = run("compare " + a + " " + b + " --strict");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("--strict"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("light 0 \"key\": size 0.5 vs 1"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("RMSE"), std::string::npos) << r.output;

    r = run("compare " + a + " " + b + " --json");
    ASSERT_EQ(r.code, 0) << r.output;
    const json j = json::parse(r.output.substr(r.output.find("\n{") + 1));
    EXPECT_EQ(j["provenance"]["differences"].size(), 1u);
    EXPECT_EQ(j["provenance"]["technique_differences"][0],
              "light 0 \"key\": technique pcf vs reference");
}

TEST(Provenance, CompareOfTheSameSettingsIsQuiet) {
    const std::string a = tmp("a.pfm"), b = tmp("b.pfm");
    renderPair(a, b, "");
    for (const std::string flags : {"", " --strict"}) {
        Result r = run("compare " + a + " " + b + flags);
        EXPECT_EQ(r.code, 0) << r.output;
        EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("RMSE"), std::string::npos) << r.output;
    }
}

TEST(Provenance, StrictRefusesWhenASidecarIsMissing) {
    const std::string a = tmp("a.pfm"), b = tmp("b.pfm");
    renderPair(a, b, "");
    fs::remove(b + ".json");
    Result r = run("compare " + a + " " + b);
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
    r = run("compare " + a + " " + b + " --strict");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(b + " has no provenance sidecar (" + b + ".json)"), std::string::npos)
        << r.output;
}

TEST(Provenance, MalformedSidecarNamesTheFile) {
    const std::string a = tmp("a.pfm"), b = tmp("b.pfm");
    renderPair(a, b, "");
    std::ofstream(b + ".json", std::ios::trunc) << "{\n  \"scene\": {\"name\": \"x\"},,\n}\n";
    Result r = run("compare " + a + " " + b);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(b + ".json:2:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("malformed JSON"), std::string::npos) << r.output;
    // Valid JSON, but not a provenance record.
    std::ofstream(b + ".json", std::ios::trunc) << "{\"scene\": {}, \"size\": {}, \"lights\": 3}";
    r = run("compare " + a + " " + b);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(b + ".json:1: lights: expected an array, got 3"), std::string::npos)
        << r.output;
}

TEST(Provenance, FailedRenderLeavesNoSidecar) {
    const std::string vis = tmp("v.pfm");
    fs::remove(vis);
    fs::remove(vis + ".json");
    Result r = run("render " + kScene + "--technique pcf --set no_such_key=1 --visibility " + vis);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_FALSE(fs::exists(vis));
    EXPECT_FALSE(fs::exists(vis + ".json"));
    for (const auto& entry : fs::directory_iterator(fs::path(vis).parent_path()))
        EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

// The library side, without the program.
RenderProvenance record(float lightSize, const std::string& technique) {
    RenderProvenance p;
    p.sceneName = "s";
    p.scenePath = "s.json";
    Light light;
    light.name = "key";
    light.size = lightSize;
    p.lights.push_back({light, technique, {{"k", 1.0}}});
    p.width = 8;
    p.height = 8;
    return p;
}

TEST(Provenance, DifferencesListEachSettingWithBothValues) {
    const json a = provenanceOf(record(0.5f, "pcf"), "visibility");
    json b = provenanceOf(record(1.0f, "reference"), "reference");
    EXPECT_EQ(provenanceDifferences(a, a), std::vector<std::string>{});
    EXPECT_EQ(provenanceDifferences(a, b),
              std::vector<std::string>{"light 0 \"key\": size 0.5 vs 1"});
    EXPECT_EQ(techniqueDifferences(a, b),
              std::vector<std::string>{"light 0 \"key\": technique pcf vs reference"});
    b["scene"]["name"] = "t";
    b["size"]["width"] = 16;
    b["lights"][0]["position"] = json::array({0.0, 5.0, 0.0});
    b["lights"].push_back(b["lights"][0]);
    const std::vector<std::string> d = provenanceDifferences(a, b);
    ASSERT_EQ(d.size(), 5u);
    EXPECT_EQ(d[0], "scene: s (s.json) vs t (s.json)");
    EXPECT_EQ(d[1], "size: 8x8 vs 16x8");
    EXPECT_EQ(d[2], "lights: 1 vs 2 lights");
    EXPECT_EQ(d[3], "light 0 \"key\": position [0, 4, 0] vs [0, 5, 0]");
    EXPECT_EQ(d[4], "light 0 \"key\": size 0.5 vs 1");
    // Same technique, other parameter values: information only.
    json c = a;
    c["lights"][0]["parameters"]["k"] = 2.0;
    EXPECT_EQ(techniqueDifferences(a, c), std::vector<std::string>{"light 0 \"key\": k 1 vs 2"});
    EXPECT_TRUE(provenanceDifferences(a, c).empty());
}

TEST(Provenance, SidecarIsStagedWithThePfm) {
    const std::string path = tmp("staged.pfm");
    fs::remove(path);
    fs::remove(sidecarPath(path));
    const json provenance = provenanceOf(record(1.0f, "hard"), "visibility");
    {
        OutputSet outputs;  // destroyed without commit(): a failed command
        writePfmWithSidecar(outputs, path, Image(2, 2, 1, 0.5f), provenance);
    }
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(sidecarPath(path)));
    EXPECT_FALSE(readSidecar(path).has_value());
    OutputSet outputs;
    writePfmWithSidecar(outputs, path, Image(2, 2, 1, 0.5f), provenance);
    outputs.commit();
    EXPECT_EQ(sidecarPath(path), path + ".json");
    EXPECT_EQ(readSidecar(path), provenance);
}

}  // namespace
}  // namespace shadowlab
