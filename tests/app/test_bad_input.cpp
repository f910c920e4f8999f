// Bad input, round two (issue 24), end to end through the binary: every reader behind one input
// gate, every output set planned and committed all-or-nothing, every number checked in its type,
// comparisons with nothing in common refused. Each answer is exit code 2 with a message naming
// the input (file, line or field, or flag) and what was expected, and nothing written.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "image/image.h"
#include "scene/scene.h"
#include "support/cli_run.h"

namespace fs = std::filesystem;

namespace {

using shadowlab::test::Result;
using shadowlab::test::run;

std::string tmp(const std::string& name) { return shadowlab::test::testPath("bad-input", name); }

std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = tmp(name);
    fs::create_directories(fs::path(path).parent_path());
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Exit 2, each of `mentions` in the message, no "internal error", none of `unwritten` on disk and
// no staged temporary left beside them.
void expectRefused(const std::string& arguments, const std::vector<std::string>& mentions,
                   const std::vector<std::string>& unwritten = {}) {
    SCOPED_TRACE(arguments);
    for (const std::string& path : unwritten) {
        std::error_code ec;
        if (!fs::is_directory(path, ec)) fs::remove(path, ec);
    }
    const Result r = run(arguments);
    EXPECT_EQ(r.code, 2) << r.output;
    for (const std::string& m : mentions) EXPECT_TRUE(contains(r.output, m)) << "'" << m << "' not in: " << r.output;
    EXPECT_FALSE(contains(r.output, "internal error")) << r.output;
    for (const std::string& path : unwritten) {
        std::error_code ec;
        EXPECT_FALSE(fs::is_regular_file(path, ec)) << "written: " << path;
        const fs::path folder = fs::path(path).parent_path();
        if (!fs::is_directory(folder, ec)) continue;
        for (const auto& entry : fs::directory_iterator(folder))
            EXPECT_FALSE(contains(entry.path().filename().string(), ".tmp-")) << "staged file left: " << entry.path();
    }
}

const std::string kSmall = "--scene square-occluder --size 8x8 ";

// A 8x8 visibility PFM with its sidecar (exit 0 checked).
std::string goodPfm(const std::string& name) {
    const std::string path = tmp(name);
    const Result r = run("render " + kSmall + "--visibility " + path);
    EXPECT_EQ(r.code, 0) << r.output;
    return path;
}

// --- 1. one input gate -------------------------------------------------------------------------

// Every command with a FIFO and with /dev/zero in every input position: exit 2 within 5 s, the
// message naming the path. Before the gate only the scene loader checked (a FIFO blocked compare,
// sidecars, lessons, specs and scripts forever; /dev/zero grew to gigabytes).
TEST(BadInputGate, EveryCommandRefusesAFifoAndDevZeroInEveryInputPosition) {
    const std::string good = goodPfm("good.pfm");
    const std::string fifo = tmp("a-fifo");
    fs::remove(fifo);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    // Positions reached through a name the reader needs (a .gltf, a sidecar beside its PFM, a glTF
    // buffer): symbolic links to BAD with that name, named in the message.
    const std::string model = tmp("model.gltf"), buffer = tmp("buffer.bin"), sidecarOf = tmp("with-bad-sidecar.pfm");
    const std::string sceneWithModel = writeFile(
        "with-model.json", R"({"camera": {"position": [0, 2, 4], "target": [0, 0, 0]},
            "lights": [{"type": "point", "position": [0, 4, 0]}], "objects": [{"type": "gltf", "file": ")" + model + R"("}]})");
    const std::string gltfWithBuffer = writeFile(
        "with-buffer.gltf", R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "buffer.bin", "byteLength": 12}],
            "bufferViews": [{"buffer": 0, "byteLength": 12}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 1, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]})");
    fs::copy_file(good, sidecarOf, fs::copy_options::overwrite_existing);
    struct Position {
        std::string command, named;  // named: the path the message must name ("BAD": the bad path itself)
    };
    const std::vector<Position> positions = {
        {"render --scene BAD --size 8x8", "BAD"},
        {"reference --scene BAD --size 8x8 --samples 4 --out " + tmp("ref.pfm"), "BAD"},
        {"scene --scene BAD --dump-triangles " + tmp("t.obj"), "BAD"},
        {"viz --view error --technique hard --scene BAD --size 8x8 --out " + tmp("viz.png"), "BAD"},
        {"viz --view error --technique hard " + kSmall + "--reference BAD --out " + tmp("viz.png"), "BAD"},
        {"render --scene " + model + " --size 8x8", model},
        {"render --scene " + sceneWithModel + " --size 8x8", model},
        {"render --scene " + gltfWithBuffer + " --size 8x8", "buffer.bin"},
        {"compare BAD " + good, "BAD"},
        {"compare " + good + " BAD", "BAD"},
        {"compare " + sidecarOf + " " + good, sidecarOf + ".json"},
        {"bench --spec BAD", "BAD"},
        {"bench --scenes BAD --techniques hard --csv " + tmp("b.csv"), "BAD"},
        {"figure --spec BAD --out " + tmp("fig.png"), "BAD"},
        {"figure --remake BAD", "BAD"},
        {"lesson BAD --check", "BAD"},
        {"lesson BAD --headless --out " + tmp("handout"), "BAD"},
        {"window --script BAD", "BAD"},
    };
    for (const std::string& bad : {fifo, std::string("/dev/zero")}) {
        for (const std::string& link : {model, buffer, sidecarOf + ".json"}) {
            fs::remove(link);
            fs::create_symlink(bad, link);
        }
        for (Position p : positions) {
            auto replace = [&](std::string& text) {
                for (size_t at; (at = text.find("BAD")) != std::string::npos;) text.replace(at, 3, bad);
            };
            replace(p.command);
            replace(p.named);
            SCOPED_TRACE(p.command);
            const auto t0 = std::chrono::steady_clock::now();
            const Result r = run(p.command);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            EXPECT_EQ(r.code, 2) << r.output;
            EXPECT_LT(seconds, 5.0);
            EXPECT_TRUE(contains(r.output, p.named)) << r.output;
            EXPECT_TRUE(contains(r.output, "not a regular file")) << r.output;
            EXPECT_FALSE(contains(r.output, "internal error")) << r.output;
        }
    }
    EXPECT_FALSE(fs::exists(tmp("handout")));
    for (const std::string& path : {fifo, model, buffer, sidecarOf + ".json"}) fs::remove(path);
}

