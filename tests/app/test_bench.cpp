// `shadowlab bench` end to end (issue 8): the CSV's columns, the chart as PNG, SVG and PDF, identical
// error columns twice, the reference cache, and bad specs refused with file and field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <stb/stb_image.h>

#include "chart_accuracy_time.h"
#include "support/cli_run.h"
#include "support/gl_fixture.h"
#include "vtk_offscreen.h"

namespace fs = std::filesystem;
using shadowlab::test::run;
using shadowlab::test::testPath;

namespace {

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<std::string> splitCsvLine(const std::string& line) {
    std::vector<std::string> out;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
        if (c == '"') quoted = !quoted;
        else if (c == ',' && !quoted) out.push_back(cell), cell.clear();
        else cell += c;
    }
    out.push_back(cell);
    return out;
}

// The CSV as rows of column -> value.
std::vector<std::map<std::string, std::string>> readCsv(const std::string& path, std::vector<std::string>* header = nullptr) {
    std::istringstream in(readText(path));
    std::string line;
    std::getline(in, line);
    std::vector<std::string> columns = splitCsvLine(line);
    if (header) *header = columns;
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        std::vector<std::string> cells = splitCsvLine(line);
        EXPECT_EQ(cells.size(), columns.size()) << line;
        std::map<std::string, std::string> row;
        for (size_t i = 0; i < columns.size() && i < cells.size(); ++i) row[columns[i]] = cells[i];
        rows.push_back(row);
    }
    return rows;
}

// A small bench: square-occluder, hard / pcf / reference (16 samples), 128x128, 2 timed frames,
// against 16 rays. Few frames and samples keep it to a few seconds.
std::string smallBench(const std::string& dir, const std::string& cache, const std::string& extra = "") {
    return "bench --scenes square-occluder --techniques hard,pcf,reference --sweep samples=16 --size 128x128 "
           "--frames 2 --warmup 1 --reference raytraced:16 --cache " + cache + " --csv " + dir + "/bench.csv " + extra;
}

}  // namespace

