#include "cli/cli.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>

#include "cli/provenance.h"
#include "cli/resource_limits.h"
#include "error.h"
#include "gl/context.h"
#include "graph/renderer.h"
#include "graph/technique.h"
#include "image/image.h"
#include "image/metrics.h"
#include "lesson/cmd_lesson.h"
#include "scene/scene.h"
#include "views.h"

namespace fs = std::filesystem;

namespace shadowlab {

int commandViz(const std::vector<std::string>& args);  // app/cli/cmd_viz.cpp

// ---- option parsing ----------------------------------------------------------------------------------
Options::Options(const std::string& command, const std::vector<std::string>& args, size_t first,
                 const std::vector<std::string>& valued, const std::vector<std::string>& bare)
    : command_(command) {
    auto known = [](const std::vector<std::string>& list, const std::string& a) {
        return std::find(list.begin(), list.end(), a) != list.end();
    };
    for (size_t i = first; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a.rfind("--", 0) == 0) {
            if (known(valued, a)) {
                if (i + 1 >= args.size()) throw InputError(command + ": " + a + " expects a value");
                // The next word is one of the command's options: the value is missing (`--set --out
                // o.png` took "--out" as the value and then called o.png an unexpected argument).
                if (known(valued, args[i + 1]) || known(bare, args[i + 1]))
                    throw InputError(command + ": " + a + " expects a value, got the option " + args[i + 1]);
                values_.push_back({a, args[++i]});
            } else if (known(bare, a)) {
                values_.push_back({a, ""});
            } else {
                std::string list;
                for (const auto& v : valued) list += " " + v;
                for (const auto& b : bare) list += " " + b;
                throw InputError(command + ": unknown option " + a + " (expected one of:" + list + ")");
            }
        } else {
            positional_.push_back(a);
        }
    }
}

bool Options::has(const std::string& flag) const {
    for (const auto& [f, v] : values_)
        if (f == flag) return true;
    return false;
}

// A flag read as one value may be given once: a repeated flag is an error, not "the last wins"
// (flags meant to repeat, like --set, are read with all()).
std::string Options::get(const std::string& flag, const std::string& fallback) const {
    const std::string* result = nullptr;
    for (const auto& [f, v] : values_) {
        if (f != flag) continue;
        if (result)
            throw InputError(command_ + ": " + flag + " given more than once ('" + *result + "' and '" + v +
                             "'); give it once");
        result = &v;
    }
    return result ? *result : fallback;
}

std::vector<std::string> Options::all(const std::string& flag) const {
    std::vector<std::string> out;
    for (const auto& [f, v] : values_)
        if (f == flag) out.push_back(v);
    return out;
}

int Options::getInt(const std::string& flag, int fallback, int lo, int hi) const {
    if (!has(flag)) return fallback;
    std::string text = get(flag);
    char* end = nullptr;
    long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < lo || v > hi)
        throw InputError(command_ + ": " + flag + ": expected a whole number in " + std::to_string(lo) + ".." +
                         std::to_string(hi) + ", got '" + text + "'");
    return int(v);
}

float Options::getFloat(const std::string& flag, float fallback, float lo, float hi) const {
    if (!has(flag)) return fallback;
    std::string text = get(flag);
    char* end = nullptr;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
        char range[64];
        std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
        throw InputError(command_ + ": " + flag + ": expected a finite number in " + range + ", got '" + text + "'");
    }
    return float(v);
}

void parseSize(const std::string& text, int& width, int& height) {
    unsigned long w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%lu%c%lu%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 1 || h < 1 || w > 8192 ||
        h > 8192 || text.find('-') != std::string::npos)
        throw InputError("--size: expected WxH with W and H whole numbers in 1..8192, got '" + text + "'");
    width = int(w);
    height = int(h);
}