// The value of `column` in the first row of a CSV.
std::string csvField(const std::string& csv, const std::string& column) {
    std::istringstream in(csv);
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    auto split = [](const std::string& line) {
        std::vector<std::string> out;
        std::stringstream s(line);
        for (std::string f; std::getline(s, f, ',');) out.push_back(f);
        return out;
    };
    const std::vector<std::string> names = split(header), values = split(row);
    for (size_t i = 0; i < names.size() && i < values.size(); ++i)
        if (names[i] == column) return values[i];
    return "";
}

// A reference cache entry that is a FIFO, or whose pixels are NaN, is no hit: it is refused with a
// warning and computed again (a NaN-filled entry was a hit with RMSE 0).
TEST(BadInputGate, ACacheEntryThatIsAFifoOrHoldsNanIsComputedAgain) {
    const std::string cache = tmp("cache");
    fs::remove_all(cache);
    const std::string bench = "bench --scenes square-occluder --techniques hard --size 16x16 --frames 1 --warmup 0 "
                              "--reference reference:4 --quiet --cache " + cache + " --csv ";
    const Result first = run(bench + tmp("first.csv"));
    ASSERT_EQ(first.code, 0) << first.output;
    std::string entry;
    for (const auto& e : fs::directory_iterator(cache))
        if (e.path().extension() == ".pfm") entry = e.path().string();
    ASSERT_FALSE(entry.empty());
    const std::string rmse = csvField(readFile(tmp("first.csv")), "rmse");
    ASSERT_FALSE(rmse.empty());
    ASSERT_NE(std::stod(rmse), 0.0);

    shadowlab::Image poisoned = shadowlab::readPFM(entry);
    for (float& v : poisoned.data) v = NAN;
    shadowlab::writePFM(entry, poisoned);
    const Result nan = run(bench + tmp("nan.csv"));
    ASSERT_EQ(nan.code, 0) << nan.output;
    EXPECT_TRUE(contains(nan.output, "ignoring the cached reference")) << nan.output;
    EXPECT_TRUE(contains(nan.output, "256 of its 256 pixels are NaN, infinite or outside [0, 1]")) << nan.output;
    // Recomputed and replaced: the entry is finite again and the RMSE is the first run's, not 0.
    EXPECT_EQ(csvField(readFile(tmp("nan.csv")), "rmse"), rmse);
    for (float v : shadowlab::readPFM(entry).data) ASSERT_TRUE(std::isfinite(v));

    fs::remove(entry);
    ASSERT_EQ(mkfifo(entry.c_str(), 0600), 0);
    const auto t0 = std::chrono::steady_clock::now();
    const Result fifo = run(bench + tmp("fifo.csv"));
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0);
    ASSERT_EQ(fifo.code, 0) << fifo.output;
    EXPECT_TRUE(contains(fifo.output, "not a regular file")) << fifo.output;
    EXPECT_TRUE(fs::is_regular_file(entry));
    EXPECT_EQ(csvField(readFile(tmp("fifo.csv")), "rmse"), rmse);
}

