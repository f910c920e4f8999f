// Bench specifications (assets/bench/README.md): reading and validating them, expanding sweeps
// into settings.
#include <algorithm>
#include <cmath>
#include <set>

#include "bench/bench.h"
#include "error.h"
#include "graph/technique.h"
#include "scene/json_reader.h"

namespace shadowlab {

using json = nlohmann::json;

std::string specValueText(const JsonReader& r, const nlohmann::json& v, const std::string& path) {
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_string()) return v.get<std::string>();
    if (v.is_number()) return formatNumber(r.number(v, path));
    r.fail(path, "a number, true/false or an enum name", describeJson(v));
}

bool paperRowMatches(const PaperRow& row, const std::string& scene, double lightSize, const std::string& technique,
                     const nlohmann::json& parameters) {
    if (row.technique != technique) return false;
    if (!row.scene.empty() && row.scene != scene) return false;
    if (row.lightSize && std::abs(*row.lightSize - lightSize) > 1e-6 * std::max(1.0, std::abs(lightSize))) return false;
    for (const auto& [key, value] : row.params) {
        if (!parameters.contains(key)) return false;
        const json& v = parameters[key];
        double x = v.is_number() ? v.get<double>() : v.is_boolean() ? double(v.get<bool>()) : NAN;
        if (v.is_string()) {
            const TechniqueDesc* d = findTechnique(technique);
            const ParamDesc* p = d ? d->findParam(key) : nullptr;
            if (p) {
                auto it = std::find(p->choices.begin(), p->choices.end(), v.get<std::string>());
                x = double(it - p->choices.begin());
            }
        }
        if (!(std::abs(x - value) <= 1e-6 * std::max(1.0, std::abs(value)))) return false;
    }
    return true;
}

bool isPlannedTechnique(const std::string& id) {
    static const std::set<std::string> planned = {"hard", "pcf",  "pcss", "sssm",      "ssm-gbp06", "ssm-contour",
                                                  "ssv",  "pvm",  "pvmf", "spsm",      "reference", "raytraced"};
    return findTechnique(id) != nullptr || planned.count(id) > 0;
}

std::vector<Setting> RunSpec::settings() const {
    std::vector<Setting> out = {Setting{technique, fixed}};
    for (const auto& [key, values] : sweep) {
        std::vector<Setting> next;
        for (const Setting& s : out)
            for (const std::string& v : values) {
                Setting t = s;
                t.sets.push_back({key, v});
                next.push_back(t);
            }
        out = next;
    }
    return out;
}

double RunSpec::settingCount() const {
    double n = 1.0;
    for (const auto& [key, values] : sweep) n = std::min(1e300, n * double(values.size()));
    return n;
}

double benchSettingCount(const BenchSpec& spec) {
    double perScene = 0.0;
    for (const RunSpec& run : spec.runs) perScene = std::min(1e300, perScene + run.settingCount());
    return std::min(1e300, perScene * double(spec.scenes.size()) * double(spec.lightSizes.size()) *
                               double(spec.cameraDistances.size()));
}

void checkBenchSettingCount(const BenchSpec& spec, double maxSettings, const std::string& where) {
    const double n = benchSettingCount(spec);
    const std::string made = std::to_string(spec.scenes.size()) + " scene(s) x " +
                             std::to_string(spec.cameraDistances.size()) + " camera distance(s) x " +
                             std::to_string(spec.lightSizes.size()) + " light size(s) x the runs' sweeps";
    if (n < 1.0) throw InputError(where + ": the bench would measure no setting (" + made + "), expected at least one");
    if (n > maxSettings)
        throw InputError(where + ": the bench would measure " + formatNumber(n) + " settings (" + made +
                         "), over the limit of " + formatNumber(maxSettings) + " (--max-settings N raises it)");
}

// "a:b:n": n values from a to b inclusive (n >= 2), or n = 1: a. Integer parameters round to the
// nearest whole number; the table then validates each value.
std::vector<std::string> expandRange(const std::string& text, const std::string& where, bool integer) {
    double a = 0, b = 0;
    long n = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%lf:%lf:%ld%c", &a, &b, &n, &extra) != 3 || !std::isfinite(a) || !std::isfinite(b) ||
        n < 1 || n > 1000)
        throw InputError(where + ": expected a range a:b:n (numbers a, b and a count n in 1..1000), got '" + text + "'");
    std::vector<std::string> out;
    for (long i = 0; i < n; ++i) {
        double v = n == 1 ? a : a + (b - a) * double(i) / double(n - 1);
        if (integer) v = std::round(v);
        std::string t = formatNumber(v);
        if (std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
    }
    return out;
}

