// Figure specifications (assets/figures/README.md): see figure_spec.h.
#include "bench/figure_spec.h"

#include "error.h"
#include "graph/technique.h"

namespace shadowlab {

using json = nlohmann::json;

namespace {

std::vector<std::pair<std::string, std::string>> readSets(const JsonReader& r, const json& v, const std::string& path) {
    if (!v.is_object()) r.fail(path, "an object {key: value}", describeJson(v));
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [k, x] : v.items()) out.push_back({k, specValueText(r, x, fieldPath(path, k))});
    return out;
}

// A label's text: at most kMaxFigureLabel characters (labels are wrapped into a cell; a
// 200,000-character title took 29 s to fit).
constexpr size_t kMaxFigureLabel = 1000;
std::string labelText(const JsonFields& f, const std::string& key) {
    std::string text = f.string(key, "");
    if (text.size() > kMaxFigureLabel)
        f.reader().fail(f.path(key), "a text of at most " + std::to_string(kMaxFigureLabel) + " characters",
                        "a text of " + std::to_string(text.size()));
    return text;
}

}  // namespace

FigureSpec parseFigureSpec(const JsonDocument& doc) {
    const JsonReader r(doc);
    const JsonFields top(r, doc.root(), "",
                         {"title", "size", "supersample", "frames", "warmup", "show", "reference", "rows", "columns",
                          "insets", "error_maps", "error_max", "text_scale"});
    FigureSpec spec;
    spec.title = labelText(top, "title");
    if (const json* size = top.find("size")) {
        if (!size->is_array() || size->size() != 2) r.fail("size", "[width, height] of each cell", describeJson(*size));
        spec.width = int(r.integer((*size)[0], "size[0]", 16, 4096));
        spec.height = int(r.integer((*size)[1], "size[1]", 16, 4096));
    }
    spec.supersample = int(top.integer("supersample", 1, 1, 8));
    if (spec.width * spec.supersample > 8192 || spec.height * spec.supersample > 8192)
        r.fail("supersample", "a factor keeping size x supersample within 8192", std::to_string(spec.supersample));
    spec.frames = int(top.integer("frames", 3, 1, 1000));
    spec.warmup = int(top.integer("warmup", 1, 0, 100));
    spec.show = top.oneOf("show", {"image", "visibility"}, "image");
    if (top.find("reference")) spec.reference = parseReferenceSpec(top.string("reference"), r.place("reference"));
    spec.errorMaps = top.boolean("error_maps", true);
    spec.errorMax = top.number("error_max", 0.0, inRange(0.0, 1.0));
    spec.textScale = int(top.integer("text_scale", 0, 0, 8));

    const json& columns = top.require("columns", "an array of columns");
    if (!columns.is_array() || columns.empty()) r.fail("columns", "a non-empty array of columns", describeJson(columns));
    for (size_t i = 0; i < columns.size(); ++i) {
        const std::string p = elementPath("columns", i);
        const JsonFields f(r, columns[i], p, {"technique", "set", "label"});
        FigureColumn c;
        c.setting.technique = f.string("technique");
        const TechniqueDesc* d = findTechnique(c.setting.technique);
        if (!d) {
            std::string ids;
            for (const TechniqueDesc* t : allTechniques()) ids += (ids.empty() ? "" : ", ") + t->id;
            r.fail(f.path("technique"), "a registered technique (" + ids + ")", describeJson(f.require("technique", "a technique")));
        }
        if (const json* set = f.find("set")) {
            c.setting.sets = readSets(r, *set, f.path("set"));
            ParamValues check(*d);
            for (const auto& [k, v] : c.setting.sets) check.set(*d, k, v, r.place(fieldPath(f.path("set"), k)));
        }
        c.label = labelText(f, "label");
        spec.columns.push_back(c);
    }

    const json& rows = top.require("rows", "an array of rows");
    if (!rows.is_array() || rows.empty()) r.fail("rows", "a non-empty array of rows", describeJson(rows));
    for (size_t i = 0; i < rows.size(); ++i) {
        const std::string p = elementPath("rows", i);
        const JsonFields f(r, rows[i], p, {"scene", "light_size", "set", "label", "camera"});
        FigureRow row;
        row.scene = f.string("scene");
        Scene scene;
        try {
            scene = loadScene(row.scene);
        } catch (const InputError& e) {
            throw InputError(r.place(f.path("scene")) + ": cannot load the scene \"" + row.scene + "\": " + e.what());
        }
        if (f.find("light_size")) row.lightSize = float(f.number("light_size", inRange(0.0, 1e6)));
        if (const json* set = f.find("set")) {
            row.sets = readSets(r, *set, f.path("set"));
            // Each key must belong to some column's technique, and be valid there.
            for (const auto& [k, v] : row.sets) {
                bool used = false;
                for (const FigureColumn& c : spec.columns) {
                    const TechniqueDesc& d = requireTechnique(c.setting.technique, "columns");
                    if (!d.findParam(k)) continue;
                    used = true;
                    ParamValues check(d);
                    check.set(d, k, v, r.place(fieldPath(f.path("set"), k)));
                }
                if (!used) r.fail(fieldPath(f.path("set"), k), "a parameter of one of the columns' techniques", "\"" + k + "\"");
            }
        }
        row.label = labelText(f, "label");
        if (f.find("camera")) {
            const JsonFields c = f.object("camera", {"position", "target", "up", "fov_deg"});
            Camera cam = scene.camera;
            cam.position = c.vec3("position", cam.position);
            cam.target = c.vec3("target", cam.target);
            cam.up = c.vec3("up", cam.up);
            cam.fovYDegrees = float(c.number("fov_deg", cam.fovYDegrees, inOpenRange(0.0, 180.0)));
            row.camera = cam;
        }
        spec.rows.push_back(row);
    }

    if (const json* insets = top.find("insets")) {
        if (!insets->is_array()) r.fail("insets", "an array of insets", describeJson(*insets));
        for (size_t i = 0; i < insets->size(); ++i) {
            const std::string p = elementPath("insets", i);
            const JsonFields f(r, (*insets)[i], p, {"rect", "row"});
            const json& rect = f.require("rect", "[x, y, width, height] in cell pixels");
            if (!rect.is_array() || rect.size() != 4) r.fail(f.path("rect"), "[x, y, width, height] in cell pixels", describeJson(rect));
            Inset in;
            in.x = int(r.integer(rect[0], elementPath(f.path("rect"), 0), 0, spec.width - 1));
            in.y = int(r.integer(rect[1], elementPath(f.path("rect"), 1), 0, spec.height - 1));
            in.w = int(r.integer(rect[2], elementPath(f.path("rect"), 2), 2, spec.width - in.x));
            in.h = int(r.integer(rect[3], elementPath(f.path("rect"), 3), 2, spec.height - in.y));
            if (f.find("row")) in.row = int(f.integer("row", 0, int64_t(spec.rows.size()) - 1));
            spec.insets.push_back(in);
        }
    }
    return spec;
}