// --- 3. metrics ---------------------------------------------------------------------------------

// No pixel finite on both sides is nothing measured: exit 2, not "pixels 0 RMSE 0 PSNR inf SSIM 1".
TEST(BadInputMetrics, AComparisonWithNoFinitePixelInCommonIsRefused) {
    const std::string good = goodPfm("good.pfm");
    shadowlab::Image nan = shadowlab::readPFM(good);
    for (float& v : nan.data) v = NAN;
    const std::string allNan = tmp("all-nan.pfm");
    shadowlab::writePFM(allNan, nan);
    expectRefused("compare " + allNan + " " + good, {"compare: ", allNan, "no pixel", "finite pixels: 0 and 64 of 64"});
    expectRefused("compare " + good + " " + allNan + " --json", {"no pixel"});
    expectRefused("compare " + good + " " + allNan + " --heatmap " + tmp("h.png"), {"no pixel"}, {tmp("h.png")});
    // Half NaN still compares: the finite half is measured.
    for (size_t i = 0; i < nan.data.size() / 2; ++i) nan.data[i] = 0.5f;
    const std::string half = tmp("half.pfm");
    shadowlab::writePFM(half, nan);
    const Result r = run("compare " + half + " " + good);
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "pixels       32")) << r.output;
}

// --- 2. numbers, flags, JSON read back ------------------------------------------------------------

// `figure --remake` reads its sidecar through a typed reader: a tampered field is exit 2 naming it
// (it was exit 1, "type must be number, but is number", or undefined behaviour for a missing key).
TEST(BadInputNumbers, ATamperedFigureSidecarNamesTheField) {
    const std::string spec =
        R"({"size": [16, 16], "frames": 1, "warmup": 0, "reference": "reference:4",
            "columns": [{"technique": "hard"}], "rows": [{"scene": "square-occluder"}]})";
    auto sidecar = [&](const std::string& cells, const std::string& extra = "") {
        return writeFile("tampered.png.json", R"({"shadowlab_figure": 1, "spec": )" + spec + R"(, "out": ")" +
                                                  tmp("remade.png") + R"(", "cells": )" + cells + extra + "}");
    };
    const std::string out = tmp("remade.png");
    expectRefused("figure --remake " + sidecar(R"([{"label_shadow_ms": "fast", "rmse": 0.1}])"),
                  {"tampered.png.json", "cells[0].label_shadow_ms", "expected a number", "fast"}, {out});
    expectRefused("figure --remake " + sidecar(R"([{"rmse": 0.1}])"),
                  {"cells[0].label_shadow_ms", "the field is required"}, {out});
    expectRefused("figure --remake " + sidecar(R"([{"label_shadow_ms": 1, "rmse": -1}])"), {"cells[0].rmse"}, {out});
    expectRefused("figure --remake " + sidecar(R"([])"), {"cells", "1 cells (the spec's rows x columns)"}, {out});
    expectRefused("figure --remake " + sidecar(R"({"a": 1})"), {"cells", "an array"}, {out});
    expectRefused("figure --remake " + sidecar(R"([{"label_shadow_ms": 1}])", R"(, "error_max": "big")"),
                  {"error_max"}, {out});
    expectRefused("figure --remake " + sidecar(R"([{"label_shadow_ms": 1}])", R"(, "out": 7)"), {"tampered.png.json", "out"},
                  {out});
    // Trailing junk after the JSON is no sidecar.
    const std::string junk = sidecar(R"([{"label_shadow_ms": 1}])") ;
    std::ofstream(junk, std::ios::app) << "\n{\"more\": 1}\n";
    expectRefused("figure --remake " + junk, {"tampered.png.json", "malformed JSON"}, {out});
    // And the PFM sidecar compare reads.
    const std::string good = goodPfm("good.pfm");
    std::ofstream(good + ".json", std::ios::app) << "trailing";
    expectRefused("compare " + good + " " + good, {"good.pfm.json", "malformed JSON"});
}