Scene benchScene(const Scene& scene, double distance) {
    Scene s = scene;
    if (distance == 1.0) return s;
    const glm::vec3 target = s.camera.target, from = s.camera.position;
    s.camera.position = target + float(distance) * (from - target);
    const float reach = float(distance) * glm::length(from - target);
    s.camera.farPlane = std::max(s.camera.farPlane, s.camera.farPlane - glm::length(from - target) + reach);
    return s;
}

std::string benchSceneLabel(const std::string& name, double distance, const std::vector<double>& distances) {
    if (distances.size() == 1 && distances[0] == 1.0) return name;
    return name + " camera " + formatNumber(distance) + "x";
}

BenchSpec loadBenchSpec(const std::string& path, double maxSettings) {
    const JsonDocument doc = JsonDocument::fromFile(path, "bench spec");
    const JsonReader r(doc);
    const JsonFields top(r, doc.root(), "",
                         {"name", "title", "reproduces", "scenes", "light_sizes", "camera_distances", "size",
                          "frames", "warmup", "reference", "runs", "chart", "paper"});
    BenchSpec spec;
    spec.file = path;
    spec.name = top.string("name");
    spec.title = top.string("title", spec.name);
    spec.reproduces = top.string("reproduces", "");

    const json& scenes = top.require("scenes", "an array of scene names");
    if (!scenes.is_array() || scenes.empty()) r.fail("scenes", "a non-empty array of scene names", describeJson(scenes));
    for (size_t i = 0; i < scenes.size(); ++i) {
        const std::string p = elementPath("scenes", i);
        std::string name = r.string(scenes[i], p, "a scene name");
        try {
            (void)loadScene(name);
        } catch (const InputError& e) {
            throw InputError(r.place(p) + ": cannot load the scene \"" + name + "\": " + e.what());
        }
        spec.scenes.push_back(name);
    }
    if (const json* ls = top.find("light_sizes")) {
        if (!ls->is_array() || ls->empty()) r.fail("light_sizes", "a non-empty array of sizes >= 0 or \"scene\"", describeJson(*ls));
        spec.lightSizes.clear();
        for (size_t i = 0; i < ls->size(); ++i) {
            const std::string p = elementPath("light_sizes", i);
            if ((*ls)[i].is_string() && (*ls)[i].get<std::string>() == "scene")
                spec.lightSizes.push_back(std::nullopt);
            else
                spec.lightSizes.push_back(float(r.number((*ls)[i], p, inRange(0.0, 1e6))));
        }
    }
    if (const json* cd = top.find("camera_distances")) {
        if (!cd->is_array() || cd->empty())
            r.fail("camera_distances", "a non-empty array of distances > 0 (times the scene camera's)", describeJson(*cd));
        spec.cameraDistances.clear();
        for (size_t i = 0; i < cd->size(); ++i) {
            const std::string p = elementPath("camera_distances", i);
            const double d = r.number((*cd)[i], p, inRange(1e-3, 1e3));
            if (std::find(spec.cameraDistances.begin(), spec.cameraDistances.end(), d) != spec.cameraDistances.end())
                r.fail(p, "distances that differ from one another", formatNumber(d) + " twice");
            spec.cameraDistances.push_back(d);
        }
    }
    if (const json* size = top.find("size")) {
        if (!size->is_array() || size->size() != 2) r.fail("size", "[width, height]", describeJson(*size));
        spec.width = int(r.integer((*size)[0], "size[0]", 1, 8192));
        spec.height = int(r.integer((*size)[1], "size[1]", 1, 8192));
    }
    spec.frames = int(top.integer("frames", 5, 1, 10000));
    spec.warmup = int(top.integer("warmup", 2, 0, 1000));
    if (top.find("reference")) spec.reference = parseReferenceSpec(top.string("reference"), r.place("reference"));

    // "runs": an array of runs; the string "all" (alone or as an element) stands for every registered
    // technique at its defaults, so the list grows as techniques land.
    const json& runsField = top.require("runs", "an array of runs, or \"all\"");
    const json runs = runsField.is_string() ? json::array({runsField}) : runsField;
    if (!runs.is_array() || runs.empty()) r.fail("runs", "a non-empty array of runs, or \"all\"", describeJson(runsField));
    for (size_t i = 0; i < runs.size(); ++i) {
        const std::string p = runsField.is_string() ? std::string("runs") : elementPath("runs", i);
        if (runs[i].is_string()) {
            if (runs[i].get<std::string>() != "all") r.fail(p, "a run object or \"all\"", describeJson(runs[i]));
            for (const TechniqueDesc* d : allTechniques()) spec.runs.push_back(RunSpec{d->id, {}, {}});
            continue;
        }
        {
            const JsonFields f(r, runs[i], p, {"technique", "sweep", "set"});
            RunSpec run;
            run.technique = f.string("technique");
            const TechniqueDesc* desc = findTechnique(run.technique);
            if (!desc) {
                std::string ids;
                for (const TechniqueDesc* d : allTechniques()) ids += (ids.empty() ? "" : ", ") + d->id;
                r.fail(f.path("technique"), "a registered technique (" + ids + ")", describeJson(f.require("technique", "a technique")));
            }
            ParamValues check(*desc);
            if (const json* set = f.find("set")) {
                if (!set->is_object()) r.fail(f.path("set"), "an object {key: value}", describeJson(*set));
                for (const auto& [key, v] : set->items()) {
                    const std::string kp = fieldPath(f.path("set"), key);
                    std::string text = specValueText(r, v, kp);
                    check.set(*desc, key, text, r.place(kp));
                    run.fixed.push_back({key, text});
                }
            }
            if (const json* sweep = f.find("sweep")) {
                if (!sweep->is_object()) r.fail(f.path("sweep"), "an object {key: [values] or \"a:b:n\"}", describeJson(*sweep));
                for (const auto& [key, v] : sweep->items()) {
                    const std::string kp = fieldPath(f.path("sweep"), key);
                    const ParamDesc* pd = desc->findParam(key);
                    if (!pd) check.set(*desc, key, "0", r.place(kp));  // throws: unknown parameter, with the list
                    for (const auto& [fixedKey, fixedValue] : run.fixed)
                        if (fixedKey == key)
                            r.fail(kp, "a parameter that the run's \"set\" does not already fix",
                                   "\"" + key + "\", fixed to " + fixedValue + " in set");
                    std::vector<std::string> values;
                    if (v.is_string()) {
                        values = expandRange(v.get<std::string>(), r.place(kp), pd->type != ParamDesc::Type::Float);
                    } else if (v.is_array() && !v.empty()) {
                        for (size_t k = 0; k < v.size(); ++k) values.push_back(specValueText(r, v[k], elementPath(kp, k)));
                    } else {
                        r.fail(kp, "a non-empty array of values or a range \"a:b:n\"", describeJson(v));
                    }
                    for (size_t k = 0; k < values.size(); ++k)
                        check.set(*desc, key, values[k], r.place(v.is_array() ? elementPath(kp, k) : kp));
                    run.sweep.push_back({key, values});
                }
            }
            spec.runs.push_back(run);
        }
    }
    // Counted before any setting is built (the paper's rows below build them).
    checkBenchSettingCount(spec, maxSettings, r.place("runs"));

    if (top.find("chart")) {
        const JsonFields c = top.object("chart", {"error"});
        spec.errorMetric = c.oneOf("error", {"rmse", "1-ssim"}, "rmse");
    }

    if (top.find("paper")) {
        const JsonFields p = top.object("paper", {"citation", "what", "machine", "note", "compare", "baseline", "columns", "rows"});
        PaperSpec& paper = spec.paper;
        paper.present = true;
        paper.citation = p.string("citation");
        paper.what = p.string("what", "");
        paper.machine = p.string("machine", "");
        paper.note = p.string("note", "");
        paper.compare = p.oneOf("compare", {"ratio", "absolute"}, "ratio");
        const json& columns = p.require("columns", "an object {paper column: CSV column}");
        if (!columns.is_object() || columns.empty())
            r.fail(p.path("columns"), "a non-empty object {paper column: CSV column}", describeJson(columns));
        const auto& fixed = fixedCsvColumns();
        for (const auto& [name, v] : columns.items()) {
            const std::string cp = fieldPath(p.path("columns"), name);
            std::string column = r.string(v, cp, "a CSV column name");
            bool ok = std::find(fixed.begin(), fixed.end(), column) != fixed.end();
            if (!ok && column.rfind("ms.", 0) == 0) {
                // "ms.<technique>/<pass>" or "ms.gbuffer" / "ms.shade": the technique's descriptor names its passes.
                std::string pass = column.substr(3);
                size_t slash = pass.find('/');
                if (slash == std::string::npos) {
                    ok = pass == "gbuffer" || pass == "shade";
                } else if (const TechniqueDesc* d = findTechnique(pass.substr(0, slash))) {
                    for (const PassDesc& pd : d->passes) ok = ok || pd.name == pass.substr(slash + 1);
                } else {
                    ok = isPlannedTechnique(pass.substr(0, slash));
                }
            }
            if (!ok)
                r.fail(cp, "a CSV column (shadow_ms, fixed_ms, total_ms, rmse, psnr, ssim, penumbra_rmse, ..., or "
                           "ms.<technique>/<pass> naming a pass of the technique)",
                       describeJson(v));
            paper.columns.push_back({name, column});
        }
        const json& rows = p.require("rows", "an array of rows");
        if (!rows.is_array() || rows.empty()) r.fail(p.path("rows"), "a non-empty array of rows", describeJson(rows));
        for (size_t i = 0; i < rows.size(); ++i) {
            const std::string rp = elementPath(p.path("rows"), i);
            const JsonFields f(r, rows[i], rp, {"label", "scene", "light_size", "technique", "params", "values"});
            PaperRow row;
            row.place = r.place(rp);
            row.label = f.string("label");
            row.scene = f.string("scene", "");
            if (!row.scene.empty() && std::find(spec.scenes.begin(), spec.scenes.end(), row.scene) == spec.scenes.end())
                r.fail(f.path("scene"), "one of the spec's scenes", describeJson(f.require("scene", "a scene")));
            if (f.find("light_size")) row.lightSize = f.number("light_size", inRange(0.0, 1e6));
            row.technique = f.string("technique");
            if (!isPlannedTechnique(row.technique))
                r.fail(f.path("technique"), "a technique id of DESIGN.md section 4", describeJson(f.require("technique", "a technique")));
            if (const json* params = f.find("params")) {
                if (!params->is_object()) r.fail(f.path("params"), "an object {key: value}", describeJson(*params));
                const TechniqueDesc* d = findTechnique(row.technique);
                for (const auto& [key, v] : params->items()) {
                    const std::string kp = fieldPath(f.path("params"), key);
                    std::string text = specValueText(r, v, kp);
                    if (d) {
                        ParamValues pv(*d);
                        pv.set(*d, key, text, r.place(kp));
                        row.params[key] = pv.get(key);
                    } else {
                        row.params[key] = v.is_number() ? v.get<double>() : 0.0;
                    }
                }
            }
            const json& values = f.require("values", "an object {paper column: number}");
            if (!values.is_object() || values.empty())
                r.fail(f.path("values"), "a non-empty object {paper column: number}", describeJson(values));
            for (const auto& item : values.items()) {
                // Not a structured binding: clang 14 (the fuzz build) cannot capture one in a lambda.
                const std::string& name = item.key();
                const json& v = item.value();
                const std::string vp = fieldPath(f.path("values"), name);
                bool known = std::any_of(paper.columns.begin(), paper.columns.end(), [&](const auto& c) { return c.first == name; });
                if (!known) r.fail(vp, "a column named in paper.columns", "the unknown column \"" + name + "\"");
                row.values.push_back({name, r.number(v, vp)});
            }
            paper.rows.push_back(row);
        }
        // Every row of a registered technique must name a setting the spec runs.
        for (const PaperRow& row : paper.rows) {
            const TechniqueDesc* d = findTechnique(row.technique);
            if (!d) continue;
            bool matched = false;
            for (const RunSpec& run : spec.runs) {
                if (run.technique != row.technique) continue;
                for (const Setting& s : run.settings()) {
                    ParamValues pv(*d);
                    for (const auto& [k, v] : s.sets) pv.set(*d, k, v, "setting");
                    nlohmann::json values = nlohmann::json::object();
                    for (const auto& [k, v] : pv.values()) values[k] = v;
                    matched = matched || paperRowMatches(row, row.scene, row.lightSize.value_or(0.0), row.technique, values);
                }
            }
            if (!matched)
                throw InputError(row.place + ": technique and params: no run of the spec has this setting (" +
                                 row.technique + " with the row's params); add it to runs or fix the row");
        }
        if (paper.compare == "ratio") {
            paper.baseline = p.string("baseline", paper.rows.front().label);
            bool found = std::any_of(paper.rows.begin(), paper.rows.end(), [&](const PaperRow& row) { return row.label == paper.baseline; });
            if (!found) r.fail(p.path("baseline"), "the label of one of paper.rows", "the string \"" + paper.baseline + "\"");
        }
    }
    return spec;
}

}  // namespace shadowlab