// ---- helpers -----------------------------------------------------------------------------------------
namespace {

// An output path must be writable where it is: its folder has to exist (nothing is created
// half-way, and nothing is written before the whole command succeeded).
void checkOutputPath(const std::string& flag, const std::string& path) {
    if (path.empty()) throw InputError(flag + ": expected a file path");
    // A plan of one file: its folder exists and takes the file, the path is no folder or device.
    OutputPlan plan;
    plan.file(flag, path);
    plan.check();
}

void checkExtension(const std::string& flag, const std::string& path, const std::string& ext) {
    if (fs::path(path).extension() != ext) throw InputError(flag + ": expected a " + ext + " file, got '" + path + "'");
}

void writeText(OutputSet& outputs, const std::string& path, const std::string& text) {
    std::ofstream out(outputs.stage(path), std::ios::binary);
    out << text;
    if (!out) throw InternalError("cannot write " + path);
}

std::unique_ptr<GLContext> makeContext(const Options& opts) {
    GLBackend backend = parseBackend(opts.get("--gl", "egl"));
    return createHeadlessContext(backend);
}

void failOnGLErrors() {
    if (glDebugState().errors > 0)
        throw InternalError(std::to_string(glDebugState().errors) + " OpenGL error(s), the last: " +
                            glDebugState().lastError);
}

// ---- list ----------------------------------------------------------------------------------------
int commandList(const std::vector<std::string>& args) {
    Options opts("list", args, 1, {}, {"--json"});
    if (!opts.positional().empty()) throw InputError("list: unexpected argument '" + opts.positional()[0] + "'");
    nlohmann::json j;
    j["techniques"] = nlohmann::json::array();
    for (const TechniqueDesc* d : allTechniques()) j["techniques"].push_back(describeTechnique(*d));
    j["scenes"] = nlohmann::json::array();
    for (const std::string& name : listScenes()) {
        nlohmann::json s{{"name", name}};
        try {
            Scene scene = loadScene(name);
            s["description"] = scene.description;
            s["lights"] = scene.lights.size();
            s["objects"] = scene.objects.size();
        } catch (const InputError& e) {
            s["error"] = e.what();
        }
        j["scenes"].push_back(s);
    }
    j["lessons"] = describeLessons();
    j["views"] = nlohmann::json::array();
    for (const ViewInfo& v : listViews())
        j["views"].push_back({{"name", v.name}, {"doc", v.doc}, {"applies_to", v.appliesTo}, {"export", v.exportExtension}});
    if (opts.has("--json")) {
        std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
        return 0;
    }
    std::cout << "Techniques\n";
    for (const TechniqueDesc* d : allTechniques()) {
        std::cout << "  " << d->id << "  " << d->name << "\n    " << d->citation << "\n    " << d->summary << "\n";
        for (const ParamDesc& p : d->params) {
            char line[512];
            if (p.type == ParamDesc::Type::Enum && !p.choices.empty()) {  // by name: the values a --set takes
                std::string choices;
                for (const std::string& c : p.choices) choices += (choices.empty() ? "" : " | ") + c;
                const size_t d = std::min(p.choices.size() - 1, size_t(std::max(0.0, p.defaultValue)));
                std::snprintf(line, sizeof line, "      %-14s %-4s %-5s default %-8s choices %s", p.key.c_str(),
                              p.symbol.c_str(), paramTypeName(p.type), p.choices[d].c_str(), choices.c_str());
            } else {
                std::snprintf(line, sizeof line, "      %-14s %-4s %-5s default %-8g range [%g, %g] %s", p.key.c_str(),
                              p.symbol.c_str(), paramTypeName(p.type), p.defaultValue, p.minValue, p.maxValue,
                              p.unit.c_str());
            }
            std::cout << line << "\n        " << p.doc << "\n";
        }
    }
    std::cout << "Scenes\n";
    for (const auto& s : j["scenes"])
        std::cout << "  " << s["name"].get<std::string>() << "  "
                  << (s.contains("description") ? s["description"].get<std::string>() : s.value("error", "")) << "\n";
    std::cout << "Lessons\n";
    for (const auto& l : j["lessons"])
        std::cout << "  " << l["name"].get<std::string>() << "  "
                  << (l.contains("title") ? l["title"].get<std::string>() + " (" + std::to_string(l["steps"].get<int>()) + " steps)"
                                          : l["error"].get<std::string>())
                  << "\n";
    std::cout << "Views (shadowlab viz --view V)\n";
    for (const auto& v : j["views"])
        std::cout << "  " << v["name"].get<std::string>() << "  " << v["doc"].get<std::string>() << "\n    applies to "
                  << v["applies_to"].get<std::string>() << "\n";
    return 0;
}

// ---- render and reference --------------------------------------------------------------------------
struct RenderJob {
    std::string scene;
    RenderOptions options;
    int frames = 1;
    std::string out, visibility, positions, ids, stats, internals;
    std::optional<glm::ivec2> pixel;
    std::string gl = "egl";
    bool checkReuse = false;
};

int runRender(const RenderJob& job, const Options& opts) {
    // Everything the user gave is checked before any pixel is rendered.
    Scene scene = loadScene(job.scene, sceneLimitsFrom(opts));
    printSceneWarnings(scene);
    checkRenderMemory(scene, job.options, opts);
    // The output plan: every file this render writes, the PFMs' sidecars included, and the folder
    // --internals fills, checked together before any pixel is rendered.
    OutputPlan plan;
    plan.file("--out", job.out);
    plan.fileWithSidecar("--visibility", job.visibility);
    plan.fileWithSidecar("--positions", job.positions);
    plan.fileWithSidecar("--ids", job.ids);
    plan.file("--stats", job.stats);
    plan.folder("--internals", job.internals);
    plan.check();
    if (!job.out.empty()) checkExtension("--out", job.out, ".png");
    for (const auto& [flag, path] : {std::pair<std::string, std::string>{"--visibility", job.visibility},
                                     {"--positions", job.positions},
                                     {"--ids", job.ids}})
        if (!path.empty()) checkExtension(flag, path, ".pfm");
    if (!job.stats.empty()) checkExtension("--stats", job.stats, ".json");
    if (job.pixel && (job.pixel->x < 0 || job.pixel->y < 0 || job.pixel->x >= job.options.width ||
                      job.pixel->y >= job.options.height))
        throw InputError("--pixel: expected x,y inside the " + std::to_string(job.options.width) + "x" +
                         std::to_string(job.options.height) + " image, got " + std::to_string(job.pixel->x) + "," +
                         std::to_string(job.pixel->y));

    auto context = makeContext(opts);
    RenderOptions options = job.options;
    options.cpuClock = context->isSoftwareRasterizer();
    Renderer renderer(scene, options);
    // A parameter that does not apply in this configuration is said, not silently ignored.
    for (const LightState* l : renderer.lights())
        for (const auto& [key, reason] : l->params.inapplicable(*l->desc))
            for (const auto& [setKey, value] : options.sets)
                if (setKey == key)
                    std::fprintf(stderr, "shadowlab: warning: --set %s=%s has no effect on %s (L%d): %s\n", key.c_str(),
                                 value.c_str(), l->desc->id.c_str(), l->index, reason.c_str());

    std::set<std::string> requested;
    if (!job.out.empty()) requested.insert("image");
    if (!job.visibility.empty() || job.pixel) requested.insert("visibility");
    if (!job.positions.empty() || !job.ids.empty()) requested.insert("gbuffer");
    if (!job.internals.empty() || job.pixel) {
        std::set<std::string> internals = renderer.internalRequests(job.pixel.has_value());
        requested.insert(internals.begin(), internals.end());
    }
    if (requested.empty()) requested = {"image", "visibility"};

    // Frame 0 warms up (programs compile, buffers allocate); frames 1..N are timed.
    std::vector<double> frameMs;
    int total = job.frames > 1 || !job.stats.empty() || job.checkReuse ? job.frames + 1 : 1;
    auto timedFrame = [&](int f) {
        glFinish();
        auto t0 = std::chrono::steady_clock::now();
        renderer.renderFrame(f, requested);
        glFinish();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    for (int f = 0; f < total; ++f) {
        double ms = timedFrame(f);
        if (f > 0 || total == 1) frameMs.push_back(ms);
        if (job.checkReuse && f > 0) {
            // Every pass the graph reused must give the same outputs when it runs again.
            std::vector<std::string> differ = renderer.checkReuse();
            if (!differ.empty()) {
                std::string list;
                for (const std::string& d : differ) list += " " + d;
                throw InternalError("--check-reuse: frame " + std::to_string(f) +
                                    ": re-running the needed passes changed:" + list +
                                    " (a pass reads something it does not declare)");
            }
        }
    }
    // cost_ms needs a timed run of every needed pass: on a static scene with reuse, passes ran only in
    // the warm-up frame (with compilation), so time them again (without counting runs or reuses).
    int costFrom = total > 1 ? 1 : 0;
    if (!job.stats.empty() && !renderer.costMeasuredSince(costFrom)) {
        costFrom = total;
        renderer.measureCost(total, std::max(1, std::min(job.frames, 3)));
    }

    // Clamped kernels said (issue 17): a technique whose capped kernel truncated over 1% of the
    // pixels that computed it says so, with the cap to raise.
    for (const Renderer::KernelCapReport& k : renderer.kernelCapReports()) {
        if (k.fraction() > 0.01)
            std::fprintf(stderr,
                         "shadowlab: warning: %s (L%d): %s clamped the kernel of %zu of %zu pixels (%.1f%%; cap %g, widest "
                         "asked %.4g): their penumbra is truncated; raise --set %s\n",
                         k.technique.c_str(), k.light, k.name.c_str(), k.count.clamped, k.count.pixels, 100.0 * k.fraction(),
                         k.count.cap, k.count.largest, k.name.c_str());
    }

    OutputSet outputs;
    const RenderProvenance provenance =
        renderProvenance(scene, renderer, options.width, options.height, frameMs, context->renderer());
    if (!job.out.empty()) writePNG(outputs.stage(job.out), renderer.image());
    if (!job.visibility.empty())
        writeRenderPfm(outputs, job.visibility, renderer.visibility(), provenance, visibilityMeaning(options.technique));
    if (!job.positions.empty()) writeRenderPfm(outputs, job.positions, renderer.positions(), provenance, "positions");
    if (!job.ids.empty()) writeRenderPfm(outputs, job.ids, renderer.ids(), provenance, "ids");
    if (!job.internals.empty()) {
        fs::create_directories(job.internals);
        InternalWriter writer(job.internals, outputs);
        writer.setProvenance(provenanceOf(provenance, "internal"));
        renderer.writeInternals(writer, job.pixel);
    }
    if (!job.stats.empty()) {
        nlohmann::json stats = renderer.stats(frameMs, total > 1 ? 1 : 0, costFrom);
        stats["gl_renderer"] = context->renderer();
        if (job.checkReuse) stats["check_reuse"] = "passed";
        writeText(outputs, job.stats, stats.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    }
    failOnGLErrors();
    outputs.commit();
    return 0;
}

std::optional<glm::ivec2> parsePixel(const std::string& text) {
    // Whole numbers of at most 4 digits each (an image side is at most 8192): "%d" of sscanf wrapped
    // 99999999999 into 1215752191 and the message then named a pixel nobody gave.
    auto whole = [](const std::string& part, int& out) {
        if (part.empty() || part.size() > 4 || !std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; }))
            return false;
        out = std::stoi(part);
        return true;
    };
    const size_t comma = text.find(',');
    int x = 0, y = 0;
    if (comma == std::string::npos || !whole(text.substr(0, comma), x) || !whole(text.substr(comma + 1), y))
        throw InputError("--pixel: expected x,y (whole numbers from 0 to 8191, y counted from the top), got '" + text + "'");
    return glm::ivec2(x, y);
}

std::vector<std::pair<std::string, std::string>> parseSets(const std::vector<std::string>& sets) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string& s : sets) {
        size_t eq = s.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("--set: expected key=value, got '" + s + "'");
        out.push_back({s.substr(0, eq), s.substr(eq + 1)});
    }
    return out;
}