// No reader of a file the user names reads its JSON through nlohmann's unchecked operator[] (a
// missing key is undefined behaviour with a const json) or .value() (a wrong type is exit 1):
// every source file that reads a user's JSON is scanned; writing fields (`j["k"] = ...`) is allowed.
TEST(BadInputNumbers, NoUncheckedJsonLookupInTheReaders) {
    const fs::path root = fs::path(shadowlab::projectRoot());
    const std::regex lookup(R"(\[\s*"[A-Za-z_0-9]+"\s*\])");
    const std::regex write(R"((\[\s*"[A-Za-z_0-9]+"\s*\])+\s*(=[^=]|\+=|\.push_back\(|\.emplace_back\())");
    size_t readers = 0;
    std::string found;
    for (const char* dir : {"app", "techniques/core", "viz"}) {
        for (const auto& e : fs::recursive_directory_iterator(root / dir)) {
            if (e.path().extension() != ".cpp" && e.path().extension() != ".h") continue;
            const std::string text = readFile(e.path().string());
            // A reader: it parses or reads a JSON document from a file the user names (the
            // validated reader's documents, a sidecar).
            if (!contains(text, "JsonDocument") && !contains(text, "JsonReader") && !contains(text, "readSidecar("))
                continue;
            if (e.path().stem() == "json_reader") continue;  // the reader itself
            ++readers;
            std::istringstream lines(text);
            std::string line;
            for (int n = 1; std::getline(lines, line); ++n) {
                const std::string code = line.substr(0, line.find("//"));
                const std::string rest = std::regex_replace(code, write, "");
                if (std::regex_search(rest, lookup) || contains(code, ".value(\"") || contains(code, ".at(\""))
                    found += fs::relative(e.path(), root).string() + ":" + std::to_string(n) + ": " + line + "\n";
            }
        }
    }
    EXPECT_GE(readers, 7u);  // the scan reaches the readers (scene, spec, figure spec and sidecar, provenance, cache)
    EXPECT_TRUE(found.empty()) << "unchecked JSON lookups in readers of untrusted files:\n" << found;
}

// bench: a key swept twice, an empty sweep and a bench over the settings limit are refused before
// any setting is built (three 1000-value sweeps made 10^9 settings: std::bad_alloc).
TEST(BadInputNumbers, BenchSweepsAreCheckedAndCountedBeforeTheyAreBuilt) {
    const std::string csv = tmp("b.csv");
    const std::string head = "bench --scenes square-occluder --techniques pcf --size 8x8 --frames 1 --warmup 0 --csv " + csv;
    expectRefused(head + " --sweep pcf_kernel=1,3 --sweep pcf_kernel=5",
                  {"--sweep", "'pcf_kernel' is swept twice", "pcf_kernel=1,3", "pcf_kernel=5"}, {csv});
    expectRefused(head + " --sweep pcf_kernel=", {"--sweep pcf_kernel=", "expected values"}, {csv});
    expectRefused(head + " --sweep pcf_kernel=1,,3", {"an empty one"}, {csv});
    const auto t0 = std::chrono::steady_clock::now();
    expectRefused(head + " --sweep sm_size=16:1024:1000 --sweep bias_const=0:100:1000 --sweep bias_slope=0:100:1000",
                  {"settings", "over the limit of 10000", "--max-settings"}, {csv});
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
    expectRefused(head + " --sweep bias_const=0:1:10 --max-settings 5", {"10 settings", "over the limit of 5"}, {csv});
    expectRefused(head + " --max-settings 0", {"--max-settings"}, {csv});
    // The same count for a spec file.
    const std::string spec = writeFile("big.json", R"({"name": "big", "scenes": ["square-occluder"],
        "runs": [{"technique": "pcf", "sweep": {"sm_size": "16:1024:1000", "bias_const": "0:100:1000"}}]})");
    expectRefused("bench --spec " + spec + " --csv " + csv, {"big.json", "runs", "over the limit of 10000"}, {csv});
    const std::string both = writeFile("both.json", R"({"name": "both", "scenes": ["square-occluder"],
        "runs": [{"technique": "pcf", "set": {"pcf_kernel": 3}, "sweep": {"pcf_kernel": [1, 5]}}]})");
    expectRefused("bench --spec " + both + " --csv " + csv, {"both.json", "runs[0].sweep.pcf_kernel", "fixed to 3"}, {csv});
}

