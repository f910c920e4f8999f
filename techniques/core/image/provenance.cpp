// Provenance sidecars of float buffers (provenance.h).
#include "image/provenance.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "error.h"
#include "scene/json_reader.h"

#ifndef SHADOWLAB_VERSION
#define SHADOWLAB_VERSION "unknown"
#endif

namespace shadowlab {

using json = nlohmann::json;

const char* programVersion() { return SHADOWLAB_VERSION; }

namespace {

json vec3Json(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

// Version of the record layout, so that a later program can read older sidecars.
constexpr int kFormat = 1;

}  // namespace

json provenanceOf(const RenderProvenance& render, const std::string& meaning) {
    json lights = json::array();
    for (const RenderedLight& r : render.lights) {
        const Light& l = r.light;
        lights.push_back({{"name", l.name},
                          {"shape", lightShapeName(l.shape)},
                          {"position", vec3Json(l.position)},
                          {"direction", vec3Json(l.direction)},
                          {"up", vec3Json(l.up)},
                          {"size", l.size},
                          {"color", vec3Json(l.color)},
                          {"intensity", l.intensity},
                          {"casts_shadows", l.castsShadows},
                          {"technique", r.technique},
                          {"parameters", r.parameters}});
    }
    return {{"shadowlab_provenance", kFormat},
            {"buffer", meaning},
            {"scene", {{"name", render.sceneName}, {"file", render.scenePath}}},
            {"size", {{"width", render.width}, {"height", render.height}}},
            {"lights", lights},
            {"frame_ms", render.frameMs},
            {"clock", render.clock},
            {"program", {{"name", "shadowlab"}, {"version", programVersion()}}},
            {"gl_renderer", render.glRenderer},
            {"command_line", render.commandLine}};
}

std::string sidecarPath(const std::string& pfmPath) { return pfmPath + ".json"; }

void writePfmWithSidecar(OutputSet& outputs, const std::string& path, const Image& image,
                         const json& provenance) {
    writePFM(outputs.stage(path), image);
    const std::string sidecar = sidecarPath(path);
    std::ofstream out(outputs.stage(sidecar), std::ios::binary);
    out << provenance.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    out.flush();
    if (!out) throw InternalError("cannot write " + sidecar);
}

std::optional<json> readSidecar(const std::string& pfmPath) {
    const std::string path = sidecarPath(pfmPath);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return std::nullopt;
    const JsonDocument document = JsonDocument::fromFile(path, "provenance sidecar");
    // Only what `compare` reads is checked; other fields may come and go between versions.
    const JsonReader r(document);
    const json& root = document.root();
    r.requireObject(root, "");
    const std::string what = "a field of a shadowlab provenance sidecar";
    const auto field = [&](const std::string& key, bool isArray) -> const json& {
        const auto it = root.find(key);
        if (it == root.end()) r.fail(key, what, "nothing (the field is required)");
        if (isArray ? !it->is_array() : !it->is_object())
            r.fail(key, isArray ? "an array" : "an object", describeJson(*it));
        return *it;
    };
    field("scene", false);
    field("size", false);
    const json& lights = field("lights", true);
    for (size_t i = 0; i < lights.size(); ++i) r.requireObject(lights[i], elementPath("lights", i));
    return root;
}

namespace {

// A value as messages print it: numbers like the scene reader ("0.5"), arrays "[0, 4, 0]".
std::string show(const json& v) {
    if (v.is_number()) return formatNumber(v.get<double>());
    if (v.is_string()) return v.get<std::string>();
    if (v.is_array()) {
        std::string out = "[";
        for (size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + show(v[i]);
        return out + "]";
    }
    return v.dump();
}

// Equal up to float round-off: both sides were written from floats, but by different builds.
bool same(const json& a, const json& b) {
    if (a.is_number() && b.is_number()) {
        const double x = a.get<double>(), y = b.get<double>();
        return x == y || std::abs(x - y) <= 1e-6 * std::max(std::abs(x), std::abs(y));
    }
    if (a.is_array() && b.is_array() && a.size() == b.size()) {
        for (size_t i = 0; i < a.size(); ++i)
            if (!same(a[i], b[i])) return false;
        return true;
    }
    return a == b;
}

json at(const json& record, const std::string& key) {
    const auto it = record.find(key);
    return it == record.end() ? json() : *it;
}

std::string lightLabel(size_t index, const json& light) {
    return "light " + std::to_string(index) + " \"" + at(light, "name").get<std::string>() + "\"";
}

// Calls f(label, lightA, lightB) for each light both records have.
template <class F>
void forEachLightPair(const json& a, const json& b, F f) {
    const json la = at(a, "lights"), lb = at(b, "lights");
    const size_t n = std::min(la.size(), lb.size());
    for (size_t i = 0; i < n; ++i) {
        const std::string label =
            at(la[i], "name").is_string() ? lightLabel(i, la[i]) : "light " + std::to_string(i);
        f(label, la[i], lb[i]);
    }
}

}  // namespace

std::vector<std::string> provenanceDifferences(const json& a, const json& b) {
    std::vector<std::string> out;
    const json sa = at(a, "scene"), sb = at(b, "scene");
    if (!same(at(sa, "name"), at(sb, "name"))) {
        out.push_back("scene: " + show(at(sa, "name")) + " (" + show(at(sa, "file")) + ") vs " +
                      show(at(sb, "name")) + " (" + show(at(sb, "file")) + ")");
    }
    const json za = at(a, "size"), zb = at(b, "size");
    if (!same(za, zb)) {
        out.push_back("size: " + show(at(za, "width")) + "x" + show(at(za, "height")) + " vs " +
                      show(at(zb, "width")) + "x" + show(at(zb, "height")));
    }
    const size_t na = at(a, "lights").size(), nb = at(b, "lights").size();
    if (na != nb) {
        out.push_back("lights: " + std::to_string(na) + " vs " + std::to_string(nb) + " lights");
    }
    static const char* kLightFields[] = {"name",  "shape",     "position",     "direction", "up",
                                         "size",  "color",     "intensity", "casts_shadows"};
    forEachLightPair(a, b, [&](const std::string& label, const json& la, const json& lb) {
        for (const char* key : kLightFields) {
            if (!same(at(la, key), at(lb, key))) {
                out.push_back(label + ": " + key + " " + show(at(la, key)) + " vs " +
                              show(at(lb, key)));
            }
        }
    });
    return out;
}

std::vector<std::string> techniqueDifferences(const json& a, const json& b) {
    std::vector<std::string> out;
    forEachLightPair(a, b, [&](const std::string& label, const json& la, const json& lb) {
        if (!same(at(la, "technique"), at(lb, "technique"))) {
            out.push_back(label + ": technique " + show(at(la, "technique")) + " vs " +
                          show(at(lb, "technique")));
            return;  // parameters of different techniques are not comparable
        }
        const json pa = at(la, "parameters"), pb = at(lb, "parameters");
        if (!pa.is_object() || !pb.is_object()) return;
        for (const auto& [key, value] : pa.items()) {
            if (!pb.contains(key) || !same(value, pb[key])) {
                out.push_back(label + ": " + key + " " + show(value) + " vs " +
                              (pb.contains(key) ? show(pb[key]) : std::string("(none)")));
            }
        }
    });
    return out;
}

}  // namespace shadowlab