int commandRender(const std::vector<std::string>& args) {
    Options opts("render", args, 1,
                 {"--scene", "--technique", "--set", "--size", "--out", "--visibility", "--positions", "--ids",
                  "--stats", "--frames", "--internals", "--pixel", "--light-size", "--gl", "--max-triangles",
                  "--max-memory-mb"},
                 {"--no-reuse", "--check-reuse"});
    if (!opts.positional().empty()) throw InputError("render: unexpected argument '" + opts.positional()[0] + "'");
    if (!opts.has("--scene")) throw InputError("render: --scene is required (a scene name or a .json path)");
    RenderJob job;
    job.scene = opts.get("--scene");
    job.options.technique = opts.get("--technique");
    if (!job.options.technique.empty()) requireTechnique(job.options.technique, "--technique");
    job.options.sets = parseSets(opts.all("--set"));
    if (opts.has("--size")) parseSize(opts.get("--size"), job.options.width, job.options.height);
    if (opts.has("--light-size")) job.options.lightSize = opts.getFloat("--light-size", 0.0f, 0.0f, 1e6f);
    job.frames = opts.getInt("--frames", 1, 1, 100000);
    job.options.reuse = !opts.has("--no-reuse");
    job.checkReuse = opts.has("--check-reuse");
    if (job.checkReuse && !job.options.reuse)
        throw InputError("render: --check-reuse checks the outputs the graph reuses; it cannot be combined with --no-reuse");
    job.out = opts.get("--out");
    job.visibility = opts.get("--visibility");
    job.positions = opts.get("--positions");
    job.ids = opts.get("--ids");
    job.stats = opts.get("--stats");
    job.internals = opts.get("--internals");
    if (opts.has("--pixel")) job.pixel = parsePixel(opts.get("--pixel"));
    return runRender(job, opts);
}