// Lesson numbers are checked in the float they are stored in, and an animated light size has the
// limits of a set one.
TEST(BadInputNumbers, LessonNumbersAreCheckedAsFloatsAndAnimationsHaveTheSetLimits) {
    const std::string head = "# Numbers\n\n```shadowlab\nscene square-occluder\ntechnique hard\n```\n\n## One\n\n```shadowlab\n";
    const std::vector<std::pair<std::string, std::vector<std::string>>> bad = {
        {"light position 1e300 4 0", {"lesson.md:11: ", "light position", "float", "1e300"}},
        {"light size 1e39", {"lesson.md:11: ", "light size", "1e39"}},
        {"light intensity 1e39", {"lesson.md:11: ", "light intensity"}},
        {"camera position 0 1e39 4", {"lesson.md:11: ", "camera position"}},
        {"animate light.size 0 1e9", {"lesson.md:11: ", "animate", "light.size TO", "[0, 1000]"}},
        {"animate light.size -1 1", {"lesson.md:11: ", "light.size FROM", "[0, 1000]"}},
        {"animate light.x 0 1e300", {"lesson.md:11: ", "animate TO"}},
    };
    for (const auto& [line, mentions] : bad) {
        const std::string lesson = writeFile("lesson.md", head + line + "\n```\n\nText.\n");
        expectRefused("lesson " + lesson + " --check", mentions);
    }
    // The limits themselves are accepted.
    const std::string ok = writeFile("lesson.md", head + "animate light.size 0 1000\nlight position 1e30 4 0\n```\n\nText.\n");
    const Result r = run("lesson " + ok + " --check");
    EXPECT_EQ(r.code, 0) << r.output;
}

// --- 4. output plans ----------------------------------------------------------------------------

// Outputs that collide, a sidecar (or an implicit output) whose path is a folder, and a folder
// that cannot take the file: exit 2 before any work, naming the user's path; nothing written.
TEST(BadInputOutputs, EveryOutputPathIsPlannedBeforeTheWork) {
    const std::string v = tmp("v.pfm"), png = tmp("o.png"), stats = tmp("s.json");
    // --stats v.pfm.json replaced the provenance sidecar of --visibility v.pfm (exit 0).
    expectRefused("render " + kSmall + "--visibility " + v + " --stats " + v + ".json",
                  {"--visibility's sidecar", "--stats", "the same file"}, {v, v + ".json"});
    // --internals I and an output inside I overwrote one another.
    const std::string internals = tmp("I");
    fs::remove_all(internals);
    expectRefused("render " + kSmall + "--technique hard --internals " + internals + " --visibility " + internals + "/shadow_map.pfm",
                  {"--visibility", "inside the folder", "--internals"});
    expectRefused("render " + kSmall + "--technique hard --internals " + internals + " --stats " + internals + "/index.json",
                  {"--stats", "inside the folder", "--internals"});
    EXPECT_FALSE(fs::exists(internals));
    // A sidecar path that is a folder: the PFM (and the PNG) stayed while the command exited 2.
    fs::create_directories(v + ".json");
    expectRefused("render " + kSmall + "--out " + png + " --visibility " + v, {"--visibility's sidecar", v + ".json", "folder"},
                  {png, v});
    expectRefused("reference " + kSmall + "--samples 4 --out " + v, {v + ".json", "folder"}, {v});
    fs::remove_all(v + ".json");
    const std::string csv = tmp("b.csv"), plot = tmp("p.png");
    fs::create_directories(csv + ".json");
    const std::string bench = "bench --scenes square-occluder --techniques hard --size 8x8 --frames 1 --warmup 0 --quiet ";
    expectRefused(bench + "--csv " + csv + " --plot " + plot, {"--csv's sidecar", csv + ".json", "folder"}, {csv, plot});
    fs::remove_all(csv + ".json");
    fs::create_directories(plot);
    expectRefused(bench + "--csv " + csv + " --plot " + plot, {"--plot", plot, "folder"}, {csv});
    fs::remove_all(plot);
    // --plot p.png --plot ./p.png left p.png.
    const std::string dotted = (fs::path(plot).parent_path() / "." / "p.png").string();
    expectRefused(bench + "--csv " + csv + " --plot " + plot + " --plot " + dotted, {"--plot", "the same file"}, {csv, plot});
    const std::string fig = tmp("fig.png");
    fs::create_directories(fig + ".json");
    const std::string figSpec = writeFile("fig.json", R"({"size": [16, 16], "frames": 1, "warmup": 0, "reference": "reference:4",
        "columns": [{"technique": "hard"}], "rows": [{"scene": "square-occluder"}]})");
    expectRefused("figure --spec " + figSpec + " --out " + fig, {"figure: --out's sidecar", fig + ".json", "folder"}, {fig});
    fs::remove_all(fig + ".json");
    // The lesson's handout: index.html is a folder; nothing is written into the handout folder.
    const std::string handout = tmp("handout");
    fs::remove_all(handout);
    fs::create_directories(handout + "/index.html");
    const std::string lesson = writeFile("l.md", "# L\n\n```shadowlab\nscene square-occluder\ntechnique hard\n```\n\n## One\n\n"
                                                 "```shadowlab\nshow visibility\n```\n\nText.\n");
    expectRefused("lesson " + lesson + " --headless --size 32x32 --out " + handout, {"index.html", "folder"});
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(handout)) files += e.path().filename() != "index.html";
    EXPECT_EQ(files, 0u);
    fs::remove_all(handout);
    // A failed handout leaves no empty folder behind.
    const std::string failing = writeFile("f.md", "# L\n\n```shadowlab\nscene square-occluder\ntechnique hard\n```\n\n## One\n\n"
                                                  "```shadowlab\nshow visibility\nexpect mean(visibility) > 2\n```\n\nText.\n");
    EXPECT_NE(run("lesson " + failing + " --headless --size 32x32 --out " + handout).code, 0);
    EXPECT_FALSE(fs::exists(handout));
}