TEST(Bench, CsvHasEveryColumnAndThePlotIsWrittenAsPngSvgPdf) {
    const std::string dir = fs::path(testPath("bench", "x")).parent_path().string();
    const std::string cache = dir + "/cache";
    fs::remove_all(cache);
    auto r = run(smallBench(dir, cache, "--plot " + dir + "/plot.png --plot " + dir + "/plot.svg --plot " + dir +
                                            "/plot.pdf --report " + dir + "/report.md --latex " + dir + "/table.tex"));
    ASSERT_EQ(r.code, 0) << r.output;
    // Progress on stderr, with the time left.
    EXPECT_NE(r.output.find("[3/3]"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("s left"), std::string::npos) << r.output;

    std::vector<std::string> header;
    auto rows = readCsv(dir + "/bench.csv", &header);
    ASSERT_EQ(rows.size(), 3u);
    for (const char* column :
         {"scene", "light_size", "technique", "params", "width", "height", "shadow_ms", "fixed_ms", "total_ms", "rmse",
          "max_abs", "psnr", "ssim", "penumbra_rmse", "penumbra_max_abs", "penumbra_psnr", "penumbra_ssim",
          "technique_memory_bytes", "memory_bytes", "clock", "reference_key", "ms.gbuffer", "ms.shade",
          "ms.hard/shadow_map", "ms.pcf/filter", "ms.reference/accumulate"})
        EXPECT_NE(std::find(header.begin(), header.end(), column), header.end()) << "missing column " << column;
    EXPECT_EQ(rows[0]["technique"], "hard");
    EXPECT_EQ(rows[1]["technique"], "pcf");
    EXPECT_EQ(rows[2]["technique"], "reference");
    EXPECT_EQ(rows[2]["setting"], "samples=16");
    for (auto& row : rows) {
        EXPECT_EQ(row["scene"], "square-occluder");
        EXPECT_EQ(row["width"], "128");
        EXPECT_EQ(row["clock"], "cpu-finish");
        EXPECT_GT(std::stod(row["shadow_ms"]), 0.0);
        EXPECT_GT(std::stod(row["fixed_ms"]), 0.0);
        // total = shadow + fixed, up to the 4 decimals written.
        EXPECT_NEAR(std::stod(row["total_ms"]), std::stod(row["shadow_ms"]) + std::stod(row["fixed_ms"]), 2e-4);
        EXPECT_GT(std::stoll(row["technique_memory_bytes"]), 0);
        EXPECT_GT(std::stoll(row["penumbra_pixels"]), 100);  // the square light's penumbra is visible
        EXPECT_EQ(row["reference_key"].size(), 16u);
    }
    // Hard shadows have no penumbra: their error there is large; the reference's small.
    EXPECT_GT(std::stod(rows[0]["penumbra_rmse"]), 0.1);
    EXPECT_LT(std::stod(rows[2]["penumbra_rmse"]), std::stod(rows[0]["penumbra_rmse"]) / 2);
    // The pass columns belong to the rows that ran them.
    EXPECT_FALSE(rows[0]["ms.hard/shadow_map"].empty());
    EXPECT_TRUE(rows[0]["ms.pcf/filter"].empty());

    // The PNG chart: the series' colours are on it (each technique's colour is fixed by the registry).
    int w = 0, h = 0, n = 0;
    unsigned char* png = stbi_load((dir + "/plot.png").c_str(), &w, &h, &n, 3);
    ASSERT_NE(png, nullptr);
    EXPECT_EQ(w, 720);
    EXPECT_EQ(h, 500);
    auto has = [&](int r0, int g0, int b0) {
        for (int i = 0; i < w * h; ++i)
            if (std::abs(png[i * 3] - r0) < 12 && std::abs(png[i * 3 + 1] - g0) < 12 && std::abs(png[i * 3 + 2] - b0) < 12)
                return true;
        return false;
    };
    for (const char* technique : {"hard", "pcf", "reference"}) {
        shadowlab::Rgb8 c = shadowlab::techniqueChartColour(technique);
        EXPECT_TRUE(has(c.r, c.g, c.b)) << technique;
    }
    stbi_image_free(png);
    // SVG and PDF: VTK's vector exporters; the PDF keeps its text as text.
    const std::string svg = readText(dir + "/plot.svg");
    EXPECT_NE(svg.find("<svg"), std::string::npos);
    {
        shadowlab::Rgb8 c = shadowlab::techniqueChartColour("hard");
        char hex[8];
        std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c.r, c.g, c.b);
        EXPECT_NE(svg.find(hex), std::string::npos) << "hard's colour " << hex;
    }
    const std::string pdf = readText(dir + "/plot.pdf");
    EXPECT_EQ(pdf.rfind("%PDF", 0), 0u);
    EXPECT_GT(pdf.size(), 2000u);

    const std::string report = readText(dir + "/report.md");
    EXPECT_NE(report.find("plot.png"), std::string::npos);
    EXPECT_NE(report.find("| 1 | reference | samples=16 |"), std::string::npos) << report;
    EXPECT_NE(readText(dir + "/table.tex").find("\\begin{tabular}"), std::string::npos);
    // The CSV's sidecar records the reference's cache key.
    EXPECT_NE(readText(dir + "/bench.csv.json").find(rows[0]["reference_key"]), std::string::npos);
}

TEST(Bench, TwiceGivesIdenticalErrorColumnsAndTheReferenceIsCached) {
    const std::string dir = fs::path(testPath("bench", "x")).parent_path().string();
    // A fresh folder: the caches must start empty (a previous run of the test leaves them).
    for (const char* sub : {"a", "b", "c", "d", "cache-a", "cache-b"}) fs::remove_all(dir + "/" + sub);
    fs::create_directories(dir + "/a");
    fs::create_directories(dir + "/b");
    // Separate caches: the reference is computed twice, so its determinism is tested too.
    auto first = run(smallBench(dir + "/a", dir + "/cache-a"));
    ASSERT_EQ(first.code, 0) << first.output;
    auto second = run(smallBench(dir + "/b", dir + "/cache-b"));
    ASSERT_EQ(second.code, 0) << second.output;
    EXPECT_NE(first.output.find("computed"), std::string::npos) << first.output;
    auto a = readCsv(dir + "/a/bench.csv");
    auto b = readCsv(dir + "/b/bench.csv");
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        for (const char* column : {"rmse", "max_abs", "psnr", "ssim", "pixels", "penumbra_rmse", "penumbra_max_abs",
                                   "penumbra_psnr", "penumbra_ssim", "penumbra_pixels", "reference_key", "params"})
            EXPECT_EQ(a[i][column], b[i][column]) << "row " << i << " column " << column;
    // A third run with the first cache reads the reference back (same key), same errors.
    fs::create_directories(dir + "/c");
    auto third = run(smallBench(dir + "/c", dir + "/cache-a"));
    ASSERT_EQ(third.code, 0) << third.output;
    EXPECT_NE(third.output.find("cached, key " + a[0]["reference_key"]), std::string::npos) << third.output;
    auto c = readCsv(dir + "/c/bench.csv");
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i]["rmse"], c[i]["rmse"]);
    // The key changes with what decides the reference (here the light size).
    fs::create_directories(dir + "/d");
    auto fourth = run(smallBench(dir + "/d", dir + "/cache-a", "--light-sizes 0.5"));
    ASSERT_EQ(fourth.code, 0) << fourth.output;
    auto d = readCsv(dir + "/d/bench.csv");
    EXPECT_NE(d[0]["reference_key"], a[0]["reference_key"]);
    EXPECT_EQ(d[0]["light_size"], "0.5");
}

