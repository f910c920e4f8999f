// `shadowlab bench` (issue 8): every scene x light size x technique setting rendered with every pass
// timed every frame, compared with a cached reference; one CSV row per setting, the
// accuracy-versus-time chart, a Markdown report with the paper's numbers beside ours, a LaTeX table.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>
#include <thread>

#include "scene/input_file.h"
#include "bench/bench.h"
#include "bench/chart.h"
#include "cli/cli.h"
#include "cli/provenance.h"
#include "cli/resource_limits.h"
#include "error.h"
#include "gl/context.h"
#include "graph/technique.h"

namespace fs = std::filesystem;

namespace shadowlab {

namespace {

std::vector<std::string> splitList(const std::string& text, char sep = ',') {
    std::vector<std::string> out;
    std::stringstream s(text);
    std::string item;
    while (std::getline(s, item, sep)) out.push_back(item);
    return out;
}

void checkOutput(const std::string& flag, const std::string& path, const std::vector<std::string>& extensions) {
    if (path.empty()) throw InputError("bench: " + flag + ": expected a file path");
    checkPathName("bench: " + flag, path);
    fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw InputError("bench: " + flag + ": folder '" + parent.string() + "' does not exist");
    std::string ext = fs::path(path).extension().string();
    std::string list;
    for (const std::string& e : extensions) {
        if (ext == e) return;
        list += (list.empty() ? "" : ", ") + e;
    }
    throw InputError("bench: " + flag + ": expected a " + list + " file, got '" + path + "'");
}

// The spec from flags: --scenes, --techniques, --sweep, --light-sizes.
BenchSpec specFromFlags(const Options& opts) {
    BenchSpec spec;
    spec.name = "bench";
    spec.title = "shadowlab bench";
    if (!opts.has("--scenes")) throw InputError("bench: --scenes A,B (or --spec NAME.json) is required");
    if (!opts.has("--techniques")) throw InputError("bench: --techniques T1,T2 (or --spec NAME.json) is required");
    for (const std::string& s : splitList(opts.get("--scenes"))) {
        try {
            (void)loadScene(s);
        } catch (const InputError& e) {
            throw InputError("bench: --scenes: cannot load the scene \"" + s + "\": " + e.what());
        }
        spec.scenes.push_back(s);
    }
    if (spec.scenes.empty()) throw InputError("bench: --scenes: expected a comma-separated list of scenes");
    for (const std::string& t : splitList(opts.get("--techniques"))) {
        requireTechnique(t, "bench: --techniques");
        spec.runs.push_back(RunSpec{t, {}, {}});
    }
    if (spec.runs.empty()) throw InputError("bench: --techniques: expected a comma-separated list of techniques");
    std::map<std::string, std::string> swept;  // key -> its --sweep, so a key is swept once
    for (const std::string& sweep : opts.all("--sweep")) {
        size_t eq = sweep.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("bench: --sweep: expected key=a:b:n or key=v1,v2,..., got '" + sweep + "'");
        std::string key = sweep.substr(0, eq), values = sweep.substr(eq + 1);
        // A repeated key kept the last sweep without a word; an empty one made no setting (a CSV of
        // its header only).
        if (const auto it = swept.find(key); it != swept.end())
            throw InputError("bench: --sweep: the key '" + key + "' is swept twice ('" + it->second + "' and '" + sweep +
                             "'), expected each key once (list its values in one sweep)");
        swept[key] = sweep;
        if (values.empty())
            throw InputError("bench: --sweep " + sweep + ": expected values after '=' (a:b:n or v1,v2,...), got none");
        bool used = false;
        for (RunSpec& run : spec.runs) {
            const TechniqueDesc& d = requireTechnique(run.technique, "--techniques");
            const ParamDesc* p = d.findParam(key);
            if (!p) continue;
            used = true;
            std::vector<std::string> list = values.find(':') != std::string::npos
                                                ? expandRange(values, "bench: --sweep " + sweep, p->type != ParamDesc::Type::Float)
                                                : splitList(values);
            for (const std::string& v : list)
                if (v.empty()) throw InputError("bench: --sweep " + sweep + ": expected a value between every two commas, got an empty one");
            ParamValues check(d);
            for (const std::string& v : list) check.set(d, key, v, "bench: --sweep " + key);
            run.sweep.push_back({key, list});
        }
        if (!used) throw InputError("bench: --sweep " + sweep + ": no technique of --techniques has the parameter '" + key + "'");
    }
    return spec;
}

std::string fmt(const char* format, double v) {
    char text[64];
    std::snprintf(text, sizeof text, format, v);
    return text;
}

}  // namespace

int commandBench(const std::vector<std::string>& args) {
    for (const std::string& a : args)
        if (a == "--calibrate") return commandCalibrate(args);
    Options opts("bench", args, 1,
                 {"--spec", "--scenes", "--techniques", "--sweep", "--light-sizes", "--size", "--frames", "--warmup",
                  "--reference", "--cache", "--csv", "--plot", "--latex", "--report", "--error", "--gl", "--max-settings",
                  "--max-memory-mb"},
                 {"--quiet"});
    if (!opts.positional().empty()) throw InputError("bench: unexpected argument '" + opts.positional()[0] + "'");
    // The settings are counted before any is built (scenes x light sizes x sweeps).
    const double maxSettings = opts.has("--max-settings") ? double(opts.getInt("--max-settings", 0, 1, 100000000))
                                                          : kDefaultMaxSettings;
    BenchSpec spec;
    if (opts.has("--spec")) {
        for (const char* f : {"--scenes", "--techniques", "--sweep"})
            if (opts.has(f)) throw InputError(std::string("bench: ") + f + " cannot be combined with --spec (the spec lists them)");
        std::string path = opts.get("--spec");
        // "quality-tiers" names assets/bench/quality-tiers.json.
        if (path.find('/') == std::string::npos && fs::path(path).extension() != ".json")
            path = projectRoot() + "/assets/bench/" + path + ".json";
        spec = loadBenchSpec(path, maxSettings);
    } else {
        spec = specFromFlags(opts);
    }
    // Flags override the spec (CI runs a spec at a reduced size).
    if (opts.has("--size")) parseSize(opts.get("--size"), spec.width, spec.height);
    spec.frames = opts.getInt("--frames", spec.frames, 1, 10000);
    spec.warmup = opts.getInt("--warmup", spec.warmup, 0, 1000);
    if (opts.has("--reference")) spec.reference = parseReferenceSpec(opts.get("--reference"), "bench: --reference");
    if (opts.has("--error")) {
        spec.errorMetric = opts.get("--error");
        if (spec.errorMetric != "rmse" && spec.errorMetric != "1-ssim")
            throw InputError("bench: --error: expected rmse or 1-ssim, got '" + spec.errorMetric + "'");
    }
    if (opts.has("--light-sizes")) {
        spec.lightSizes.clear();
        for (const std::string& s : splitList(opts.get("--light-sizes"))) {
            if (s == "scene") {
                spec.lightSizes.push_back(std::nullopt);
                continue;
            }
            char* end = nullptr;
            double v = std::strtod(s.c_str(), &end);
            if (s.empty() || *end != '\0' || !std::isfinite(v) || v < 0.0 || v > 1e6)
                throw InputError("bench: --light-sizes: expected sizes >= 0 (or \"scene\"), comma-separated, got '" + s + "'");
            spec.lightSizes.push_back(float(v));
        }
        if (spec.lightSizes.empty()) throw InputError("bench: --light-sizes: expected at least one size");
    }

    const std::string csv = opts.get("--csv"), latex = opts.get("--latex"), report = opts.get("--report");
    const std::vector<std::string> plots = opts.all("--plot");
    if (csv.empty() && latex.empty() && report.empty() && plots.empty())
        throw InputError("bench: nothing to write: give --csv out.csv (and/or --plot, --report, --latex)");
    if (!csv.empty()) checkOutput("--csv", csv, {".csv"});
    if (!latex.empty()) checkOutput("--latex", latex, {".tex"});
    if (!report.empty()) checkOutput("--report", report, {".md"});
    for (const std::string& p : plots) checkOutput("--plot", p, {".png", ".svg", ".pdf"});
    // The output plan: the CSV and its sidecar, each plot, the table and the report, checked
    // together (`--plot p.png --plot ./p.png`, `--csv b.csv --report b.csv.json`, a folder where a
    // file goes) before anything is rendered; written through one OutputSet at the end.
    OutputPlan plan;
    plan.fileWithSidecar("bench: --csv", csv);
    for (const std::string& p : plots) plan.file("bench: --plot", p);
    plan.file("bench: --latex", latex);
    plan.file("bench: --report", report);
    plan.check();
    const std::string cacheDir = opts.has("--cache") ? opts.get("--cache") : defaultReferenceCacheDir();

    // Counted again with the flags' light sizes, before any setting is built.
    checkBenchSettingCount(spec, maxSettings, opts.has("--spec") ? spec.file : std::string("bench"));
    // Every setting, validated before any pixel is rendered.
    std::vector<Setting> settings;
    for (const RunSpec& run : spec.runs)
        for (const Setting& s : run.settings()) settings.push_back(s);
    std::vector<Scene> scenes;
    std::vector<std::string> labels;  // the rows' scene column
    for (const std::string& s : spec.scenes) {
        const Scene base = loadScene(s);
        for (double d : spec.cameraDistances) {
            scenes.push_back(benchScene(base, d));
            labels.push_back(benchSceneLabel(s, d, spec.cameraDistances));
        }
    }
    const size_t total = scenes.size() * spec.lightSizes.size() * settings.size();
    // The memory estimate `render` applies, for every render the bench makes (each setting and the
    // reference, on each scene), before the first: an 8192x8192 bench allocated first.
    for (size_t si = 0; si < scenes.size(); ++si) {
        RenderOptions reference;
        reference.width = spec.width;
        reference.height = spec.height;
        reference.technique = spec.reference.technique;
        std::vector<std::pair<std::string, RenderOptions>> renders = {{"the reference " + spec.reference.describe(), reference}};
        for (const Setting& setting : settings) {
            RenderOptions o = reference;
            o.technique = setting.technique;
            o.sets = setting.sets;
            renders.push_back({setting.technique + " " + setting.describe(), o});
        }
        for (const auto& [what, options] : renders) {
            try {
                checkRenderMemory(scenes[si], options, opts);
            } catch (const InputError& e) {
                throw InputError("bench: " + labels[si] + ", " + what + ": " + e.what());
            }
        }
    }

    // llvmpipe's thread count decides its speed: fixed for the run and recorded (DESIGN.md section 3).
    if (!std::getenv("LP_NUM_THREADS"))
        setenv("LP_NUM_THREADS", std::to_string(std::max(1u, std::thread::hardware_concurrency())).c_str(), 1);
    auto context = createHeadlessContext(parseBackend(opts.get("--gl", "egl")));
    RunInfo info = currentRunInfo(context->renderer());  // before the run: its load average is the others'
    const bool quiet = opts.has("--quiet");
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

    if (!quiet && total > 0) {
        // The run's time, said before it starts: one frame of each technique (its first setting,
        // after one warm-up frame) on the first scene at the bench size, timed with the renderer's
        // construction, then scaled by the frames every setting of that technique runs on every
        // scene and light size. Settings of one technique that cost differently (an sm_size sweep)
        // make this rougher; the per-setting "left" below corrects it as the run goes.
        std::map<std::string, double> frameMs;
        double estimate = 0.0;
        for (const Setting& setting : settings) {
            auto it = frameMs.find(setting.technique);
            if (it == frameMs.end()) {
                const auto t0 = std::chrono::steady_clock::now();
                measureSetting(scenes.front(), labels.front(), spec.width, spec.height, spec.lightSizes.front(), setting, 1, 1,
                               nullptr, context->isSoftwareRasterizer());
                const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                it = frameMs.emplace(setting.technique, ms / 2.0).first;
            }
            estimate += it->second * double(spec.warmup + spec.frames);
        }
        estimate *= double(scenes.size() * spec.lightSizes.size()) / 1000.0;
        std::fprintf(stderr,
                     "bench: %zu setting(s) x %zu scene(s) x %zu light size(s) = %zu renders of %d frames at %dx%d: about "
                     "%.0f s (from one probe frame per technique), plus the references not yet in the cache\n",
                     settings.size(), scenes.size(), spec.lightSizes.size(), total, spec.warmup + spec.frames, spec.width,
                     spec.height, estimate);
    }

    std::vector<Measurement> rows;
    std::vector<nlohmann::json> references;
    size_t done = 0;
    for (size_t si = 0; si < scenes.size(); ++si) {
        for (const std::optional<float>& lightSize : spec.lightSizes) {
            CachedReference ref = cachedReference(scenes[si], spec.width, spec.height, lightSize, spec.reference, cacheDir,
                                                  context->renderer());
            references.push_back({{"scene", labels[si]},
                                  {"light_size", lightSize ? nlohmann::json(*lightSize) : nlohmann::json("scene")},
                                  {"path", ref.path},
                                  {"cache_key", ref.key},
                                  {"cache_key_fields", ref.fields},
                                  {"cache_hit", ref.hit}});
            if (!quiet)
                std::fprintf(stderr, "bench: reference %s for %s (light %s): %s\n", spec.reference.describe().c_str(),
                             labels[si].c_str(), lightSize ? fmt("%g", *lightSize).c_str() : "as in the scene",
                             ref.hit ? ("cached, key " + ref.key).c_str()
                                     : ("computed in " + fmt("%.1f", ref.computeMs / 1000.0) + " s, cached as " + ref.path).c_str());
            for (const Setting& setting : settings) {
                Measurement m = measureSetting(scenes[si], labels[si], spec.width, spec.height, lightSize, setting,
                                               spec.frames, spec.warmup, &ref.visibility, context->isSoftwareRasterizer());
                m.referenceKey = ref.key;
                m.referenceDesc = spec.reference.describe();
                m.visibility = Image();  // the rows keep numbers only
                m.image = Image();
                ++done;
                if (!quiet) {
                    double seconds = elapsed();
                    double left = seconds / double(done) * double(total - done);
                    std::fprintf(stderr, "bench: [%zu/%zu] %s %s %s: shadow %.2f ms, RMSE %.4f  (%.0f s elapsed, about %.0f s left)\n",
                                 done, total, labels[si].c_str(), setting.technique.c_str(),
                                 setting.describe().c_str(), m.shadowMs, m.all.rmse, seconds, left);
                }
                rows.push_back(std::move(m));
                if (glDebugState().errors > 0)
                    throw InternalError(std::to_string(glDebugState().errors) + " OpenGL error(s), the last: " +
                                        glDebugState().lastError);
            }
        }
    }

    info.seconds = elapsed();
    info.commandLine = {"shadowlab"};
    info.commandLine.insert(info.commandLine.end(), args.begin(), args.end());

    OutputSet outputs;
    auto write = [&](const std::string& path, const std::string& text) {
        std::ofstream out(outputs.stage(path), std::ios::binary);
        out << text;
        if (!out) throw InternalError("cannot write " + path);
    };
    if (!csv.empty()) {
        write(csv, toCsv(rows));
        // The CSV's sidecar: how it was made, and the reference cache keys.
        nlohmann::json side{{"spec", spec.file.empty() ? nlohmann::json(nullptr) : nlohmann::json(spec.file)},
                            {"name", spec.name},
                            {"program", {{"name", "shadowlab"}, {"version", info.version}}},
                            {"gl_renderer", info.glRenderer},
                            {"cpu", info.cpu},
                            {"lp_num_threads", info.lpNumThreads},
                            {"load_average", info.loadAverage},
                            {"date", info.date},
                            {"command_line", info.commandLine},
                            {"size", {spec.width, spec.height}},
                            {"frames", spec.frames},
                            {"warmup", spec.warmup},
                            {"reference", spec.reference.describe()},
                            {"references", references},
                            {"seconds", info.seconds}};
        write(csv + ".json", side.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    }
    for (const std::string& p : plots) writeBenchChart(rows, spec, outputs.stage(p), fs::path(p).extension().string());
    if (!latex.empty()) write(latex, benchLatexTable(spec, rows));
    if (!report.empty()) {
        std::string chart;
        for (const std::string& p : plots)
            if (chart.empty() || fs::path(p).extension() == ".png") chart = p;
        if (!chart.empty()) {
            fs::path base = fs::path(report).parent_path();
            chart = fs::relative(fs::absolute(chart), fs::absolute(base.empty() ? fs::path(".") : base)).string();
        }
        write(report, benchReportMarkdown(spec, rows, info, chart));
    }
    outputs.commit();
    if (!quiet) std::fprintf(stderr, "bench: %zu settings in %.1f s\n", rows.size(), info.seconds);
    return 0;
}

}  // namespace shadowlab