// A folder that cannot take the file (/sys refuses even root): exit 2 naming the user's path, not
// "internal error" naming the temporary.
TEST(BadInputOutputs, AnUnwritableFolderIsExit2NamingTheUsersPath) {
    const std::string good = goodPfm("g.pfm");
    for (const std::string& args : std::vector<std::string>{"render " + kSmall + "--out /sys/o.png", "render " + kSmall + "--stats /sys/s.json",
                                    "render " + kSmall + "--visibility /sys/v.pfm", "render " + kSmall + "--internals /sys/I",
                                    std::string("bench --scenes square-occluder --techniques hard --size 8x8 --csv /sys/b.csv"),
                                    "compare " + good + " " + good + " --heatmap /sys/h.png",
                                    std::string("scene --scene square-occluder --dump-triangles /sys/t.obj")}) {
        SCOPED_TRACE(args);
        const Result r = run(args);
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_TRUE(contains(r.output, "/sys/")) << r.output;
        EXPECT_TRUE(contains(r.output, "cannot write the output in the folder '/sys'")) << r.output;
        EXPECT_FALSE(contains(r.output, ".tmp-")) << r.output;
        EXPECT_FALSE(contains(r.output, "internal error")) << r.output;
    }
}

}  // namespace

namespace {

// A file name that is not UTF-8 is still a file name: the sidecar records it with U+FFFD in place
// of the bad byte (the JSON writer threw: exit 1).
TEST(BadInputOutputs, ANonUtf8OutputNameIsWrittenWithItsSidecar) {
    const std::string v = tmp("bad-\xff-name.pfm"), stats = tmp("stats-\xfe.json");
    const Result r = run("render " + kSmall + "--visibility '" + v + "' --stats '" + stats + "'");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::is_regular_file(v));
    EXPECT_TRUE(fs::is_regular_file(v + ".json"));
    EXPECT_TRUE(fs::is_regular_file(stats));
    EXPECT_TRUE(contains(readFile(v + ".json"), "bad-\xef\xbf\xbd-name.pfm"));
}

}  // namespace

