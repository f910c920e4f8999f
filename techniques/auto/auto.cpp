// `auto` (issue 25; README.md beside this file): the features, the calibration file and the choice.
#include "auto/auto.h"
#include "auto/trial.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include "error.h"
#include "scene/json_reader.h"
#include "scene/light_view.h"
#include "visibility/raytracer.h"

namespace shadowlab {

namespace {

std::string fmt(const char* format, double v) {
    char text[64];
    std::snprintf(text, sizeof text, format, v);
    return text;
}

// Corners of a box.
std::vector<glm::vec3> corners(const Bounds& b) {
    std::vector<glm::vec3> out;
    for (int i = 0; i < 8; ++i)
        out.push_back({(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z});
    return out;
}

// Points spanning the light: its centre and the corners of the box around its surface.
std::vector<glm::vec3> lightPoints(const Light& light) {
    std::vector<glm::vec3> out = {light.position};
    if (light.isPoint()) return out;
    const float h = light.shape == LightShape::Square ? 0.5f * light.size : light.size;
    const glm::vec3 r = light.right() * h, u = light.up * h;
    const glm::vec3 d = light.shape == LightShape::Sphere ? light.direction * h : glm::vec3(0.0f);
    for (float sr : {-1.0f, 1.0f})
        for (float su : {-1.0f, 1.0f})
            for (float sd : {-1.0f, 1.0f}) out.push_back(light.position + sr * r + su * u + sd * d);
    return out;
}

Bounds intersect(const Bounds& a, const Bounds& b) {
    Bounds out;
    out.lo = glm::max(a.lo, b.lo);
    out.hi = glm::min(a.hi, b.hi);
    return out;
}

// Points spread over the receivers inside `region`, each with its normal and the area it stands
// for, and the light's visibility there: what the penumbra fraction is made of. It depends on the
// scene, the light and the time only, so the camera's moves reuse it (the window asks on every move).
struct ShadowSamples {
    std::vector<glm::vec3> position, normal;
    std::vector<float> area, visibility;
};

}  // namespace

uint64_t mixKey(uint64_t key, uint64_t value) { return (key ^ value) * 0x100000001B3ull; }
uint64_t mixKey(uint64_t key, float value) {
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return mixKey(key, uint64_t(bits));
}

uint64_t sceneContentKey(const Scene& scene, double t) {
    uint64_t key = mixKey(0xcbf29ce484222325ull, uint64_t(t * 1e6));
    for (const Object& o : scene.objects) {
        key = mixKey(key, o.mesh.triangleCount());
        key = mixKey(key, o.mesh.positions.size());
        if (!o.mesh.positions.empty())
            for (size_t v : {size_t(0), o.mesh.positions.size() / 2, o.mesh.positions.size() - 1})
                for (int c = 0; c < 3; ++c) key = mixKey(key, o.mesh.positions[v][c]);
        const glm::mat4 m = o.worldFromObjectAt(t);
        for (int i = 0; i < 4; ++i)
            for (int c = 0; c < 4; ++c) key = mixKey(key, m[i][c]);
        key = mixKey(key, uint64_t(o.castsShadows) * 2 + uint64_t(o.receivesShadows));
    }
    return key;
}

uint64_t mixLightKey(uint64_t key, const Light& light) {
    for (int c = 0; c < 3; ++c) {
        key = mixKey(key, light.position[c]);
        key = mixKey(key, light.direction[c]);
        key = mixKey(key, light.up[c]);
        key = mixKey(key, light.color[c]);
    }
    key = mixKey(key, light.size);
    key = mixKey(key, light.intensity);
    key = mixKey(key, uint64_t(light.shape) * 2 + uint64_t(light.castsShadows));
    return key;
}

namespace {

const ShadowSamples& shadowSamples(const Scene& scene, const Light& light, const Bounds& region, double t) {
    // The key: the scene's content (sceneContentKey: not its address, so the same scene loaded again
    // reuses its samples, and a scene freed and another allocated at its address cannot), the light,
    // the region and the time.
    uint64_t key = mixLightKey(sceneContentKey(scene, t), light);
    for (int c = 0; c < 3; ++c) {
        key = mixKey(key, region.lo[c]);
        key = mixKey(key, region.hi[c]);
    }
    static std::mutex mutex;
    static std::map<uint64_t, ShadowSamples> cache;
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
    if (cache.size() >= 64) cache.clear();

    // Candidates spread over the receivers' triangles that touch the region, by area, with a fixed
    // sequence (R2 low-discrepancy pairs: the same points every time); those inside the region kept.
    struct Tri {
        glm::vec3 a, b, c, n;
        double area;
    };
    std::vector<Tri> tris;
    double total = 0.0;
    for (const Object& o : scene.objects) {
        if (!o.receivesShadows) continue;
        const glm::mat4 m = o.worldFromObjectAt(t);
        for (size_t i = 0; i + 2 < o.mesh.indices.size(); i += 3) {
            Tri tr;
            tr.a = glm::vec3(m * glm::vec4(o.mesh.positions[o.mesh.indices[i]], 1.0f));
            tr.b = glm::vec3(m * glm::vec4(o.mesh.positions[o.mesh.indices[i + 1]], 1.0f));
            tr.c = glm::vec3(m * glm::vec4(o.mesh.positions[o.mesh.indices[i + 2]], 1.0f));
            const glm::vec3 lo = glm::min(tr.a, glm::min(tr.b, tr.c)), hi = glm::max(tr.a, glm::max(tr.b, tr.c));
            if (glm::any(glm::lessThan(hi, region.lo)) || glm::any(glm::greaterThan(lo, region.hi))) continue;
            const glm::vec3 cr = glm::cross(tr.b - tr.a, tr.c - tr.a);
            tr.area = 0.5 * double(glm::length(cr));
            if (!(tr.area > 0.0)) continue;
            tr.n = glm::normalize(cr);
            total += tr.area;
            tris.push_back(tr);
        }
    }
    ShadowSamples out;
    if (tris.empty()) return cache.emplace(key, std::move(out)).first->second;
    constexpr int kCandidates = 24000;
    const float perSample = float(total / kCandidates);
    double carry = 0.0;
    uint64_t k = 0;
    for (const Tri& tr : tris) {
        carry += tr.area / total * kCandidates;
        for (; carry >= 1.0; carry -= 1.0, ++k) {
            // R2 sequence (Roberts 2018) folded into the triangle.
            double u = std::fmod(0.5 + 0.7548776662466927 * double(k), 1.0);
            double v = std::fmod(0.5 + 0.5698402909980532 * double(k), 1.0);
            if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
            const glm::vec3 p = tr.a + float(u) * (tr.b - tr.a) + float(v) * (tr.c - tr.a);
            if (glm::any(glm::lessThan(p, region.lo)) || glm::any(glm::greaterThan(p, region.hi))) continue;
            out.position.push_back(p);
            out.normal.push_back(tr.n);
            out.area.push_back(perSample);
        }
    }
    if (!out.position.empty()) {
        const int n = int(out.position.size());
        Image positions(n, 1, 3), normals(n, 1, 3);
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                positions.at(i, 0, c) = out.position[size_t(i)][c];
                normals.at(i, 0, c) = out.normal[size_t(i)][c];
            }
        RayTracer tracer(scene, t);
        tracer.setThreadCount(1);  // a few thousand points: threads would cost more than they save
        const Image v = tracer.visibility(positions, normals, light, 16);
        out.visibility.assign(v.data.begin(), v.data.end());
    }
    return cache.emplace(key, std::move(out)).first->second;
}

}  // namespace

// ---- features -------------------------------------------------------------------------------------------
nlohmann::json LightFeatures::toJson() const {
    return {{"point", point},
            {"light_extent", lightExtent},
            {"caster_near", casterNear},
            {"receiver_far", receiverFar},
            {"penumbra_world", penumbraWorld},
            {"penumbra_pixels", penumbraPixels},
            {"penumbra_texels", penumbraTexels},
            {"caster_triangles", casterTriangles},
            {"penumbra_fraction", penumbraFraction},
            {"shadow_on_screen", shadowOnScreen}};
}

LightFeatures measureLightFeatures(const Scene& scene, const Light& light, const Camera& camera, int width,
                                   int height, double t, const std::vector<Light>& all) {
    LightFeatures f;
    f.point = light.isPoint();
    f.lightExtent = f.point ? 0.0
                    : light.shape == LightShape::Square ? double(light.size) * std::sqrt(2.0)
                                                        : 2.0 * double(light.size);
    const glm::vec3 dir = glm::normalize(light.direction);
    auto depth = [&](const glm::vec3& p) { return double(glm::dot(p - light.position, dir)); };

    // The casters' and the receivers' world bounds, and the casters' nearest depth (per vertex: the
    // bounds' corners would put a corner of a tilted caster nearer than any of its points).
    Bounds casters, receivers;
    double near = std::numeric_limits<double>::infinity();
    for (const Object& o : scene.objects) {
        const glm::mat4 m = o.worldFromObjectAt(t);
        if (o.castsShadows) f.casterTriangles += double(o.mesh.triangleCount());
        for (const glm::vec3& p : o.mesh.positions) {
            const glm::vec3 w = glm::vec3(m * glm::vec4(p, 1.0f));
            if (o.castsShadows) {
                casters.extend(w);
                const double z = depth(w);
                if (z > 1e-4) near = std::min(near, z);
            }
            if (o.receivesShadows) receivers.extend(w);
        }
    }
    if (casters.empty() || receivers.empty() || !std::isfinite(near) || !light.castsShadows) {
        f.shadowOnScreen = false;
        return f;
    }
    double far = 0.0;
    for (const glm::vec3& c : corners(receivers)) far = std::max(far, depth(c));
    f.casterNear = near;
    f.receiverFar = far;
    f.penumbraWorld = far > near ? f.lightExtent * (far - near) / near : 0.0;

    // Where shadows can fall: the box around the casters and their corners pushed from every light
    // point to the farthest receiver depth, within the receivers' box.
    Bounds region;
    bool unbounded = false;
    for (const glm::vec3& c : corners(casters)) {
        region.extend(c);
        for (const glm::vec3& l : lightPoints(light)) {
            const double zc = depth(c), zl = depth(l);
            if (zc - zl < 1e-3) {
                unbounded = true;  // a caster beside or behind the light: its shadow is not bounded
                continue;
            }
            region.extend(l + (c - l) * float((far - zl) / (zc - zl)));
        }
    }
    region = unbounded ? receivers : intersect(region, receivers);
    if (region.empty()) {
        f.shadowOnScreen = false;
        return f;
    }

    // Outside the view frustum when every corner lies beyond one of its planes.
    const float aspect = float(width) / float(std::max(height, 1));
    const glm::mat4 clip = camera.clipFromView(aspect) * camera.viewFromWorld();
    const std::vector<glm::vec3> rc = corners(region);
    for (int axis = 0; axis < 3 && f.shadowOnScreen; ++axis)
        for (float side : {-1.0f, 1.0f}) {
            bool allOut = true;
            for (const glm::vec3& p : rc) {
                const glm::vec4 q = clip * glm::vec4(p, 1.0f);
                if (side * q[axis] <= q.w) allOut = false;
            }
            if (allOut) {
                f.shadowOnScreen = false;
                break;
            }
        }

    // Eq. 5 without the normal term (a receiver facing the camera): the penumbra at the region's
    // nearest eye depth (linear over the box, so at a corner), not nearer than the near plane.
    const glm::mat4 view = camera.viewFromWorld();
    double eye = std::numeric_limits<double>::infinity();
    for (const glm::vec3& p : rc) eye = std::min(eye, double(-(view * glm::vec4(p, 1.0f)).z));
    eye = std::max(eye, double(camera.nearPlane));
    const double focalPixels = double(height) / (2.0 * std::tan(glm::radians(double(camera.fovYDegrees)) * 0.5));
    f.penumbraPixels = f.penumbraWorld * focalPixels / eye;

    // The penumbra's share of the frame: the sampled points in penumbra (0 < v < 1), each weighted by
    // the pixels its patch covers, area x cos / distance^2 x focal^2, when it lies in the frustum and
    // faces the camera.
    if (f.shadowOnScreen && !f.point && t != 0.0) {
        // Moving objects: the fraction and the share at the scene's first pose (t = 0). A choice is
        // not made again as objects move, and the samples stay cached (one ray-traced set per scene
        // and light, not one per frame time: a window or a soak would otherwise fill the cache with
        // times).
        const LightFeatures rest = measureLightFeatures(scene, light, camera, width, height, 0.0, all);
        f.penumbraFraction = rest.penumbraFraction;
        f.share = rest.share;
    } else if (f.shadowOnScreen && !f.point) {
        const ShadowSamples& samples = shadowSamples(scene, light, region, t);
        double pixels = 0.0, share2 = 0.0;
        size_t inPenumbra = 0;
        auto irradiance = [](const Light& l, const glm::vec3& p, const glm::vec3& n) {  // shade.frag's E_l
            const glm::vec3 radiance = l.color * l.intensity;
            return std::max(0.0, double(glm::dot(n, glm::normalize(l.position - p)))) *
                   double(radiance.r + radiance.g + radiance.b) / 3.0;
        };
        for (size_t i = 0; i < samples.position.size(); ++i) {
            const float v = samples.visibility[i];
            if (!(v > 0.0f && v < 1.0f)) continue;
            if (all.size() > 1) {
                double sum = 0.0;
                for (const Light& l : all) sum += irradiance(l, samples.position[i], samples.normal[i]);
                const double w = sum > 0.0 ? irradiance(light, samples.position[i], samples.normal[i]) / sum : 1.0;
                share2 += w * w;
                ++inPenumbra;
            }
            const glm::vec4 q = clip * glm::vec4(samples.position[i], 1.0f);
            if (q.w <= 0.0f || std::abs(q.x) > q.w || std::abs(q.y) > q.w) continue;
            const glm::vec3 toCamera = camera.position - samples.position[i];
            const double d2 = double(glm::dot(toCamera, toCamera));
            const double cosine = double(glm::dot(samples.normal[i], toCamera)) / std::sqrt(d2);
            if (cosine <= 0.0) continue;
            pixels += double(samples.area[i]) * cosine / d2 * focalPixels * focalPixels;
        }
        f.penumbraFraction = std::min(1.0, pixels / (double(width) * double(height)));
        if (inPenumbra > 0) f.share = std::sqrt(share2 / double(inPenumbra));
    }

    // From the light's centre the penumbra at depth z_r spans the angle w_p / z_r; a texel of a
    // 1024^2 map fitted to the scene spans 2 tan(half fov) / 1024.
    const LightView lv = fitLightView(light, light.position, scene.bounds(t));
    f.penumbraTexels = far > 0.0 ? (f.penumbraWorld / far) / (2.0 * double(lv.tanHalfFov) / 1024.0) : 0.0;
    return f;
}

double lightBudget(double frameBudget, const LightFeatures& light, int lightsByCalibration) {
    const double share = std::max(light.share, 1e-3);
    return std::min(1.0, frameBudget / (double(std::max(lightsByCalibration, 1)) * share));
}

// ---- calibration ------------------------------------------------------------------------------------------
std::string CalibrationSetting::describe() const {
    std::string text = technique;
    if (sets.empty()) return text + " defaults";
    for (const auto& [k, v] : sets) text += " " + k + "=" + v;
    return text;
}

nlohmann::json Calibration::toJson() const {
    nlohmann::json j;
    j["format"] = "shadowlab-calibration";
    j["version"] = kVersion;
    j["program"] = program;
    j["date"] = date;
    j["machine"] = {{"gl_renderer", glRenderer}, {"cpu", cpu}, {"lp_num_threads", lpNumThreads}, {"probe_ms", probeMs}};
    j["reference"] = reference;
    j["settings"] = nlohmann::json::array();
    for (const CalibrationSetting& s : settings) {
        nlohmann::json sets = nlohmann::json::object();
        for (const auto& [k, v] : s.sets) sets[k] = v;
        j["settings"].push_back({{"technique", s.technique}, {"set", sets}});
    }
    j["cases"] = nlohmann::json::array();
    for (const CalibrationCase& c : cases) {
        nlohmann::json results = nlohmann::json::array();
        for (const CalibrationResult& r : c.results)
            results.push_back({{"rmse", r.rmse}, {"rmse_penumbra", r.rmsePenumbra}, {"fixed_ms", r.fixedMs}, {"frame_ms", r.frameMs}});
        j["cases"].push_back({{"scene", c.scene},
                              {"light_size", c.lightSize},
                              {"size", {c.width, c.height}},
                              {"features", c.features.toJson()},
                              {"results", results}});
    }
    return j;
}

Calibration loadCalibration(const std::string& path) {
    const JsonDocument doc = JsonDocument::fromFile(path, "calibration");
    const JsonReader r(doc);
    const JsonFields top(r, doc.root(), "", {"format", "version", "program", "date", "machine", "reference", "settings", "cases"});
    Calibration cal;
    cal.file = path;
    top.oneOf("format", {"shadowlab-calibration"});
    const int64_t version = top.integer("version", 1, 1000);
    if (version != Calibration::kVersion)
        r.fail("version", "version " + std::to_string(Calibration::kVersion) + " (remake it: shadowlab bench --calibrate)",
               std::to_string(version));
    cal.program = top.string("program", "");
    cal.date = top.string("date", "");
    cal.reference = top.string("reference", "");
    const JsonFields machine = top.object("machine", {"gl_renderer", "cpu", "lp_num_threads", "probe_ms"});
    cal.glRenderer = machine.string("gl_renderer", "");
    cal.cpu = machine.string("cpu", "");
    cal.lpNumThreads = machine.string("lp_num_threads", "");
    cal.probeMs = machine.number("probe_ms", greaterThan(0.0));

    const nlohmann::json& settings = top.require("settings", "an array of settings");
    if (!settings.is_array() || settings.empty()) r.fail("settings", "a non-empty array of settings", describeJson(settings));
    for (size_t i = 0; i < settings.size(); ++i) {
        const std::string p = elementPath("settings", i);
        const JsonFields f(r, settings[i], p, {"technique", "set"});
        CalibrationSetting s;
        s.technique = f.string("technique");
        const TechniqueDesc* desc = findTechnique(s.technique);
        if (!desc || desc->choose) {
            std::string ids;
            for (const TechniqueDesc* d : allTechniques())
                if (!d->choose) ids += (ids.empty() ? "" : ", ") + d->id;
            r.fail(fieldPath(p, "technique"), "a registered technique (" + ids + ")", describeJson(settings[i]["technique"]));
        }
        ParamValues check(*desc);
        if (const nlohmann::json* sets = f.find("set")) {
            r.requireObject(*sets, fieldPath(p, "set"));
            for (const auto& [k, v] : sets->items()) {
                const std::string where = r.place(fieldPath(fieldPath(p, "set"), k));
                if (!v.is_string()) r.fail(fieldPath(fieldPath(p, "set"), k), "a value as --set text (a string)", describeJson(v));
                check.set(*desc, k, v.get<std::string>(), where);
                s.sets.push_back({k, v.get<std::string>()});
            }
        }
        cal.settings.push_back(std::move(s));
    }

    const nlohmann::json& cases = top.require("cases", "an array of cases");
    if (!cases.is_array() || cases.empty()) r.fail("cases", "a non-empty array of measured cases", describeJson(cases));
    for (size_t i = 0; i < cases.size(); ++i) {
        const std::string p = elementPath("cases", i);
        const JsonFields f(r, cases[i], p, {"scene", "light_size", "size", "features", "results"});
        CalibrationCase c;
        c.scene = f.string("scene");
        c.lightSize = f.number("light_size", atLeast(0.0));
        const nlohmann::json& size = f.require("size", "[width, height]");
        if (!size.is_array() || size.size() != 2) r.fail(fieldPath(p, "size"), "[width, height]", describeJson(size));
        c.width = int(r.integer(size[0], elementPath(fieldPath(p, "size"), 0), 1, 8192));
        c.height = int(r.integer(size[1], elementPath(fieldPath(p, "size"), 1), 1, 8192));
        const JsonFields ff = f.object("features", {"point", "light_extent", "caster_near", "receiver_far", "penumbra_world",
                                                    "penumbra_pixels", "penumbra_texels", "caster_triangles",
                                                    "penumbra_fraction", "shadow_on_screen"});
        c.features.point = ff.boolean("point");
        c.features.lightExtent = ff.number("light_extent", atLeast(0.0));
        c.features.casterNear = ff.number("caster_near", atLeast(0.0));
        c.features.receiverFar = ff.number("receiver_far", atLeast(0.0));
        c.features.penumbraWorld = ff.number("penumbra_world", atLeast(0.0));
        c.features.penumbraPixels = ff.number("penumbra_pixels", atLeast(0.0));
        c.features.penumbraTexels = ff.number("penumbra_texels", atLeast(0.0));
        c.features.casterTriangles = ff.number("caster_triangles", atLeast(0.0));
        c.features.penumbraFraction = ff.number("penumbra_fraction", inRange(0.0, 1.0));
        c.features.shadowOnScreen = ff.boolean("shadow_on_screen");
        const nlohmann::json& results = f.require("results", "an array of results, one per setting");
        if (!results.is_array() || results.size() != cal.settings.size())
            r.fail(fieldPath(p, "results"), "an array of " + std::to_string(cal.settings.size()) + " results (one per setting)",
                   describeJson(results));
        for (size_t k = 0; k < results.size(); ++k) {
            const JsonFields rf(r, results[k], elementPath(fieldPath(p, "results"), k), {"rmse", "rmse_penumbra", "fixed_ms", "frame_ms"});
            CalibrationResult res;
            res.rmse = rf.number("rmse", inRange(0.0, 1.0));
            res.rmsePenumbra = rf.number("rmse_penumbra", inRange(0.0, 1.0));
            res.fixedMs = rf.number("fixed_ms", atLeast(0.0));
            res.frameMs = rf.number("frame_ms", atLeast(0.0));
            c.results.push_back(res);
        }
        cal.cases.push_back(std::move(c));
    }
    return cal;
}

std::string defaultCalibrationPath() {
    if (const char* env = std::getenv("SHADOWLAB_CALIBRATION"); env && *env) return env;
    return projectRoot() + "/assets/calibration/default.json";
}

const Calibration& defaultCalibration() {
    static std::mutex mutex;
    static std::map<std::string, Calibration> loaded;
    const std::string path = defaultCalibrationPath();
    std::lock_guard<std::mutex> lock(mutex);
    auto it = loaded.find(path);
    if (it == loaded.end()) it = loaded.emplace(path, loadCalibration(path)).first;
    return it->second;
}

double machineProbeMs() {
    static const double probe = [] {
        double best = std::numeric_limits<double>::infinity();
        volatile float sink = 0.0f;
        for (int round = 0; round < 3; ++round) {
            const auto t0 = std::chrono::steady_clock::now();
            float x = 0.5f, acc = 0.0f;
            for (int i = 0; i < 2'000'000; ++i) {
                x = x * 1.0000001f + 1e-7f;
                acc += std::sqrt(x + float(i & 7));
            }
            sink = sink + acc;
            best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        return std::max(best, 1e-3);
    }();
    return probe;
}

// ---- prediction -------------------------------------------------------------------------------------------
double featureDistance(const LightFeatures& a, const LightFeatures& b) {
    const double dp = std::log2(1.0 + a.penumbraPixels) - std::log2(1.0 + b.penumbraPixels);
    const double dt = std::log2(1.0 + a.penumbraTexels) - std::log2(1.0 + b.penumbraTexels);
    const double dc = 0.5 * (std::log10(1.0 + a.casterTriangles) - std::log10(1.0 + b.casterTriangles));
    return std::sqrt(dp * dp + dt * dt + dc * dc);
}

Prediction predictSetting(const Calibration& cal, size_t setting, const LightFeatures& features, bool penumbraBudget,
                          int pixels, double machineScale) {
    // The cases of an area light (a point-light case says nothing of soft shadows), nearest first.
    std::vector<std::pair<double, size_t>> order;
    for (size_t i = 0; i < cal.cases.size(); ++i)
        if (!cal.cases[i].features.point) order.push_back({featureDistance(features, cal.cases[i].features), i});
    std::sort(order.begin(), order.end());
    Prediction p;
    if (order.empty()) {
        p.error = 1.0;
        p.distance = std::numeric_limits<double>::infinity();
        return p;
    }
    const size_t k = std::min<size_t>(kNeighbours, order.size());
    p.distance = order[0].first;
    std::vector<double> ms;
    for (size_t n = 0; n < k; ++n) {
        const CalibrationCase& c = cal.cases[order[n].second];
        const CalibrationResult& r = c.results.at(setting);
        // The image's RMSE is the penumbra's spread over the image: sqrt(fraction) x the penumbra's
        // (most of every technique's error lies in the penumbra), so a case's RMSE is scaled by the
        // square root of the two penumbra fractions' ratio (at most 4x either way).
        double scale = 1.0;
        if (!penumbraBudget && features.penumbraFraction > 0.0 && c.features.penumbraFraction > 0.0)
            scale = std::sqrt(std::clamp(features.penumbraFraction / c.features.penumbraFraction, 1.0 / 16.0, 16.0));
        p.error = std::max(p.error, std::min(1.0, (penumbraBudget ? r.rmsePenumbra : r.rmse) * scale));
        const double pixelScale = double(pixels) / double(std::max(1, c.width * c.height));
        ms.push_back((r.fixedMs + r.frameMs * pixelScale) * machineScale);
        p.nearest.push_back(c.scene + " light " + fmt("%g", c.lightSize));
    }
    p.ms = *std::max_element(ms.begin(), ms.end());
    return p;
}

namespace {

// How a shared budget came about: " = 0.02 / (1 light x share 0.56 of v)"; "" when not shared.
std::string sharedBudgetText(const AutoBudget& budget, const LightFeatures& features) {
    if (!(budget.frameError > 0.0 && budget.frameError != budget.error)) return "";
    if (budget.byFacts >= 0.0)
        return " = sqrt((" + fmt("%.4g", budget.frameError) + "^2 - " + fmt("%.4f", budget.byFacts) +
               "^2 measured for the lights the facts give hard) / " + std::to_string(budget.sharedBy) +
               (budget.sharedBy == 1 ? " light)" : " lights)");
    return " = " + fmt("%.4g", budget.frameError) + " / (" + std::to_string(budget.sharedBy) +
           (budget.sharedBy == 1 ? " light" : " lights") + " x share " + fmt("%.2f", features.share) + " of v)";
}

// The measured choice: every setting within the time budget (predicted), by predicted time, its
// error measured; those within the error budget timed side by side; the fastest of them taken
// (equal times: the first by predicted time). Nothing within the budget: the most accurate measured.
void chooseMeasured(const Calibration& cal, const LightFeatures& features, const AutoBudget& budget,
                    const std::vector<Prediction>& predictions, const SettingTrials& trials, double machineScale,
                    TechniqueChoice& choice,
                    const std::function<void(const TechniqueDesc*, const std::vector<std::pair<std::string, std::string>>&)>& pick) {
    const std::string metric = budget.penumbra ? "penumbra RMSE" : "RMSE";
    const bool timed = budget.timeMs > 0.0;
    std::vector<size_t> order;
    for (size_t s = 0; s < predictions.size(); ++s)
        if (!timed || predictions[s].ms <= budget.timeMs) order.push_back(s);
    if (order.empty())  // nothing fits the time budget: the fastest alone
        order.push_back(size_t(std::min_element(predictions.begin(), predictions.end(),
                                                [](const Prediction& a, const Prediction& b) { return a.ms < b.ms; }) -
                               predictions.begin()));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return predictions[a].ms < predictions[b].ms; });
    std::vector<std::optional<double>> measured(predictions.size()), measuredMs(predictions.size());
    long best = -1, mostAccurate = -1;
    std::vector<size_t> within;
    for (size_t s : order) {
        const std::optional<MeasuredError> m = trials.error(s);
        if (!m) continue;
        measured[s] = budget.penumbra ? m->rmsePenumbra : m->rmse;
        if (mostAccurate < 0 || *measured[s] < *measured[size_t(mostAccurate)]) mostAccurate = long(s);
        if (*measured[s] <= budget.error) within.push_back(s);
    }
    // Timed together, side by side (trial.h): a time measured alone, or cached from another budget's
    // choice, met another load of the machine.
    const std::vector<double> ms = within.empty() ? std::vector<double>{} : trials.time(within);
    for (size_t i = 0; i < within.size(); ++i) {
        const size_t s = within[i];
        measuredMs[s] = i < ms.size() && ms[i] >= 0.0 ? ms[i] : predictions[s].ms;
        if (best < 0 || *measuredMs[s] < *measuredMs[size_t(best)]) best = long(s);
    }
    std::string rule = "measured";
    if (best < 0) {
        rule = "nothing meets the budget";
        best = mostAccurate >= 0 ? mostAccurate : long(order.front());
    }
    nlohmann::json alternatives = nlohmann::json::array();
    for (size_t s = 0; s < predictions.size(); ++s) {
        const Prediction& p = predictions[s];
        std::string rejected;
        if (long(s) == best)
            rejected = "chosen";
        else if (measured[s] && *measured[s] > budget.error)
            rejected = "measured " + metric + " " + fmt("%.4f", *measured[s]) + " > budget " + fmt("%.4f", budget.error);
        else if (measuredMs[s])
            rejected = "measured " + metric + " " + fmt("%.4f", *measured[s]) + " in " + fmt("%.2f", *measuredMs[s]) +
                       " ms, slower than the chosen one";
        else if (measured[s])
            rejected = "measured " + metric + " " + fmt("%.4f", *measured[s]) + ", less accurate than the chosen one";
        else if (timed && p.ms > budget.timeMs)
            rejected = "predicted " + fmt("%.2f", p.ms) + " ms > time budget " + fmt("%.2f", budget.timeMs) + " ms";
        else
            rejected = "not measured";
        nlohmann::json a = {{"setting", cal.settings[s].describe()},
                            {"predicted_error", p.error},
                            {"predicted_ms", p.ms},
                            {"rejected", rejected}};
        if (measured[s]) a["measured_error"] = *measured[s];
        if (measuredMs[s]) a["measured_ms"] = *measuredMs[s];
        alternatives.push_back(a);
    }
    const CalibrationSetting& chosen = cal.settings[size_t(best)];
    pick(&requireTechnique(chosen.technique, cal.file), chosen.sets);
    const Prediction& p = predictions[size_t(best)];
    choice.report["rule"] = rule;
    choice.report["predicted"] = {{"error", p.error}, {"ms", p.ms}, {"distance", p.distance}, {"nearest", p.nearest}};
    if (measured[size_t(best)]) choice.report["measured_error"] = *measured[size_t(best)];
    if (measuredMs[size_t(best)]) choice.report["measured_ms"] = *measuredMs[size_t(best)];
    choice.report["alternatives"] = alternatives;
    choice.report["calibration"] = {{"file", cal.file}, {"cases", cal.cases.size()}, {"machine_scale", machineScale}};
    const std::string what = chosen.describe();
    const double e = measured[size_t(best)].value_or(p.error);
    if (rule == "measured")
        choice.report["why"] = what + ": the fastest measured (" + fmt("%.2f", measuredMs[size_t(best)].value_or(p.ms)) +
                               " ms) whose measured " + metric + " meets the budget (" + fmt("%.4f", e) + " <= " +
                               fmt("%.4f", budget.error) + sharedBudgetText(budget, features) + ")";
    else
        choice.report["why"] = what + ": no setting" + std::string(timed ? " within the time budget" : "") +
                               " measured within the budget; the most accurate measured (" + metric + " " +
                               fmt("%.4f", e) + ")";
}

}  // namespace