namespace {

// Writes `text` as a spec and runs it; returns the result.
shadowlab::test::Result runSpec(const std::string& name, const std::string& text) {
    const std::string path = testPath("bench", name);
    std::ofstream(path) << text;
    return run("bench --spec " + path + " --csv " + fs::path(path).parent_path().string() + "/out.csv --cache " +
               fs::path(path).parent_path().string() + "/cache");
}

const char* kGoodRuns = R"("runs": [{"technique": "pcf", "sweep": {"pcf_kernel": [3, 5]}}])";

}  // namespace

TEST(Bench, BadSpecsAreRefusedWithFileAndField) {
    struct Case {
        const char* name;
        std::string text;
        std::vector<std::string> expected;  // substrings of the message
    };
    const std::vector<Case> cases = {
        {"unknown-technique.json", R"({"name": "x", "scenes": ["square-occluder"], "runs": [{"technique": "pcss2"}]})",
         {"unknown-technique.json:1: runs[0].technique", "registered technique", "pcss2"}},
        {"unknown-key.json",
         "{\"name\": \"x\", \"scenes\": [\"square-occluder\"],\n \"runs\": [{\"technique\": \"pcf\", \"sweep\": {\"kernel\": [3]}}]}",
         {"unknown-key.json:2: runs[0].sweep.kernel", "unknown parameter 'kernel'", "pcf_kernel"}},
        {"out-of-range.json",
         R"({"name": "x", "scenes": ["square-occluder"], "runs": [{"technique": "pcf", "sweep": {"pcf_kernel": [3, 99]}}]})",
         {"out-of-range.json:1: runs[0].sweep.pcf_kernel[1]", "expected a value in [1, 63], got 99"}},
        {"bad-range.json",
         R"({"name": "x", "scenes": ["square-occluder"], "runs": [{"technique": "pcf", "sweep": {"pcf_kernel": "3:9"}}]})",
         {"bad-range.json:1: runs[0].sweep.pcf_kernel", "a:b:n"}},
        {"missing-scene.json", std::string(R"({"name": "x", "scenes": ["square-occluder", "no-such-scene"], )") + kGoodRuns + "}",
         {"missing-scene.json:1: scenes[1]", "no-such-scene"}},
        {"no-scenes.json", std::string(R"({"name": "x", )") + kGoodRuns + "}", {"no-scenes.json", "scenes", "required"}},
        {"unknown-field.json", std::string(R"({"name": "x", "scenes": ["plant"], "frame": 3, )") + kGoodRuns + "}",
         {"unknown-field.json:1", "frame"}},
        {"bad-paper-column.json",
         std::string(R"({"name": "x", "scenes": ["plant"], )") + kGoodRuns +
             R"(, "paper": {"citation": "c", "columns": {"Step1": "ms.pcf/step1"}, "rows": [{"label": "a", "technique": "pcf", "values": {"Step1": 1}}]}})",
         {"bad-paper-column.json:1: paper.columns.Step1", "ms.<technique>/<pass>"}},
        {"paper-row-not-run.json",
         std::string(R"({"name": "x", "scenes": ["plant"], )") + kGoodRuns +
             R"(, "paper": {"citation": "c", "columns": {"T": "shadow_ms"}, "rows": [{"label": "a", "technique": "pcf", "params": {"pcf_kernel": 9}, "values": {"T": 1}}]}})",
         {"paper-row-not-run.json:1: paper.rows[0]", "no run of the spec has this setting"}},
        {"bad-camera-distance.json",
         std::string(R"({"name": "x", "scenes": ["plant"], "camera_distances": [1, -2], )") + kGoodRuns + "}",
         {"bad-camera-distance.json:1: camera_distances[1]", "-2"}},
        {"repeated-camera-distance.json",
         std::string(R"({"name": "x", "scenes": ["plant"], "camera_distances": [2, 2], )") + kGoodRuns + "}",
         {"repeated-camera-distance.json:1: camera_distances[1]", "differ"}},
        {"empty-camera-distances.json",
         std::string(R"({"name": "x", "scenes": ["plant"], "camera_distances": [], )") + kGoodRuns + "}",
         {"empty-camera-distances.json:1: camera_distances", "non-empty array"}},
    };
    for (const Case& c : cases) {
        auto r = runSpec(c.name, c.text);
        EXPECT_EQ(r.code, 2) << c.name << ": " << r.output;
        for (const std::string& e : c.expected) EXPECT_NE(r.output.find(e), std::string::npos) << c.name << ": " << r.output;
        // Nothing half-written.
        EXPECT_FALSE(fs::exists(fs::path(testPath("bench", c.name)).parent_path() / "out.csv")) << c.name;
    }
    // Flags are checked the same way.
    auto r = run("bench --scenes square-occluder --techniques hard --sweep pcf_kernel=3,5 --csv /tmp/x.csv");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("no technique of --techniques has the parameter 'pcf_kernel'"), std::string::npos) << r.output;
    r = run("bench --scenes square-occluder --techniques hard --plot plot.gif");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("--plot: expected a .png, .svg, .pdf file"), std::string::npos) << r.output;
}