namespace {

// bench, figure and lesson apply the memory estimate `render` applies, to every render they would
// make, before the first (at 8192x8192 they allocated first).
TEST(BadInputLimits, BenchFigureAndLessonEstimateTheirMemoryFirst) {
    const std::string csv = tmp("b.csv");
    auto quick = [&](const std::string& args, const std::vector<std::string>& mentions) {
        const auto t0 = std::chrono::steady_clock::now();
        expectRefused(args, mentions);
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
    };
    quick("bench --scenes square-occluder --techniques hard --size 8192x8192 --csv " + csv,
          {"bench: square-occluder, ", "would need about", "--max-memory-mb"});
    quick("bench --scenes square-occluder --techniques hard --size 256x256 --max-memory-mb 16 --csv " + csv,
          {"over the limit of 16 MB"});
    const std::string spec = writeFile("big-fig.json", R"({"size": [4096, 4096], "supersample": 2, "reference": "reference:4",
        "columns": [{"technique": "hard"}], "rows": [{"scene": "square-occluder"}]})");
    quick("figure --spec " + spec + " --out " + tmp("f.png"), {"figure: rows[0] square-occluder", "would need about"});
    const std::string lesson = writeFile("l.md", "# L\n\n```shadowlab\nscene square-occluder\ntechnique hard\n```\n\n## One\n\n"
                                                 "```shadowlab\nshow visibility\n```\n\nText.\n");
    quick("lesson " + lesson + " --headless --size 8192x8192 --out " + tmp("h"), {"l.md:8: ", "would need about"});
    quick("lesson " + lesson + " --check --sizes 320x320,8192x8192", {"l.md:8: ", "8192x8192", "would need about"});
    EXPECT_FALSE(fs::exists(tmp("h")));
    // viz renders its technique first: the same estimate, with the technique's declared resources
    // (ssm-gbp06 at sm_size 8192: the map, its z-buffer, the HSM pyramid and the two-layer
    // depth_levels atlas, about 1.3 GB).
    quick("viz --view shadow-map --scene square-occluder --technique ssm-gbp06 --set sm_size=8192 --max-memory-mb 600 --out " +
              tmp("v.png"),
          {"would need about 1.3 GB", "over the limit of 600 MB"});
    EXPECT_FALSE(fs::exists(tmp("v.png")));
}

// A view a step shows that its technique cannot give (`show hsm` under `hard`) names the lesson's
// file and line when the handout is made (it named only the view).
TEST(BadInputNumbers, AViewTheTechniqueCannotGiveNamesTheLessonLine) {
    const std::string lesson = writeFile("hsm.md", "# L\n\n```shadowlab\nscene square-occluder\ntechnique hard\n```\n\n## One\n\n"
                                                   "```shadowlab\nshow hsm\n```\n\nText.\n");
    expectRefused("lesson " + lesson + " --headless --size 32x32 --out " + tmp("h"), {"hsm.md:8: show hsm (technique hard)"});
    EXPECT_FALSE(fs::exists(tmp("h")));
    // --check without --sizes renders nothing, and asks every view of its technique all the same
    // (it said "valid" before).
    expectRefused("lesson " + lesson + " --check", {"hsm.md:8: show hsm (technique hard): view hsm: technique hard builds no "
                                                     "min/max pyramid"});
    // The same view under a technique that has one is valid; a view that needs a pick says so.
    const std::string good = writeFile("hsm-ok.md", "# L\n\n```shadowlab\nscene square-occluder\ntechnique ssm-gbp06\n```\n\n"
                                                    "## One\n\n```shadowlab\nshow hsm\n```\n\nText.\n");
    const Result r = run("lesson " + good + " --check");
    EXPECT_EQ(r.code, 0) << r.output;
    const std::string nopick = writeFile("bp.md", "# L\n\n```shadowlab\nscene square-occluder\ntechnique ssm-contour\n```\n\n"
                                                  "## One\n\n```shadowlab\nshow backprojection\n```\n\nText.\n");
    expectRefused("lesson " + nopick + " --check", {"bp.md:8: show backprojection (technique ssm-contour)", "--pixel"});
}

}  // namespace

namespace {

// A figure's title and labels have a stated length (a 200,000-character title took 29 s to fit).
TEST(BadInputLimits, AFigureLabelHasAStatedLength) {
    const std::string title(200000, 'x');
    const std::string spec = writeFile("long.json", R"({"title": ")" + title + R"(", "size": [16, 16], "reference": "reference:4",
        "columns": [{"technique": "hard"}], "rows": [{"scene": "square-occluder", "label": "ok"}]})");
    const auto t0 = std::chrono::steady_clock::now();
    expectRefused("figure --spec " + spec + " --out " + tmp("f.png"),
                  {"long.json:1: title: expected a text of at most 1000 characters, got a text of 200000"}, {tmp("f.png")});
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

}  // namespace

#include "graph/renderer.h"
#include "graph/technique.h"