int commandReference(const std::vector<std::string>& args) {
    Options opts("reference", args, 1,
                 {"--scene", "--samples", "--rays", "--out", "--size", "--light-size", "--set", "--gl", "--stats",
                  "--max-triangles", "--max-memory-mb"},
                 {});
    if (!opts.positional().empty()) throw InputError("reference: unexpected argument '" + opts.positional()[0] + "'");
    if (!opts.has("--scene")) throw InputError("reference: --scene is required");
    if (!opts.has("--out")) throw InputError("reference: --out v.pfm is required");
    if (opts.has("--samples") && opts.has("--rays"))
        throw InputError("reference: give --samples N (shadow-map reference) or --rays M (ray traced), not both");
    RenderJob job;
    job.scene = opts.get("--scene");
    job.options.sets = parseSets(opts.all("--set"));
    if (opts.has("--rays")) {
        job.options.technique = "raytraced";
        job.options.sets.push_back({"rays", std::to_string(opts.getInt("--rays", 256, 1, 65536))});
    } else {
        job.options.technique = "reference";
        if (opts.has("--samples"))
            job.options.sets.push_back({"samples", std::to_string(opts.getInt("--samples", 1024, 1, 65536))});
    }
    if (opts.has("--size")) parseSize(opts.get("--size"), job.options.width, job.options.height);
    if (opts.has("--light-size")) job.options.lightSize = opts.getFloat("--light-size", 0.0f, 0.0f, 1e6f);
    job.visibility = opts.get("--out");
    job.stats = opts.get("--stats");
    return runRender(job, opts);
}