TEST(Bench, ShippedSpecsLoad) {
    // quality-tiers and all-techniques parse and validate: the spec is read before the outputs are
    // checked, so a CSV in a missing folder is the first (and only) complaint.
    for (const char* spec : {"quality-tiers", "all-techniques", "cournia2005"}) {
        auto r = run(std::string("bench --spec ") + spec + " --csv /nonexistent-folder/x.csv");
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_NE(r.output.find("--csv: folder '/nonexistent-folder' does not exist"), std::string::npos)
            << spec << ": " << r.output;
    }
}

// camera_distances: one row per scene x distance, labelled "<scene> camera Dx"; light 0's counters
// come out as counter.<counter>.<field> columns. pvmf lists fewer pixels as the camera moves away
// (sec. 5.5's masked fraction) and its filter then runs on fewer pixels; the count is compared, not
// the time (timings are a benchmark's, not a test's).
TEST(Bench, CameraDistancesGiveOneRowEachAndTheCountersAreColumns) {
    const std::string dir = testPath("bench", "camera");
    fs::create_directories(dir);
    const std::string path = dir + "/spec.json";
    std::ofstream(path) << R"({"name": "cam", "scenes": ["sphere-light"], "camera_distances": [1, 4], "size": [96, 96],
        "frames": 1, "warmup": 0, "reference": "raytraced:4", "runs": [{"technique": "pvmf"}, {"technique": "hard"}]})";
    auto r = run("bench --spec " + path + " --csv " + dir + "/out.csv --cache " + dir + "/cache --quiet");
    ASSERT_EQ(r.code, 0) << r.output;
    std::vector<std::string> header;
    auto rows = readCsv(dir + "/out.csv", &header);
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[0]["scene"], "sphere-light camera 1x");
    EXPECT_EQ(rows[2]["scene"], "sphere-light camera 4x");
    EXPECT_NE(std::find(header.begin(), header.end(), "counter.mask.masked_fraction"), header.end());
    EXPECT_EQ(rows[1]["counter.mask.masked_fraction"], "");  // hard has no mask counter
    const double near = std::stod(rows[0]["counter.mask.listed_pixels"]);
    const double far = std::stod(rows[2]["counter.mask.listed_pixels"]);
    EXPECT_GT(near, 2.0 * far) << near << " " << far;
    EXPECT_GT(std::stod(rows[0]["counter.mask.masked_fraction"]), std::stod(rows[2]["counter.mask.masked_fraction"]));
}