namespace {

// The memory estimate counts what each technique declares (techniqueResourceBytes): for every
// technique, under a point light (its `hard` stand-in when it has soft passes) and an area light,
// the estimate of one light's resources is at least what the pool allocated for that light in a
// render that asks for every internal (so every pass ran), and at most 1% more (an estimate that
// counted only the shadow map said 538 MB for ssm-gbp06 at sm_size 8192, which took 1,065 MB).
TEST(BadInputLimits, TheMemoryEstimateCountsEveryResourceTheTechniqueAllocates) {
    using namespace shadowlab;
    for (const TechniqueDesc* desc : allTechniques()) {
        for (const double size : {0.0, 0.8}) {
            SCOPED_TRACE(desc->id + " at light size " + std::to_string(size));
            const std::string stats = tmp("estimate-" + desc->id + ".json"), internals = tmp("estimate-" + desc->id);
            fs::remove_all(internals);
            const Result r = run("render --scene square-occluder --size 48x40 --technique " + desc->id + " --light-size " +
                                 std::to_string(size) + " --stats " + stats + " --internals " + internals);
            ASSERT_EQ(r.code, 0) << r.output;
            const nlohmann::json j = nlohmann::json::parse(readFile(stats));
            double allocated = 0.0;
            for (const nlohmann::json& res : j.at("resources"))
                if (res.at("name").get<std::string>().rfind("L0/", 0) == 0 && res.at("kind").get<std::string>() != "mesh")
                    allocated += res.at("bytes").get<double>();
            // What the light runs, resolved as the renderer resolves it (a point light's `hard`,
            // `auto`'s pick).
            RenderOptions options;
            options.width = 48;
            options.height = 40;
            options.technique = desc->id;
            options.lightSize = float(size);
            const std::vector<LightState> lights = Renderer::resolveLights(loadScene("square-occluder"), options);
            const TechniqueDesc* runs = lights.at(0).desc;
            const double estimated = techniqueResourceBytes(*runs, lights.at(0).params, {48, 40});
            EXPECT_GT(allocated, 0.0) << runs->id;  // the stats list the light's resources
            EXPECT_GE(estimated, allocated) << runs->id;
            EXPECT_LE(estimated, allocated * 1.01 + 64.0) << runs->id;
        }
    }
}

}  // namespace

namespace {

// A name over the file system's 255 bytes in an output (or input) path is bad input, exit 2 naming
// the flag and the limit, from every command: std::filesystem's throwing calls made it "internal
// error: filesystem error: status: File name too long" (exit 1). Found by fuzz_cli in its first
// 10-minute run (`viz --view hsm --scene n,5 --out /dev/111...1nu...`).
TEST(BadInputOutputs, ANameOverTheFileSystemLimitIsExit2FromEveryCommand) {
    const std::string longName(300, 'n');
    const std::string out = tmp(longName + ".png");
    const std::string script = writeFile("long-name.txt", "screenshot " + tmp(longName + ".png") + "\n");
    const std::string spec = writeFile("long-name.json", R"({"title": "t", "size": [16, 16], "reference": "reference:4",
        "columns": [{"technique": "hard"}], "rows": [{"scene": "square-occluder", "label": "ok"}]})");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"render --scene square-occluder --size 16x16 --out " + out, "--out"},
        {"render --scene square-occluder --size 16x16 --stats " + tmp(longName + ".json"), "--stats"},
        {"render --scene " + tmp(longName + ".gltf") + " --size 16x16 --out " + tmp("o.png"), longName.substr(0, 40)},
        {"viz --view scene3d --scene square-occluder --out " + out, "--out"},
        {"bench --scenes square-occluder --techniques hard --size 16x16 --csv " + tmp(longName + ".csv"), "--csv"},
        {"figure --spec " + spec + " --out " + out, "--out"},
        {"lesson intro --headless --out " + tmp(longName), "--out"},
        {"scene --scene square-occluder --dump-triangles " + tmp(longName + ".obj"), "--dump-triangles"},
        {"window --screenshot " + out, "--screenshot"},
        {"window --script " + script, "long-name.txt:1: screenshot"},
    };
    for (const auto& [arguments, flag] : cases) {
        SCOPED_TRACE(arguments.substr(0, 120));
        const Result r = run(arguments);
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(flag), std::string::npos) << r.output;
        if (arguments.find("gltf") == std::string::npos)
            EXPECT_NE(r.output.find("bytes long, over the file system's limit of 255"), std::string::npos) << r.output;
    }
}

}  // namespace
