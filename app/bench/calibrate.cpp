// `shadowlab bench --calibrate` (issue 25): the table `auto` predicts from. Every scene x light size
// is a case: its features (techniques/auto/auto.h, measured as `auto` measures them) and, per
// technique setting, the error against the ray-traced reference and shadow_ms split into the passes
// that scale with the frame and those that do not. Written as a versioned JSON file with the machine
// and the program that made it (assets/calibration/default.json is made by this command).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "scene/input_file.h"
#include "auto/auto.h"
#include "bench/bench.h"
#include "cli/cli.h"
#include "cli/provenance.h"
#include "cli/resource_limits.h"
#include "error.h"
#include "gl/context.h"
#include "graph/technique.h"

namespace fs = std::filesystem;

namespace shadowlab {

namespace {

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream s(text);
    std::string item;
    while (std::getline(s, item, ',')) out.push_back(item);
    return out;
}

// The settings `auto` chooses among unless --settings names others: every registered technique
// that renders by itself at its defaults (not the references, not auto itself).
std::vector<CalibrationSetting> defaultSettings() {
    std::vector<CalibrationSetting> out;
    for (const TechniqueDesc* d : allTechniques()) {
        if (d->choose || d->id == "reference" || d->id == "raytraced") continue;
        out.push_back({d->id, {}});
    }
    return out;
}

// "pcss", "pcf:pcf_kernel=9", "pcss:sm_size=512:filter_kernel=...": a technique and its --set pairs.
CalibrationSetting parseSetting(const std::string& text) {
    std::vector<std::string> parts;
    std::stringstream s(text);
    std::string item;
    while (std::getline(s, item, ':')) parts.push_back(item);
    if (parts.empty() || parts[0].empty())
        throw InputError("bench --calibrate: --settings: expected technique[:key=value...], got '" + text + "'");
    CalibrationSetting setting;
    const TechniqueDesc& desc = requireTechnique(parts[0], "bench --calibrate: --settings");
    if (desc.choose) throw InputError("bench --calibrate: --settings: '" + parts[0] + "' chooses techniques itself; name the techniques it may choose");
    setting.technique = desc.id;
    ParamValues check(desc);
    for (size_t i = 1; i < parts.size(); ++i) {
        const size_t eq = parts[i].find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("bench --calibrate: --settings " + text + ": expected key=value after ':', got '" + parts[i] + "'");
        const std::string key = parts[i].substr(0, eq), value = parts[i].substr(eq + 1);
        check.set(desc, key, value, "bench --calibrate: --settings " + text);
        setting.sets.push_back({key, value});
    }
    return setting;
}

// The shadow passes' time split by what their work scales with: a pass that creates a frame-size
// texture runs per pixel; the others (shadow maps, pyramids, light-space buffers) do not.
std::pair<double, double> splitShadowMs(const Measurement& m) {
    double fixed = 0.0, frame = 0.0;
    for (const auto& [name, ms] : m.passMs) {
        const size_t slash = name.find('/');
        if (slash == std::string::npos) continue;  // gbuffer, shade: not shadow passes
        const TechniqueDesc* desc = findTechnique(name.substr(0, slash));
        if (!desc) continue;
        bool perPixel = false;
        for (const PassDesc& p : desc->passes)
            if (p.name == name.substr(slash + 1))
                for (const ResourceDesc& r : p.creates)
                    if (r.size.kind == SizeRule::Kind::Frame) perPixel = true;
        (perPixel ? frame : fixed) += ms;
    }
    return {fixed, frame};
}

}  // namespace