json specJson(const FigureSpec& s) {
    json j{{"title", s.title},
           {"size", {s.width, s.height}},
           {"supersample", s.supersample},
           {"frames", s.frames},
           {"warmup", s.warmup},
           {"show", s.show},
           {"reference", s.reference.technique + ":" + std::to_string(s.reference.count)},
           {"error_maps", s.errorMaps},
           {"error_max", s.errorMax},
           {"text_scale", s.textScale}};
    auto setsJson = [](const std::vector<std::pair<std::string, std::string>>& sets) {
        json o = json::object();
        for (const auto& [k, v] : sets) o[k] = v;
        return o;
    };
    j["columns"] = json::array();
    for (const FigureColumn& c : s.columns)
        j["columns"].push_back({{"technique", c.setting.technique}, {"set", setsJson(c.setting.sets)}, {"label", c.label}});
    j["rows"] = json::array();
    for (const FigureRow& r : s.rows) {
        json row{{"scene", r.scene}, {"set", setsJson(r.sets)}, {"label", r.label}};
        if (r.lightSize) row["light_size"] = *r.lightSize;
        if (r.camera)
            row["camera"] = {{"position", {r.camera->position.x, r.camera->position.y, r.camera->position.z}},
                             {"target", {r.camera->target.x, r.camera->target.y, r.camera->target.z}},
                             {"up", {r.camera->up.x, r.camera->up.y, r.camera->up.z}},
                             {"fov_deg", r.camera->fovYDegrees}};
        j["rows"].push_back(row);
    }
    j["insets"] = json::array();
    for (const Inset& in : s.insets) {
        json i{{"rect", {in.x, in.y, in.w, in.h}}};
        if (in.row) i["row"] = *in.row;
        j["insets"].push_back(i);
    }
    return j;
}

FigureSidecar readFigureSidecar(const JsonDocument& doc) {
    const JsonReader r(doc);
    const json& root = doc.root();
    r.requireObject(root, "");
    auto field = [&](const char* key) -> const json* {
        const auto it = root.find(key);
        return it == root.end() ? nullptr : &*it;
    };
    if (!field("shadowlab_figure") || !field("spec") || !field("cells"))
        r.fail("", "a figure sidecar (with shadowlab_figure, spec and cells)", "another JSON object");
    FigureSidecar side;
    r.integer(*field("shadowlab_figure"), "shadowlab_figure", 1, 1);
    r.requireObject(*field("spec"), "spec");
    side.spec = field("spec")->dump();
    if (const json* v = field("spec_file")) side.specFile = r.string(*v, "spec_file");
    if (const json* v = field("out")) side.out = r.string(*v, "out");
    if (const json* v = field("date")) side.date = r.string(*v, "date");
    if (const json* v = field("error_max")) side.errorMax = float(r.number(*v, "error_max", greaterThan(0.0)));
    const json& cells = *field("cells");
    if (!cells.is_array()) r.fail("cells", "an array of the figure's cells", describeJson(cells));
    for (size_t i = 0; i < cells.size(); ++i) {
        const std::string p = elementPath("cells", i);
        r.requireObject(cells[i], p);
        FigureSidecar::OldCell c;
        const auto label = cells[i].find("label_shadow_ms");
        if (label == cells[i].end()) r.fail(fieldPath(p, "label_shadow_ms"), "a number >= 0", "nothing (the field is required)");
        c.labelShadowMs = r.number(*label, fieldPath(p, "label_shadow_ms"), inRange(0.0, 1e9));
        const auto rmse = cells[i].find("rmse");
        if (rmse != cells[i].end() && !rmse->is_null()) c.rmse = r.number(*rmse, fieldPath(p, "rmse"), atLeast(0.0));
        side.cells.push_back(c);
    }
    return side;
}

}  // namespace shadowlab