TechniqueChoice chooseTechnique(const Calibration& cal, const LightFeatures& features, const AutoBudget& budget,
                                int pixels, double machineScale, const SettingTrials* trials) {
    TechniqueChoice choice;
    const std::string metric = budget.penumbra ? "penumbra RMSE" : "RMSE";
    choice.report["budget"] = {{"error", budget.error}, {"on", budget.penumbra ? "penumbra" : "all"}};
    if (budget.frameError > 0.0 && budget.frameError != budget.error)
        choice.report["budget"]["shared"] = {{"frame_error", budget.frameError},
                                             {"lights", budget.sharedBy},
                                             {"measured_by_facts", budget.byFacts},
                                             {"share", features.share}};
    if (budget.timeMs > 0.0) choice.report["budget"]["time_ms"] = budget.timeMs;
    choice.report["features"] = features.toJson();
    auto pick = [&](const TechniqueDesc* desc, const std::vector<std::pair<std::string, std::string>>& sets) {
        choice.desc = desc;
        choice.params = std::make_shared<ParamValues>(*desc);
        for (const auto& [k, v] : sets) choice.params->set(*desc, k, v, cal.file.empty() ? "calibration" : cal.file);
        std::string setting;
        for (const auto& [k, v] : sets) setting += (setting.empty() ? "" : " ") + k + "=" + v;
        choice.report["technique"] = desc->id;
        choice.report["setting"] = setting.empty() ? "defaults" : setting;
    };
    const TechniqueDesc& hard = requireTechnique("hard", "auto");
    if (features.point) {
        pick(&hard, {});
        choice.report["rule"] = "point light";
        choice.report["why"] = "a point light (size 0) casts hard shadows: hard";
        return choice;
    }
    if (!features.shadowOnScreen) {
        choice.desc = nullptr;
        choice.report["technique"] = "none";
        choice.report["setting"] = "";
        choice.report["rule"] = "no visible shadow";
        choice.report["why"] = "the region where this light's shadows can fall lies outside the camera's view: nothing runs, v = 1";
        return choice;
    }
    if (features.penumbraPixels < 1.0) {
        pick(&hard, {});
        choice.report["rule"] = "penumbra under a pixel";
        choice.report["why"] = "the largest penumbra is at most " + fmt("%.2f", features.penumbraPixels) +
                               " pixel (conservative estimate): hard";
        return choice;
    }

    // The calibration: every setting's predicted error and time; the cheapest within both budgets.
    double widest = 0.0;
    for (const CalibrationCase& c : cal.cases) widest = std::max(widest, c.features.penumbraPixels);
    std::vector<Prediction> predictions;
    for (size_t s = 0; s < cal.settings.size(); ++s)
        predictions.push_back(predictSetting(cal, s, features, budget.penumbra, pixels, machineScale));
    const bool outside = predictions.empty() || predictions[0].distance > kOutsideCalibration ||
                         features.penumbraPixels > 2.0 * widest;
    const bool timed = budget.timeMs > 0.0;
    if (trials && trials->error && trials->time && !predictions.empty()) {
        chooseMeasured(cal, features, budget, predictions, *trials, machineScale, choice, pick);
        return choice;
    }
    long best = -1;
    nlohmann::json alternatives = nlohmann::json::array();
    for (size_t s = 0; s < cal.settings.size(); ++s) {
        const Prediction& p = predictions[s];
        std::string rejected;
        if (!outside && p.error > budget.error)
            rejected = "predicted " + metric + " " + fmt("%.4f", p.error) + " > budget " + fmt("%.4f", budget.error);
        else if (timed && p.ms > budget.timeMs)
            rejected = "predicted " + fmt("%.2f", p.ms) + " ms > time budget " + fmt("%.2f", budget.timeMs) + " ms";
        alternatives.push_back({{"setting", cal.settings[s].describe()},
                                {"predicted_error", p.error},
                                {"predicted_ms", p.ms},
                                {"rejected", rejected}});
        if (!rejected.empty()) continue;
        // Within the budgets: the cheapest; outside the calibration's range: the most accurate.
        const bool better = best < 0 || (outside ? p.error < predictions[size_t(best)].error
                                                 : p.ms < predictions[size_t(best)].ms);
        if (better) best = long(s);
    }
    std::string rule = outside ? "outside the calibration" : "calibration";
    if (best < 0) {
        // Nothing meets the error budget within the time budget: the most accurate within the time
        // budget, else the fastest.
        rule = "nothing meets the budget";
        for (size_t s = 0; s < predictions.size(); ++s) {
            const bool fits = !timed || predictions[s].ms <= budget.timeMs;
            if (fits && (best < 0 || predictions[s].error < predictions[size_t(best)].error)) best = long(s);
        }
        if (best < 0)
            for (size_t s = 0; s < predictions.size(); ++s)
                if (best < 0 || predictions[s].ms < predictions[size_t(best)].ms) best = long(s);
    }
    const CalibrationSetting& chosen = cal.settings[size_t(best)];
    pick(&requireTechnique(chosen.technique, cal.file), chosen.sets);
    for (nlohmann::json& a : alternatives)
        if (a["setting"] == chosen.describe()) a["rejected"] = "chosen";
    const Prediction& p = predictions[size_t(best)];
    choice.report["rule"] = rule;
    choice.report["predicted"] = {{"error", p.error}, {"ms", p.ms}, {"distance", p.distance}, {"nearest", p.nearest}};
    choice.report["alternatives"] = alternatives;
    choice.report["calibration"] = {{"file", cal.file}, {"cases", cal.cases.size()}, {"machine_scale", machineScale}};
    const std::string what = chosen.describe();
    const std::string shared = sharedBudgetText(budget, features);
    if (rule == "calibration")
        choice.report["why"] = what + ": the cheapest setting predicted within the budget (" + metric + " " +
                               fmt("%.4f", p.error) + " <= " + fmt("%.4f", budget.error) + shared + ", " +
                               fmt("%.2f", p.ms) + " ms)";
    else if (rule == "outside the calibration")
        choice.report["why"] = what + ": the light's features lie outside the calibration's range (distance " +
                               fmt("%.2f", p.distance) + "), so the most accurate setting" +
                               (timed ? " within the time budget" : "") + " is taken";
    else
        choice.report["why"] = what + ": no setting is predicted within the budget" +
                               std::string(timed ? " and the time budget" : "") + "; the most accurate that fits (" +
                               metric + " " + fmt("%.4f", p.error) + ")";
    return choice;
}

