// Timed renders, their error against a cached reference, and the machine a run was made on
// (bench.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/bench.h"
#include "cli/provenance.h"
#include "error.h"
#include "gl/util.h"
#include "graph/renderer.h"
#include "scene/input_file.h"

namespace fs = std::filesystem;

namespace shadowlab {

namespace {

// FNV-1a over bytes: the cache key (stable across runs and builds, unlike std::hash).
uint64_t fnv1a(const std::string& bytes, uint64_t h = 1469598103934665603ull) {
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return h;
}

std::string hex16(uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

// A field of a JSON this program built itself (the renderer's stats): missing is a program error.
const nlohmann::json& own(const nlohmann::json& j, const char* key) {
    const auto it = j.find(key);
    if (it == j.end()) throw InternalError(std::string("the renderer's stats have no field '") + key + "'");
    return *it;
}

nlohmann::json lightJson(const Light& l) {
    auto v3 = [](const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    return {{"shape", lightShapeName(l.shape)}, {"position", v3(l.position)}, {"direction", v3(l.direction)},
            {"up", v3(l.up)},                   {"size", l.size},             {"casts_shadows", l.castsShadows}};
}

// Version of what a cached reference means: bump when the reference techniques change their output.
constexpr int kReferenceCacheFormat = 1;

}  // namespace

ReferenceSpec parseReferenceSpec(const std::string& text, const std::string& where) {
    ReferenceSpec r;
    size_t colon = text.find(':');
    r.technique = text.substr(0, colon);
    if (r.technique != "raytraced" && r.technique != "reference")
        throw InputError(where + ": expected raytraced[:rays] or reference[:samples], got '" + text + "'");
    r.count = r.technique == "raytraced" ? 256 : 1024;
    if (colon != std::string::npos) {
        std::string n = text.substr(colon + 1);
        char* end = nullptr;
        long v = std::strtol(n.c_str(), &end, 10);
        if (n.empty() || *end != '\0' || v < 1 || v > 65536)
            throw InputError(where + ": expected a whole number of " + r.countKey() + " in 1..65536 after ':', got '" + n +
                             "'");
        r.count = int(v);
    }
    return r;
}

std::string defaultReferenceCacheDir() {
    if (const char* d = std::getenv("SHADOWLAB_CACHE"); d && *d) return std::string(d) + "/references";
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::string(d) + "/shadowlab/references";
    if (const char* d = std::getenv("HOME"); d && *d) return std::string(d) + "/.cache/shadowlab/references";
    return ".shadowlab-cache/references";
}

CachedReference cachedReference(const Scene& scene, int width, int height, std::optional<float> lightSize,
                                const ReferenceSpec& reference, const std::string& cacheDir,
                                const std::string& glRenderer) {
    CachedReference out;
    nlohmann::json lights = nlohmann::json::array();
    for (Light l : scene.lights) {
        if (lightSize) {
            l.size = *lightSize;
            if (*lightSize == 0.0f) l.shape = LightShape::Point;
        }
        lights.push_back(lightJson(l));
    }
    out.fields = {{"format", kReferenceCacheFormat},
                  {"scene", scene.name},
                  {"scene_file_fnv1a", hex16(fnv1a(isRandomSceneName(scene.path) ? "generated " + scene.path
                                                                                   : readInputFile(scene.path, "scene file", kMaxSceneInputBytes)))},
                  {"camera",
                   {{"position", {scene.camera.position.x, scene.camera.position.y, scene.camera.position.z}},
                    {"target", {scene.camera.target.x, scene.camera.target.y, scene.camera.target.z}},
                    {"up", {scene.camera.up.x, scene.camera.up.y, scene.camera.up.z}},
                    {"fov_y_degrees", scene.camera.fovYDegrees}}},
                  {"size", {width, height}},
                  {"light_size", lightSize ? nlohmann::json(*lightSize) : nlohmann::json("scene")},
                  {"lights", lights},
                  {"reference", {{"technique", reference.technique}, {reference.countKey(), reference.count}}}};
    out.key = hex16(fnv1a(out.fields.dump()));
    out.path = cacheDir + "/" + scene.name + "-" + std::to_string(width) + "x" + std::to_string(height) + "-" +
               out.key + ".pfm";

    std::error_code ec;
    if (fs::exists(out.path, ec)) {
        try {
            // An entry is used only when its sidecar's key fields are the ones asked for and every
            // pixel is a finite visibility in [0, 1]: a NaN-filled entry was a hit with RMSE 0
            // (issue 24). Anything else is recomputed and replaced.
            const std::optional<nlohmann::json> sidecar = readSidecar(out.path);
            const auto key = sidecar ? sidecar->find("cache_key") : nlohmann::json::const_iterator();
            const auto fields = sidecar ? sidecar->find("cache_key_fields") : nlohmann::json::const_iterator();
            if (sidecar && key != sidecar->end() && key->is_string() && key->get<std::string>() == out.key &&
                fields != sidecar->end() && *fields == out.fields) {
                Image cached = readPFM(out.path);
                if (cached.width == width && cached.height == height && cached.channels == 1) {
                    const size_t bad = size_t(std::count_if(cached.data.begin(), cached.data.end(),
                                                            [](float v) { return !(v >= 0.0f && v <= 1.0f); }));
                    if (bad == 0) {
                        out.visibility = std::move(cached);
                        out.hit = true;
                        return out;
                    }
                    std::fprintf(stderr,
                                 "shadowlab: warning: ignoring the cached reference %s: %zu of its %zu pixels are NaN, "
                                 "infinite or outside [0, 1]; computing it again\n",
                                 out.path.c_str(), bad, cached.data.size());
                }
            }
        } catch (const InputError& e) {
            std::fprintf(stderr, "shadowlab: warning: ignoring the cached reference %s: %s\n", out.path.c_str(), e.what());
        }
    }

    // Not cached (or stale): compute it, frame 0, and store it with its key.
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.technique = reference.technique;
    options.sets = {{reference.countKey(), std::to_string(reference.count)}};
    options.lightSize = lightSize;
    options.reuse = false;
    auto t0 = std::chrono::steady_clock::now();
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"visibility"});
    out.visibility = renderer.visibility();
    out.computeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    RenderProvenance record = renderProvenance(scene, renderer, width, height, {out.computeMs}, glRenderer);
    nlohmann::json sidecar = provenanceOf(record, "reference");
    sidecar["cache_key"] = out.key;
    sidecar["cache_key_fields"] = out.fields;
    fs::create_directories(cacheDir, ec);
    if (ec) throw InputError("reference cache: cannot create the folder '" + cacheDir + "': " + ec.message());
    // A cache entry that is no regular file (a FIFO, a folder) is the cache's own debris: replaced.
    for (const std::string& p : {out.path, sidecarPath(out.path)}) {
        const fs::file_status status = fs::symlink_status(p, ec);
        if (fs::exists(status) && !fs::is_regular_file(status)) fs::remove_all(p, ec);
    }
    OutputSet outputs;
    writePfmWithSidecar(outputs, out.path, out.visibility, sidecar);
    outputs.commit();
    return out;
}

std::string Setting::describe() const {
    if (sets.empty()) return "defaults";
    std::string out;
    for (const auto& [k, v] : sets) out += (out.empty() ? "" : " ") + k + "=" + v;
    return out;
}

Measurement measureSetting(const Scene& scene, const std::string& sceneName, int width, int height,
                           std::optional<float> lightSize, const Setting& setting, int frames, int warmup,
                           const Image* reference, bool cpuClock) {
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.technique = setting.technique;
    options.sets = setting.sets;
    options.lightSize = lightSize;
    options.cpuClock = cpuClock;
    options.reuse = false;  // every needed pass runs every frame: each frame is a timed run of each pass
    Renderer renderer(scene, options);
    const std::set<std::string> requested = {"image", "visibility"};
    std::vector<double> frameMs;
    for (int f = 0; f < warmup + frames; ++f) {
        glFinish();
        auto t0 = std::chrono::steady_clock::now();
        renderer.renderFrame(f, requested);
        glFinish();
        double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (f >= warmup) frameMs.push_back(ms);
    }
    const nlohmann::json stats = renderer.stats(frameMs, warmup, warmup);

    Measurement m;
    m.scene = sceneName;
    m.setting = setting;
    m.width = width;
    m.height = height;
    m.frames = frames;
    m.warmup = warmup;
    m.clock = own(stats, "clock").get<std::string>();
    m.shadowMs = own(stats, "shadow_ms").get<double>();
    m.fixedMs = own(stats, "fixed_ms").get<double>();
    m.totalMs = own(stats, "cost_ms").get<double>();
    for (const auto& p : own(stats, "passes")) {
        if (!own(p, "needed").get<bool>() || own(p, "runs").get<int>() == 0) continue;
        // "L0/pcf/filter" -> "pcf/filter": per pass name, summed over the lights.
        std::string name = own(p, "name").get<std::string>();
        const std::string group = own(p, "group").get<std::string>();
        if (group != "frame" && name.rfind(group + "/", 0) == 0) name = name.substr(group.size() + 1);
        m.passMs[name] += own(p, "median_ms").get<double>();
    }
    const auto lights = renderer.lights();
    m.lights = nlohmann::json::array();
    for (const LightState* l : lights) {
        nlohmann::json lj = lightJson(l->light);
        lj["name"] = l->light.name;
        lj["technique"] = l->desc->id;
        lj["parameters"] = l->params.toJson(*l->desc);
        m.lights.push_back(lj);
    }
    if (!lights.empty()) {
        m.lightSize = lights[0]->light.size;
        m.techniqueRan = lights[0]->desc->id;
        m.parameters = lights[0]->params.toJson(*lights[0]->desc);
    }
    for (const auto& [name, r] : renderer.pool().all())
        if (name.rfind("frame/", 0) != 0) m.techniqueBytes += r->bytes();
    m.memoryBytes = own(stats, "memory_bytes").get<size_t>();
    for (const auto& l : own(stats, "lights"))
        for (const auto& k : own(l, "kernel_caps")) {
            const double f = own(k, "clamped_fraction").get<double>();
            m.kernelClampedFraction = std::isnan(m.kernelClampedFraction) ? f : std::max(m.kernelClampedFraction, f);
        }
    const nlohmann::json& statLights = own(stats, "lights");
    const auto counters = statLights.empty() ? statLights.end() : statLights.front().find("counters");
    if (!statLights.empty() && counters != statLights.front().end() && counters->is_object())
        for (const auto& [counter, fields] : counters->items())
            if (fields.is_object())
                for (const auto& [field, v] : fields.items())
                    if (v.is_number()) m.counters[counter + "." + field] = v.get<double>();
    m.visibility = renderer.visibility();
    m.image = renderer.image();
    m.ids = renderer.ids();
    if (reference && reference->width > 0) {
        m.all = computeMetrics(m.visibility, *reference);
        std::vector<uint8_t> mask = penumbraMask(*reference);
        m.penumbra = computeMetrics(m.visibility, *reference, &mask);
    }
    return m;
}

RunInfo currentRunInfo(const std::string& glRenderer) {
    RunInfo info;
    info.glRenderer = glRenderer;
    info.version = programVersion();
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    int cores = 0;
    while (std::getline(cpuinfo, line)) {
        if (line.rfind("model name", 0) == 0) {
            ++cores;
            if (info.cpu.empty()) {
                size_t colon = line.find(':');
                info.cpu = colon == std::string::npos ? line : line.substr(colon + 2);
            }
        }
    }
    if (cores) info.cpu += " (" + std::to_string(cores) + " logical cores)";
    std::ifstream loadavg("/proc/loadavg");
    std::string l1, l5, l15;
    if (loadavg >> l1 >> l5 >> l15) info.loadAverage = l1 + " " + l5 + " " + l15;
    const char* lp = std::getenv("LP_NUM_THREADS");
    info.lpNumThreads = lp ? lp : "unset";
    std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    info.date = date;
    return info;
}

}  // namespace shadowlab