// ---- compare ----------------------------------------------------------------------------------------
nlohmann::json metricsJson(const Metrics& m) {
    return {{"rmse", m.rmse},
            {"max_abs", m.maxAbs},
            {"psnr", std::isinf(m.psnr) ? nlohmann::json("inf") : nlohmann::json(m.psnr)},
            {"ssim", m.ssim},
            {"pixels", m.pixels}};
}

int commandCompare(const std::vector<std::string>& args) {
    Options opts("compare", args, 1, {"--mask", "--heatmap"}, {"--json", "--strict"});
    if (opts.positional().size() != 2)
        throw InputError("compare: expected two PFM files, A.pfm (tested) and B.pfm (reference), got " +
                         std::to_string(opts.positional().size()));
    std::string mask = opts.get("--mask", "none");
    if (mask != "none" && mask != "penumbra")
        throw InputError("compare: --mask: expected penumbra, got '" + mask + "'");
    std::string heatmap = opts.get("--heatmap");
    if (!heatmap.empty()) {
        checkOutputPath("--heatmap", heatmap);
        checkExtension("--heatmap", heatmap, ".png");
    }
    Image a = readPFM(opts.positional()[0]);
    Image b = readPFM(opts.positional()[1]);
    const nlohmann::json provenance =
        checkComparedProvenance(opts.positional()[0], opts.positional()[1], opts.has("--strict"));
    if (a.channels != 1 || b.channels != 1)
        throw InputError("compare: expected 1-channel visibility PFMs (Pf), got " + std::to_string(a.channels) + " and " +
                         std::to_string(b.channels) + " channels");
    if (a.width != b.width || a.height != b.height)
        throw InputError("compare: images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                         " (" + opts.positional()[0] + ") vs " + std::to_string(b.width) + "x" +
                         std::to_string(b.height) + " (" + opts.positional()[1] + ")");
    Metrics all = computeMetrics(a, b);
    std::vector<uint8_t> penumbra = penumbraMask(b);
    Metrics pen = computeMetrics(a, b, &penumbra);
    // No pixel finite on both sides is nothing measured, not a perfect match (an all-NaN PFM
    // compared as "pixels 0 RMSE 0 PSNR inf SSIM 1", exit 0).
    const Metrics& measured = mask == "penumbra" ? pen : all;
    if (measured.pixels == 0) {
        auto finite = [](const Image& image) {
            return std::to_string(std::count_if(image.data.begin(), image.data.end(), [](float v) { return std::isfinite(v); }));
        };
        throw InputError("compare: " + opts.positional()[0] + " and " + opts.positional()[1] + " have no pixel " +
                         (mask == "penumbra" ? std::string("in the penumbra of B ") : std::string()) +
                         "where both are finite (finite pixels: " + finite(a) + " and " + finite(b) + " of " +
                         std::to_string(a.pixelCount()) + "), expected at least one to compare");
    }
    OutputSet outputs;
    if (!heatmap.empty()) writePNG(outputs.stage(heatmap), errorHeatmap(a, b));
    nlohmann::json j{{"a", opts.positional()[0]}, {"b", opts.positional()[1]}, {"all", metricsJson(all)},
                     {"penumbra", metricsJson(pen)}};
    j["mask"] = mask;
    const Metrics& primary = mask == "penumbra" ? pen : all;
    j["rmse"] = primary.rmse;
    j["max_abs"] = primary.maxAbs;
    j["psnr"] = metricsJson(primary)["psnr"];
    j["ssim"] = primary.ssim;
    j["pixels"] = primary.pixels;
    if (!provenance.is_null()) j["provenance"] = provenance;
    outputs.commit();
    if (opts.has("--json")) {
        std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
        return 0;
    }
    auto line = [](const char* label, const Metrics& m) {
        std::printf("%-9s pixels %8zu  RMSE %.6f  max %.6f  PSNR %s dB  SSIM %.6f\n", label, m.pixels, m.rmse, m.maxAbs,
                    std::isinf(m.psnr) ? "inf" : std::to_string(m.psnr).c_str(), m.ssim);
    };
    if (mask != "penumbra") line("all", all);
    line("penumbra", pen);
    return 0;
}