// ---- the descriptor ---------------------------------------------------------------------------------------
const TechniqueDesc& autoTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "auto";
        d.name = "Auto: the cheapest technique within an error budget";
        d.citation = "this project (issue 25); penumbra estimate from guennebaud2007 eq. 4-5";
        d.summary = "Per light, picks the cheapest registered technique and setting whose predicted error meets "
                    "error_budget: a point light or a penumbra under a pixel takes hard, a shadow on no visible pixel "
                    "runs nothing, else a measured calibration (shadowlab bench --calibrate) predicts each setting's "
                    "error and time. --stats says what it chose and why.";
        d.soft = true;
        ParamDesc budget;
        budget.key = "error_budget";
        budget.type = ParamDesc::Type::Float;
        budget.defaultValue = 0.02;
        budget.minValue = 0.0005;
        budget.maxValue = 1.0;
        budget.step = 0.001;
        budget.doc = "the largest RMSE of v against the exact visibility the choice may predict (default 0.02: about "
                     "the error of a good filtered soft shadow on the scenes in assets/)";
        d.params.push_back(budget);
        ParamDesc on;
        on.key = "budget_on";
        on.type = ParamDesc::Type::Enum;
        on.choices = {"all", "penumbra"};
        on.defaultValue = 0;
        on.doc = "where the error is measured: the whole image, or the reference's penumbra (0 < v < 1) only";
        d.params.push_back(on);
        ParamDesc time;
        time.key = "time_budget_ms";
        time.type = ParamDesc::Type::Float;
        time.unit = "ms";
        time.defaultValue = 0.0;
        time.minValue = 0.0;
        time.maxValue = 10000.0;
        time.step = 1.0;
        time.doc = "the largest predicted shadow_ms of the choice (0: none); when nothing meets both budgets, the most "
                   "accurate setting within this one";
        d.params.push_back(time);
        ParamDesc measured{"measure", "", ParamDesc::Type::Bool, "", 1.0, 0, 1, 1,
                           "measure before trusting: every setting within the time budget is rendered on this light "
                           "at a trial size (at most 256x256 pixels) against a ray-traced reference (256 rays), those "
                           "within the error budget are timed, and the fastest runs (cached per view; the calibration "
                           "orders them and scales their times); off: the calibration's prediction alone decides"};
        d.params.push_back(measured);
        d.choose = [](const ChoiceInputs& in) {
            const LightFeatures f =
                measureLightFeatures(*in.scene, *in.light, *in.camera, in.width, in.height, in.time, in.lights);
            AutoBudget b;
            b.frameError = in.params->get("error_budget");
            // The lights the facts do not decide share the frame's budget (lightBudget); those the
            // facts decide (hard: a point, a penumbra under a pixel) are listed for the measured share.
            int byCalibration = 0;
            std::vector<int> byFacts;
            for (size_t k = 0; k < in.lights.size(); ++k) {
                const Light& l = in.lights[k];
                if (!l.castsShadows) continue;
                if (l.isPoint()) {
                    byFacts.push_back(int(k));
                    continue;
                }
                const LightFeatures o = measureLightFeatures(*in.scene, l, *in.camera, in.width, in.height, in.time);
                byCalibration += o.shadowOnScreen && o.penumbraPixels >= 1.0;
                if (o.shadowOnScreen && o.penumbraPixels < 1.0) byFacts.push_back(int(k));
            }
            b.sharedBy = std::max(byCalibration, 1);
            b.error = lightBudget(b.frameError, f, b.sharedBy);
            b.penumbra = in.params->getChoice("budget_on") == "penumbra";
            b.timeMs = in.params->get("time_budget_ms");
            // The facts need no calibration: a point light takes hard even without the file.
            if (f.point || !f.shadowOnScreen || f.penumbraPixels < 1.0) {
                static const Calibration none;
                return chooseTechnique(none, f, b, in.width * in.height, 1.0);
            }
            const Calibration& cal = defaultCalibration();
            const double scale = std::clamp(machineProbeMs() / cal.probeMs, 0.25, 4.0);
            if (!in.measure || !in.params->getBool("measure"))
                return chooseTechnique(cal, f, b, in.width * in.height, scale);
            TrialInputs trial;
            trial.scene = in.scene;
            trial.lights = in.lights.empty() ? std::vector<Light>{*in.light} : in.lights;
            trial.light = in.lights.empty() ? 0 : in.lightIndex;
            trial.camera = *in.camera;
            trial.width = in.width;
            trial.height = in.height;
            // At the scene's first pose, as the penumbra fraction and the shares: a choice is not made
            // again as objects move, and one trial per view is kept whatever the frame's time (the
            // soak's rounds at later times otherwise measured again, and resident memory grew).
            trial.time = 0.0;
            TrialLog log;
            const int trialPixels = trialSize(in.width, in.height).width * trialSize(in.width, in.height).height;
            SettingTrials measure;
            measure.error = [&](size_t s) -> std::optional<MeasuredError> {
                return measureSettingError(trial, cal.settings.at(s), log);
            };
            measure.time = [&](const std::vector<size_t>& settings) {
                std::vector<CalibrationSetting> timed;
                for (size_t s : settings) timed.push_back(cal.settings.at(s));
                std::vector<double> ms = timeSettingsSideBySide(trial, timed, log);
                for (size_t i = 0; i < ms.size(); ++i) {  // at the trial size: put at the frame's by the calibration's split
                    const double atTrial = predictSetting(cal, settings[i], f, b.penumbra, trialPixels, scale).ms;
                    const double atFrame = predictSetting(cal, settings[i], f, b.penumbra, in.width * in.height, scale).ms;
                    if (ms[i] >= 0.0 && atTrial > 0.0) ms[i] *= atFrame / atTrial;
                }
                return ms;
            };
            // Measured, a light's error is its part of v's error already (the trial lights the scene
            // with the other lights, unshadowed: v's error there is this light's error weighted by its
            // share of the light at each pixel). The lights the facts give `hard` err by aliasing:
            // their measured parts come off the frame's budget first, and the rest is shared equally,
            // in quadrature: the lights' errors lie in different penumbrae, so their squares add
            // (sum_l e_l^2 <= budget^2); a linear sum (Minkowski's bound, the shares' rule) assumes
            // every error falls on the same pixels with the same sign, and on `three-lights` leaves
            // nothing for the third light at 0.02 (its two hard lights measure 0.010 each).
            if (!b.penumbra && in.lights.size() > 1) {
                double squares = 0.0;
                for (int k : byFacts) {
                    if (k == trial.light) continue;
                    TrialInputs other = trial;
                    other.light = k;
                    const double e = measureSettingError(other, CalibrationSetting{"hard", {}}, log).rmse;
                    squares += e * e;
                }
                b.byFacts = std::sqrt(squares);
                b.error = std::sqrt(std::max(0.0, b.frameError * b.frameError - squares) / double(b.sharedBy));
            }
            TechniqueChoice c = chooseTechnique(cal, f, b, in.width * in.height, scale, &measure);
            releaseTrialRenderers();
            c.report["trial"] = log.toJson();
            return c;
        };
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