// ---- the chart in-process: the Pareto front and the window's highlighted setting -----------------

TEST(AccuracyTimeChart, ParetoFrontKeepsOnlyUnbeatenSettings) {
    using shadowlab::AccuracyTimePoint;
    std::vector<AccuracyTimePoint> points = {
        {"hard", "default", 1.0, 0.10, false},  // fastest: on the front
        {"pcf", "n=3", 2.0, 0.12, false},       // slower and worse than hard: off
        {"pcf", "n=9", 4.0, 0.08, false},       // on
        {"pcf", "n=15", 4.0, 0.09, false},      // same time as n=9, worse: off
        {"reference", "N=16", 50.0, 0.02, false},  // on
        {"reference", "N=64", 40.0, 0.03, false},  // faster than N=16 and better than n=9: on
    };
    std::vector<size_t> front = shadowlab::paretoFront(points);
    EXPECT_EQ(front, (std::vector<size_t>{0, 2, 5, 4}));
}

class AccuracyTimeChartGL : public shadowlab::testing::GLTest {};

TEST_F(AccuracyTimeChartGL, HighlightedSettingIsRingedAndZeroErrorIsDrawn) {
    using shadowlab::AccuracyTimePoint;
    shadowlab::AccuracyTimePanel panel{"test", {{"hard", "default", 1.5, 0.1, false},
                                                {"pcf", "n=9", 6.0, 0.05, true},
                                                {"exact", "zero", 300.0, 0.0, false},  // a series the registry does not know: the next colour
                                                {"reference", "N=64", 200.0, 0.004, false}}};
    const std::string path = testPath("bench", "highlight.png");
    shadowlab::writeAccuracyTimeChart({panel}, {}, 600, 400, path, ".png");
    EXPECT_EQ(shadowlab::vtkMessages().errors, 0) << shadowlab::vtkMessages().last;
    int w = 0, h = 0, n = 0;
    unsigned char* png = stbi_load(path.c_str(), &w, &h, &n, 3);
    ASSERT_NE(png, nullptr);
    auto count = [&](int r0, int g0, int b0) {
        int c = 0;
        for (int i = 0; i < w * h; ++i)
            if (std::abs(png[i * 3] - r0) < 20 && std::abs(png[i * 3 + 1] - g0) < 20 && std::abs(png[i * 3 + 2] - b0) < 20) ++c;
        return c;
    };
    // The red ring around the current setting and its legend entry: about 166 pixels each.
    EXPECT_GT(count(220, 0, 0), 250);
    // The zero-error point, in its series' colour, though an error of 0 has no place on a log axis:
    // it is drawn at the axis floor. (Its colour is used by no other mark or text.)
    const shadowlab::Rgb8 exact = shadowlab::techniqueChartColour("exact");
    // A disc of radius 5 covers about 58 pixels of its exact colour: the legend's swatch and the point.
    EXPECT_GT(count(exact.r, exact.g, exact.b), 90);
    stbi_image_free(png);
}

// Issue 24: the bench says how long it will take before its first setting (it said only the time
// left after each one): the estimate line comes before the first "[1/N]" line and counts the renders.
TEST(Bench, TheEstimatedTimeIsPrintedBeforeTheFirstSetting) {
    const std::string dir = testPath("bench", "estimate");
    fs::create_directories(dir);
    const auto r = run("bench --scenes square-occluder --techniques hard,pcf --size 32x32 --frames 2 --warmup 1 --csv " + dir +
                       "/out.csv --cache " + dir + "/cache");
    ASSERT_EQ(r.code, 0) << r.output;
    const size_t estimate = r.output.find("bench: 2 setting(s) x 1 scene(s) x 1 light size(s) = 2 renders of 3 frames at 32x32: about ");
    ASSERT_NE(estimate, std::string::npos) << r.output;
    EXPECT_NE(r.output.find(" s (from one probe frame per technique)", estimate), std::string::npos) << r.output;
    const size_t first = r.output.find("bench: [1/2]");
    ASSERT_NE(first, std::string::npos) << r.output;
    EXPECT_LT(estimate, first) << r.output;
}