// ---- scene --------------------------------------------------------------------------------------------
int commandScene(const std::vector<std::string>& args) {
    Options opts("scene", args, 1, {"--scene", "--dump-triangles", "--time", "--max-triangles"}, {});
    if (!opts.positional().empty()) throw InputError("scene: unexpected argument '" + opts.positional()[0] + "'");
    if (!opts.has("--scene")) throw InputError("scene: --scene is required");
    if (!opts.has("--dump-triangles")) throw InputError("scene: --dump-triangles out.obj is required");
    std::string out = opts.get("--dump-triangles");
    checkOutputPath("--dump-triangles", out);
    checkExtension("--dump-triangles", out, ".obj");
    float t = opts.getFloat("--time", 0.0f, 0.0f, 1e6f);
    Scene scene = loadScene(opts.get("--scene"), sceneLimitsFrom(opts));
    printSceneWarnings(scene);
    OutputSet outputs;
    writeTrianglesOBJ(scene, t, outputs.stage(out));
    outputs.commit();
    return 0;
}

void printUsage() {
    std::puts(
        "shadowlab: real-time soft shadows, taught\n"
        "  shadowlab                         the window; with no display: renders the default scene into ./shadowlab-output\n"
        "  shadowlab window [--scene S|file.gltf] [--technique T] [--size WxH] [--ui-scale F] [--no-reduce]\n"
        "                   [--lesson L] [--present] [--screenshot f.png --frames N] [--script steps.txt]\n"
        "                   [--report frames.json]   (F1: keys; F5: presentation mode)\n"
        "  shadowlab list [--json]           techniques with parameters, scenes, lessons\n"
        "  shadowlab render --scene S [--technique T] [--set k=v]... [--size WxH] [--out img.png]\n"
        "                   [--visibility v.pfm] [--positions p.pfm] [--ids i.pfm] [--stats s.json]\n"
        "                   [--frames N] [--no-reuse] [--check-reuse] [--internals DIR] [--pixel x,y] [--light-size S]\n"
        "                   [--gl egl|osmesa] [--max-triangles N] [--max-memory-mb M]\n"
        "  shadowlab reference --scene S [--samples N | --rays M] --out v.pfm [--size WxH] [--light-size S]\n"
        "  shadowlab compare A.pfm B.pfm [--mask penumbra] [--json] [--heatmap err.png] [--strict]\n"
        "  shadowlab scene --scene S --dump-triangles out.obj [--time t] [--max-triangles N]\n"
        "  shadowlab lesson L --headless --out DIR [--size WxH] | --check   a lesson as PNGs + HTML handout\n"
        "  shadowlab bench (--spec NAME|file.json | --scenes A,B --techniques T1,T2 [--sweep key=a:b:n|key=v1,v2]...)\n"
        "                  [--light-sizes s1,s2] [--size WxH] [--frames N] [--warmup N] [--reference raytraced:M|reference:N]\n"
        "                  [--cache DIR] [--csv out.csv] [--plot p.png|p.svg|p.pdf]... [--latex t.tex] [--report r.md]\n"
        "                  [--error rmse|1-ssim] [--max-settings N] [--quiet]\n"
        "  shadowlab figure --spec fig.json --out fig.png|fig.pdf | --remake fig.png.json [--out fig.png]\n"
        "  shadowlab viz --view V --scene S [--technique T] [--set k=v]... [--pixel x,y] [--internal NAME] [--light N]\n"
        "                [--size WxH] [--view-size WxH] --out view.png [--export data.vtp|.vti] [--max-memory-mb MB]\n"
        "                [--reference v.pfm | --reference-samples N]"
        " [--rays M] [--azimuth deg] [--elevation deg] [--zoom z] [--json]");
}

}  // namespace

int runCommandLine(const std::vector<std::string>& args) {
    try {
        rememberCommandLine(args);
        removeStagedOutputsOnSignals();  // SIGINT/SIGTERM delete staged temporaries
        if (args.empty()) return runDefault();
        const std::string& command = args[0];
        if (command == "list") return commandList(args);
        if (command == "render") return commandRender(args);
        if (command == "reference") return commandReference(args);
        if (command == "compare") return commandCompare(args);
        if (command == "scene") return commandScene(args);
        if (command == "lesson") return commandLesson(args);
        if (command == "bench") return commandBench(args);
        if (command == "figure") return commandFigure(args);
        if (command == "viz") return commandViz(args);
        if (command == "window") return runWindow(std::vector<std::string>(args.begin() + 1, args.end()));
        if (command == "help" || command == "--help" || command == "-h") {
            printUsage();
            return 0;
        }
        throw InputError("unknown command '" + command +
                         "' (expected one of: list, render, reference, compare, scene, bench, figure, viz, lesson, window, help)");
    } catch (const InputError& e) {
        std::fprintf(stderr, "shadowlab: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "shadowlab: internal error: %s\n", e.what());
        return 1;
    }
}

}  // namespace shadowlab