int commandCalibrate(const std::vector<std::string>& args) {
    Options opts("bench --calibrate", args, 1,
                 {"--out", "--scenes", "--random", "--light-scales", "--settings", "--size", "--frames", "--warmup",
                  "--reference", "--cache", "--gl", "--max-memory-mb"},
                 {"--calibrate", "--quiet"});
    if (!opts.positional().empty()) throw InputError("bench --calibrate: unexpected argument '" + opts.positional()[0] + "'");
    const std::string out = opts.get("--out");
    if (out.empty()) throw InputError("bench --calibrate: --out FILE.json is required (the shipped one: assets/calibration/default.json)");
    checkPathName("bench --calibrate: --out", out);
    if (fs::path(out).extension() != ".json") throw InputError("bench --calibrate: --out: expected a .json file, got '" + out + "'");
    {
        const fs::path parent = fs::path(out).parent_path();
        std::error_code ec;
        if (!parent.empty() && !fs::is_directory(parent, ec))
            throw InputError("bench --calibrate: --out: folder '" + parent.string() + "' does not exist");
    }
    OutputPlan plan;
    plan.file("bench --calibrate: --out", out);
    plan.check();

    // The scenes: every scene of assets/ but `complex` (1.2 million triangles: minutes per case) and
    // the real-mesh scenes `mesh-*` (fetched at build time, assets/models/README.md: the shipped
    // calibration must not depend on them; --scenes names them), and --random N generated ones
    // (seeds 1000 ..; 40 by default).
    std::vector<std::string> names;
    if (opts.has("--scenes")) {
        names = splitList(opts.get("--scenes"));
        if (names.empty()) throw InputError("bench --calibrate: --scenes: expected a comma-separated list of scenes");
    } else {
        for (const std::string& s : listScenes())
            if (s != "complex" && s.rfind("mesh-", 0) != 0) names.push_back(s);
    }
    const int randoms = opts.getInt("--random", 40, 0, 1000);
    for (int i = 0; i < randoms; ++i) names.push_back("random:" + std::to_string(1000 + i));
    std::vector<Scene> scenes;
    for (const std::string& n : names) {
        try {
            scenes.push_back(loadScene(n));
        } catch (const InputError& e) {
            throw InputError("bench --calibrate: --scenes: cannot load the scene \"" + n + "\": " + e.what());
        }
    }
    std::vector<double> scales = {0.5, 1.0, 2.0};
    if (opts.has("--light-scales")) {
        scales.clear();
        for (const std::string& s : splitList(opts.get("--light-scales"))) {
            char* end = nullptr;
            const double v = std::strtod(s.c_str(), &end);
            if (s.empty() || *end != '\0' || !std::isfinite(v) || v <= 0.0 || v > 100.0)
                throw InputError("bench --calibrate: --light-scales: expected factors in (0, 100], comma-separated, got '" + s + "'");
            scales.push_back(v);
        }
        if (scales.empty()) throw InputError("bench --calibrate: --light-scales: expected at least one factor");
    }
    std::vector<CalibrationSetting> settings;
    if (opts.has("--settings")) {
        for (const std::string& s : splitList(opts.get("--settings"))) settings.push_back(parseSetting(s));
        if (settings.empty()) throw InputError("bench --calibrate: --settings: expected at least one setting");
    } else {
        settings = defaultSettings();
    }
    int width = 256, height = 256;
    if (opts.has("--size")) parseSize(opts.get("--size"), width, height);
    const int frames = opts.getInt("--frames", 3, 1, 1000), warmup = opts.getInt("--warmup", 1, 0, 100);
    const ReferenceSpec reference =
        parseReferenceSpec(opts.get("--reference", "raytraced:64"), "bench --calibrate: --reference");
    const std::string cacheDir = opts.has("--cache") ? opts.get("--cache") : defaultReferenceCacheDir();
    const bool quiet = opts.has("--quiet");

    if (!std::getenv("LP_NUM_THREADS"))
        setenv("LP_NUM_THREADS", std::to_string(std::max(1u, std::thread::hardware_concurrency())).c_str(), 1);
    auto context = createHeadlessContext(parseBackend(opts.get("--gl", "egl")));
    const RunInfo info = currentRunInfo(context->renderer());
    const auto start = std::chrono::steady_clock::now();

    Calibration cal;
    cal.program = "shadowlab " + info.version;
    cal.date = info.date;
    cal.glRenderer = info.glRenderer;
    cal.cpu = info.cpu;
    cal.lpNumThreads = info.lpNumThreads;
    cal.reference = reference.describe();
    cal.probeMs = machineProbeMs();
    cal.settings = settings;
    const size_t total = scenes.size() * scales.size();
    for (size_t si = 0; si < scenes.size(); ++si) {
        const Scene& scene = scenes[si];
        if (scene.lights.empty()) continue;
        for (double scale : scales) {
            const float base = scene.lights[0].isPoint() ? 1.0f : scene.lights[0].size;
            const float size = float(base * scale);
            Scene lit = scene;
            for (Light& l : lit.lights) {
                l.size = size;
                if (l.shape == LightShape::Point) l.shape = LightShape::Square;
            }
            CalibrationCase c;
            c.scene = names[si];
            c.lightSize = size;
            c.width = width;
            c.height = height;
            c.features = measureLightFeatures(lit, lit.lights[0], lit.camera, width, height, 0.0);
            const CachedReference ref =
                cachedReference(scene, width, height, size, reference, cacheDir, context->renderer());
            for (const CalibrationSetting& s : settings) {
                RenderOptions o;
                o.width = width;
                o.height = height;
                o.technique = s.technique;
                o.sets = s.sets;
                o.lightSize = size;
                checkRenderMemory(scene, o, opts);
                const Measurement m = measureSetting(scene, names[si], width, height, size, Setting{s.technique, s.sets},
                                                     frames, warmup, &ref.visibility, context->isSoftwareRasterizer());
                CalibrationResult r;
                r.rmse = m.all.rmse;
                r.rmsePenumbra = std::isfinite(m.penumbra.rmse) ? m.penumbra.rmse : 0.0;
                std::tie(r.fixedMs, r.frameMs) = splitShadowMs(m);
                c.results.push_back(r);
            }
            cal.cases.push_back(std::move(c));
            if (!quiet) {
                const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                std::fprintf(stderr, "bench --calibrate: [%zu/%zu] %s light %g: penumbra %.1f px, %.1f texels (%.0f s)\n",
                             cal.cases.size(), total, names[si].c_str(), double(size), cal.cases.back().features.penumbraPixels,
                             cal.cases.back().features.penumbraTexels, seconds);
            }
        }
    }
    if (cal.cases.empty()) throw InputError("bench --calibrate: no scene has a light, so nothing was measured");

    OutputSet outputs;
    {
        std::ofstream f(outputs.stage(out), std::ios::binary);
        f << cal.toJson().dump(1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
        if (!f) throw InternalError("cannot write " + out);
    }
    outputs.commit();
    if (!quiet)
        std::fprintf(stderr, "bench --calibrate: %zu cases x %zu settings written to %s\n", cal.cases.size(), settings.size(),
                     out.c_str());
    return 0;
}

}  // namespace shadowlab
