#include "lesson/lesson.h"
#include "scene/input_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "error.h"
#include "lesson/html.h"
#include "views.h"

namespace fs = std::filesystem;

namespace shadowlab {

namespace {

std::string joinList(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
    return out;
}

std::string trim(const std::string& s) {
    size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    size_t b = s.find_last_not_of(" \t\r");
    return s.substr(a, b - a + 1);
}

std::string formatValue(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

// A finite number, the whole word; else InputError naming `what`.
double parseNumber(const std::string& text, const SourceLocation& where, const std::string& what) {
    char* end = nullptr;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError(where.str() + ": " + what + ": expected a finite number, got '" + text + "'");
    // Every lesson number ends in a float (light, camera, picks, parameters, thresholds): checked in
    // that type, so "light position 1e300 4 0" is refused here instead of becoming infinity.
    if (std::abs(v) > double(std::numeric_limits<float>::max()))
        throw InputError(where.str() + ": " + what + ": expected a finite number in a float's range (|x| <= 3.4e38), got '" +
                         text + "'");
    return v;
}

// The light size's limits, the same whether it is set (light size, light.size=S) or animated.
constexpr double kMaxLessonLightSize = 1000.0;
void checkLightSize(double v, const std::string& at, const std::string& text) {
    if (v < 0.0 || v > kMaxLessonLightSize)
        throw InputError(at + ": expected a value in [0, 1000], got " + text);
}

// Scenes are loaded once per process for validation (a lesson names few).
const Scene& sceneNamed(const std::string& name, const SourceLocation& where) {
    static std::map<std::string, std::unique_ptr<Scene>> cache;
    auto it = cache.find(name);
    if (it != cache.end()) return *it->second;
    std::vector<std::string> names = listScenes();
    if (std::find(names.begin(), names.end(), name) == names.end())
        throw InputError(where.str() + ": unknown scene '" + name + "' (scenes: " + joinList(names) + ")");
    try {
        auto scene = std::make_unique<Scene>(loadScene(name));
        return *cache.emplace(name, std::move(scene)).first->second;
    } catch (const InputError& e) {
        throw InputError(where.str() + ": scene '" + name + "' does not load: " + e.what());
    }
}

// Splits a command line into words; "double quotes" group words.
std::vector<std::string> splitWords(const std::string& line, const SourceLocation& where) {
    std::vector<std::string> words;
    std::string word;
    bool inQuote = false, have = false;
    for (char c : line) {
        if (c == '"') {
            inQuote = !inQuote;
            have = true;
        } else if (!inQuote && (c == ' ' || c == '\t')) {
            if (have) words.push_back(word);
            word.clear();
            have = false;
        } else {
            word += c;
            have = true;
        }
    }
    if (inQuote) throw InputError(where.str() + ": unclosed quote in '" + line + "'");
    if (have) words.push_back(word);
    return words;
}

const std::vector<std::string> kStateCommands = {"scene", "technique", "set",  "light", "camera",
                                                 "show",  "hide",      "pick", "split", "reference"};
const std::vector<std::string> kStepCommands = {"animate", "try", "check", "answer", "expect"};

std::vector<std::string> allCommands() {
    std::vector<std::string> all = kStateCommands;
    all.insert(all.end(), kStepCommands.begin(), kStepCommands.end());
    return all;
}

void expectArgs(const LessonCommand& c, size_t lo, size_t hi, const std::string& usage) {
    if (c.args.size() < lo || c.args.size() > hi)
        throw InputError(c.where.str() + ": " + c.name + ": expected '" + usage + "', got " +
                         std::to_string(c.args.size()) + " argument(s)");
}

glm::vec3 parseVec3(const LessonCommand& c, size_t& i, const std::string& key) {
    if (i + 3 > c.args.size())
        throw InputError(c.where.str() + ": " + c.name + " " + key + ": expected three numbers x y z");
    glm::vec3 v;
    for (int k = 0; k < 3; ++k) v[k] = float(parseNumber(c.args[i + k], c.where, c.name + " " + key));
    i += 3;
    return v;
}

LightShape parseShape(const std::string& text, const SourceLocation& where) {
    for (LightShape s : {LightShape::Point, LightShape::Square, LightShape::Disk, LightShape::Sphere})
        if (text == lightShapeName(s)) return s;
    throw InputError(where.str() + ": light shape: expected one of point, square, disk, sphere, got '" + text + "'");
}

void applyLight(LessonState& state, const LessonCommand& c) {
    if (state.scene.empty()) throw InputError(c.where.str() + ": light: no scene yet (give 'scene NAME' first)");
    size_t i = 0;
    size_t index = 0;
    if (!c.args.empty() && std::isdigit(static_cast<unsigned char>(c.args[0][0]))) {
        double n = parseNumber(c.args[0], c.where, "light index");
        if (n != std::floor(n) || n < 0 || n >= double(state.lights.size()))
            throw InputError(c.where.str() + ": light: index " + c.args[0] + " out of range (the scene has " +
                             std::to_string(state.lights.size()) + " light(s))");
        index = size_t(n);
        i = 1;
    }
    if (state.lights.empty()) throw InputError(c.where.str() + ": light: the scene has no light");
    if (i >= c.args.size())
        throw InputError(c.where.str() + ": light: expected key value pairs (keys: shape, size, position, direction, up, "
                                         "intensity) or 'reset'");
    Light& light = state.lights[index];
    const std::string keys = "shape, size, position, direction, up, intensity, reset";
    while (i < c.args.size()) {
        const std::string key = c.args[i++];
        if (key == "reset") {
            light = sceneNamed(state.scene, c.where).lights.at(index);
            continue;
        }
        if (key == "position" || key == "direction" || key == "up") {
            glm::vec3 v = parseVec3(c, i, key);
            if (key != "position") {
                if (glm::length(v) == 0.0f) throw InputError(c.where.str() + ": light " + key + ": expected a non-zero vector");
                v = glm::normalize(v);
            }
            (key == "position" ? light.position : key == "direction" ? light.direction : light.up) = v;
            continue;
        }
        if (i >= c.args.size()) throw InputError(c.where.str() + ": light " + key + ": expected a value");
        const std::string value = c.args[i++];
        if (key == "shape") {
            light.shape = parseShape(value, c.where);
            if (light.shape == LightShape::Point) light.size = 0.0f;
        } else if (key == "size") {
            double v = parseNumber(value, c.where, "light size");
            checkLightSize(v, c.where.str() + ": light size", value);
            light.size = float(v);
            if (v > 0.0 && light.shape == LightShape::Point) light.shape = LightShape::Square;
        } else if (key == "intensity") {
            double v = parseNumber(value, c.where, "light intensity");
            if (v < 0.0) throw InputError(c.where.str() + ": light intensity: expected a value >= 0, got " + value);
            light.intensity = float(v);
        } else {
            throw InputError(c.where.str() + ": light: unknown key '" + key + "' (keys: " + keys + ")");
        }
    }
    if (glm::length(glm::cross(light.direction, light.up)) < 1e-6f)
        throw InputError(c.where.str() + ": light: up is parallel to direction");
    light.up = glm::normalize(light.up - glm::dot(light.up, light.direction) * light.direction);
}

void applyCamera(LessonState& state, const LessonCommand& c) {
    if (state.scene.empty()) throw InputError(c.where.str() + ": camera: no scene yet (give 'scene NAME' first)");
    if (c.args.empty())
        throw InputError(c.where.str() + ": camera: expected key value pairs (keys: position, target, up, fov) or 'reset'");
    Camera& cam = state.camera;
    size_t i = 0;
    while (i < c.args.size()) {
        const std::string key = c.args[i++];
        if (key == "reset") {
            cam = sceneNamed(state.scene, c.where).camera;
        } else if (key == "position") {
            cam.position = parseVec3(c, i, key);
        } else if (key == "target") {
            cam.target = parseVec3(c, i, key);
        } else if (key == "up") {
            cam.up = parseVec3(c, i, key);
        } else if (key == "fov") {
            if (i >= c.args.size()) throw InputError(c.where.str() + ": camera fov: expected a value in degrees");
            double v = parseNumber(c.args[i++], c.where, "camera fov");
            if (v <= 0.0 || v >= 180.0) throw InputError(c.where.str() + ": camera fov: expected a value in (0, 180) degrees");
            cam.fovYDegrees = float(v);
        } else {
            throw InputError(c.where.str() + ": camera: unknown key '" + key + "' (keys: position, target, up, fov, reset)");
        }
    }
    glm::vec3 forward = cam.target - cam.position;
    if (glm::length(forward) == 0.0f) throw InputError(c.where.str() + ": camera: target equals position");
    if (glm::length(glm::cross(forward, cam.up)) < 1e-6f) throw InputError(c.where.str() + ": camera: up is parallel to the view direction");
}

// key value, or key=value.
std::pair<std::string, std::string> keyValue(const LessonCommand& c, size_t& i) {
    const std::string& a = c.args[i++];
    size_t eq = a.find('=');
    if (eq != std::string::npos) {
        if (eq == 0) throw InputError(c.where.str() + ": " + c.name + ": expected key=value, got '" + a + "'");
        return {a.substr(0, eq), a.substr(eq + 1)};
    }
    if (i >= c.args.size()) throw InputError(c.where.str() + ": " + c.name + " " + a + ": expected a value");
    return {a, c.args[i++]};
}

}  // namespace

// ---- state ---------------------------------------------------------------------------------------------
const std::vector<std::string>& lessonViews() {
    // Each is rendered by renderLessonView() (app/lesson/step_views.cpp): the two visibility buffers,
    // the shadow map texel by texel around the casters, and every view of viz/ (listViews()).
    static const std::vector<std::string> views = [] {
        std::vector<std::string> v = {"visibility", "reference", "shadow-map-texels", "accuracy-time"};
        for (const ViewInfo& info : listViews()) v.push_back(info.name);
        return v;
    }();
    return views;
}

static std::vector<std::pair<std::string, std::string>> textsOf(const std::string& id, const ParamValues& values) {
    std::vector<std::pair<std::string, std::string>> out;
    const TechniqueDesc* desc = findTechnique(id);
    if (!desc) return out;
    for (const ParamDesc& p : desc->params)
        out.push_back({p.key, p.type == ParamDesc::Type::Enum ? values.getChoice(p.key) : formatValue(values.get(p.key))});
    return out;
}

std::vector<std::pair<std::string, std::string>> LessonState::paramTexts() const { return textsOf(technique, params); }
std::vector<std::pair<std::string, std::string>> LessonState::referenceParamTexts() const {
    return textsOf(referenceTechnique, referenceParams);
}

static bool sameLight(const Light& a, const Light& b) {
    return a.shape == b.shape && a.position == b.position && a.direction == b.direction && a.up == b.up &&
           a.size == b.size && a.color == b.color && a.intensity == b.intensity && a.castsShadows == b.castsShadows;
}

std::optional<glm::ivec2> pickPixelAt(const LessonPick& pick, const Camera& camera, int width, int height) {
    if (width <= 0 || height <= 0) return std::nullopt;
    if (!pick.world) {
        return glm::ivec2(std::clamp(int(std::floor(pick.fraction.x * float(width))), 0, width - 1),
                          std::clamp(int(std::floor(pick.fraction.y * float(height))), 0, height - 1));
    }
    const glm::vec4 view = camera.viewFromWorld() * glm::vec4(pick.point, 1.0f);
    if (view.z >= 0.0f) return std::nullopt;  // behind the camera (view space looks down -z)
    const glm::vec4 clip = camera.clipFromView(float(width) / float(height)) * view;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    const glm::vec2 p((ndc.x * 0.5f + 0.5f) * float(width), (0.5f - ndc.y * 0.5f) * float(height));
    if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < float(width) && p.y < float(height))) return std::nullopt;
    return glm::ivec2(p);
}

bool LessonState::operator==(const LessonState& o) const {
    if (lights.size() != o.lights.size()) return false;
    for (size_t i = 0; i < lights.size(); ++i)
        if (!sameLight(lights[i], o.lights[i])) return false;
    return scene == o.scene && technique == o.technique && params.values() == o.params.values() &&
           camera.position == o.camera.position && camera.target == o.camera.target && camera.up == o.camera.up &&
           camera.fovYDegrees == o.camera.fovYDegrees && camera.nearPlane == o.camera.nearPlane &&
           camera.farPlane == o.camera.farPlane && views == o.views && pick == o.pick && split == o.split &&
           referenceTechnique == o.referenceTechnique && referenceParams.values() == o.referenceParams.values();
}

std::string LessonState::describe() const {
    std::ostringstream s;
    auto v3 = [](const glm::vec3& v) { return formatValue(v.x) + " " + formatValue(v.y) + " " + formatValue(v.z); };
    s << "scene " << scene << "\ntechnique " << technique;
    for (const auto& [k, v] : paramTexts()) s << " " << k << "=" << v;
    for (size_t i = 0; i < lights.size(); ++i)
        s << "\nlight " << i << " shape " << lightShapeName(lights[i].shape) << " size " << formatValue(lights[i].size)
          << " position " << v3(lights[i].position) << " direction " << v3(lights[i].direction);
    s << "\ncamera position " << v3(camera.position) << " target " << v3(camera.target) << " fov "
      << formatValue(camera.fovYDegrees);
    s << "\nviews";
    for (const std::string& v : views) s << " " << v;
    if (pick && pick->world)
        s << "\npick at " << v3(pick->point);
    else if (pick)
        s << "\npick fraction " << formatValue(pick->fraction.x) << " " << formatValue(pick->fraction.y);
    if (!split.empty()) s << "\nsplit " << split;
    s << "\nreference " << referenceTechnique;
    for (const auto& [k, v] : referenceParamTexts()) s << " " << k << "=" << v;
    return s.str();
}

void applyLessonCommand(LessonState& state, const LessonCommand& c) {
    const std::string at = c.where.str() + ": ";
    if (c.name == "scene") {
        expectArgs(c, 1, 1, "scene NAME");
        const Scene& scene = sceneNamed(c.args[0], c.where);
        state.scene = c.args[0];
        state.lights = scene.lights;
        state.camera = scene.camera;
        state.pick.reset();
    } else if (c.name == "technique") {
        expectArgs(c, 1, 1, "technique ID");
        const TechniqueDesc& desc = requireTechnique(c.args[0], c.where.str());
        state.technique = desc.id;
        state.params = ParamValues(desc);
    } else if (c.name == "set") {
        if (state.technique.empty()) throw InputError(at + "set: no technique yet (give 'technique ID' first)");
        if (c.args.empty()) throw InputError(at + "set: expected 'set KEY VALUE' or 'set KEY=VALUE ...'");
        const TechniqueDesc& desc = *findTechnique(state.technique);
        size_t i = 0;
        while (i < c.args.size()) {
            auto [key, value] = keyValue(c, i);
            state.params.set(desc, key, value, c.where.str());
        }
    } else if (c.name == "light") {
        applyLight(state, c);
    } else if (c.name == "camera") {
        applyCamera(state, c);
    } else if (c.name == "show" || c.name == "hide") {
        if (c.args.empty()) throw InputError(at + c.name + ": expected one or more view names (views: " + joinList(lessonViews()) + ")");
        for (const std::string& v : c.args) {
            if (c.name == "hide" && v == "all") {
                state.views.clear();
                continue;
            }
            if (std::find(lessonViews().begin(), lessonViews().end(), v) == lessonViews().end())
                throw InputError(at + c.name + ": unknown view '" + v + "' (views: " + joinList(lessonViews()) +
                                 (c.name == "hide" ? ", all" : "") + ")");
            if (c.name == "show")
                state.views.insert(v);
            else
                state.views.erase(v);
        }
    } else if (c.name == "pick") {
        const char* usage = "'pick at X Y Z' (a world point), 'pick fraction U V' (of the image, from the top left) or "
                            "'pick none'";
        if (c.args.size() == 1 && c.args[0] == "none") {
            state.pick.reset();
        } else if (c.args.size() == 4 && c.args[0] == "at") {
            LessonPick p;
            p.world = true;
            for (int k = 0; k < 3; ++k) p.point[k] = float(parseNumber(c.args[size_t(k) + 1], c.where, "pick at X Y Z"));
            p.where = c.where;
            state.pick = p;
        } else if (c.args.size() == 3 && c.args[0] == "fraction") {
            double u = parseNumber(c.args[1], c.where, "pick fraction U"), v = parseNumber(c.args[2], c.where, "pick fraction V");
            if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0)
                throw InputError(at + "pick fraction: expected U and V in [0, 1] (fractions of the image from the top left), got " +
                                 c.args[1] + " " + c.args[2]);
            LessonPick p;
            p.world = false;
            p.fraction = glm::vec2(float(u), float(v));
            p.where = c.where;
            state.pick = p;
        } else {
            std::string got;
            for (const std::string& a : c.args) got += (got.empty() ? "" : " ") + a;
            throw InputError(at + "pick: expected " + usage + ", got 'pick " + got + "' (a bare fraction lands elsewhere "
                             "at another size or aspect)");
        }
    } else if (c.name == "split") {
        expectArgs(c, 1, 1, "split reference|TECHNIQUE|off");
        if (c.args[0] == "off")
            state.split.clear();
        else if (c.args[0] == "reference")
            state.split = "reference";
        else
            state.split = requireTechnique(c.args[0], c.where.str()).id;
    } else if (c.name == "reference") {
        if (c.args.empty()) throw InputError(at + "reference: expected 'reference reference|raytraced [key=value ...]'");
        const TechniqueDesc& desc = requireTechnique(c.args[0], c.where.str());
        if (desc.id != "reference" && desc.id != "raytraced")
            throw InputError(at + "reference: expected a reference technique (reference, raytraced), got '" + desc.id + "'");
        state.referenceTechnique = desc.id;
        state.referenceParams = ParamValues(desc);
        size_t i = 1;
        while (i < c.args.size()) {
            auto [key, value] = keyValue(c, i);
            state.referenceParams.set(desc, key, value, c.where.str());
        }
    } else {
        bool stepOnly = std::find(kStepCommands.begin(), kStepCommands.end(), c.name) != kStepCommands.end();
        if (stepOnly) throw InputError(at + c.name + ": only allowed in a step, not here");
        throw InputError(at + "unknown command '" + c.name + "' (commands: " + joinList(allCommands()) + ")");
    }
}

// ---- conditions --------------------------------------------------------------------------------------
namespace {

struct CondToken {
    std::string text;
    bool number = false;
    double value = 0.0;
    bool bracket = false;  // "[...]": a variant's changes, the text between the brackets
};

std::vector<CondToken> tokenizeCondition(const std::string& text, const SourceLocation& where, const std::string& command) {
    std::vector<CondToken> out;
    size_t i = 0;
    auto after = [&](const char* s) { return !out.empty() && out.back().text == s && !out.back().bracket; };
    while (i < text.size()) {
        char c = text[i];
        if (c == ' ' || c == '\t') {
            ++i;
        } else if (c == '(' || c == ')' || c == '&' || c == ',') {
            out.push_back({std::string(1, c)});
            ++i;
        } else if (c == '[') {
            size_t close = text.find(']', i);
            if (close == std::string::npos)
                throw InputError(where.str() + ": " + command + ": '[' without ']' in '" + text + "'");
            CondToken t;
            t.text = text.substr(i + 1, close - i - 1);
            t.bracket = true;
            out.push_back(t);
            i = close + 1;
        } else if (c == '<' || c == '>' || c == '=' || c == '!') {
            std::string op(1, c);
            if (i + 1 < text.size() && text[i + 1] == '=') op += '=';
            if (op == "=" || op == "!" || op == "==" || op == "!=")
                throw InputError(where.str() + ": " + command + ": comparisons are < <= > >=, got '" + op + "'");
            out.push_back({op});
            i += op.size();
        } else if ((c == '+' || c == '-') && (after(")") || i + 1 >= text.size() || text[i + 1] == ' ')) {
            out.push_back({std::string(1, c)});  // the offset after a statistic: "mean(reference) - 0.02"
            ++i;
        } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+') {
            char* end = nullptr;
            double v = std::strtod(text.c_str() + i, &end);
            size_t n = size_t(end - (text.c_str() + i));
            if (n == 0 || !std::isfinite(v) || std::abs(v) > double(std::numeric_limits<float>::max()))
                throw InputError(where.str() + ": " + command + ": expected a number (in a float's range) at '" + text.substr(i) + "'");
            out.push_back({text.substr(i, n), true, v});
            i += n;
        } else if (std::isalpha(static_cast<unsigned char>(c))) {
            size_t j = i;
            while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_' ||
                                       text[j] == ':' || text[j] == '-' || text[j] == '.' || text[j] == '/'))
                ++j;
            out.push_back({text.substr(i, j - i)});
            i = j;
        } else {
            throw InputError(where.str() + ": " + command + ": unexpected character '" + std::string(1, c) + "' in '" + text + "'");
        }
    }
    return out;
}

bool isComparison(const std::string& s) { return s == "<" || s == "<=" || s == ">" || s == ">="; }
bool compare(double a, const std::string& op, double b) {
    return op == "<" ? a < b : op == "<=" ? a <= b : op == ">" ? a > b : a >= b;
}

std::string shortNumber(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// Lit, umbra and penumbra come from the reference with a margin of 0.01 that absorbs the noise of
// a finite number of light samples.
constexpr float kLitThreshold = 0.99f;
constexpr float kUmbraThreshold = 0.01f;

}  // namespace

TaskCondition::TaskCondition(const std::string& text, const SourceLocation& where, const std::string& command,
                             bool allowVariants)
    : text_(text), where_(where), command_(command) {
    const std::string usage =
        "expected STAT(BUFFER [in MASK & ...]) OP NUMBER joined by 'and' (or OP STAT(...) [+|- NUMBER]), STAT one of "
        "min, max, mean, fraction (fraction(BUFFER < T ...)), BUFFER one of visibility, reference, error, "
        "internal:NAME[.CHANNEL] or diff(BUFFER, BUFFER), MASK one of all, lit, umbra, penumbra, object:N, pick, "
        "near(X Y Z, R)";
    std::vector<CondToken> t = tokenizeCondition(text, where, command);
    size_t i = 0;
    auto fail = [&](const std::string& what) {
        throw InputError(where.str() + ": " + command + ": " + what + " in '" + text + "' (" + usage + ")");
    };
    auto peek = [&]() -> std::string {
        return i < t.size() ? (t[i].bracket ? "[" + t[i].text + "]" : t[i].text) : std::string("end of line");
    };
    auto expect = [&](const std::string& s) {
        if (i >= t.size() || t[i].bracket || t[i].text != s) fail("expected '" + s + "', got '" + peek() + "'");
        ++i;
    };
    auto number = [&]() {
        if (i >= t.size() || !t[i].number) fail("expected a number, got '" + peek() + "'");
        return t[i++].value;
    };
    auto buffer = [&]() {
        Buffer b;
        b.name = peek();
        if (b.name.rfind("internal:", 0) == 0) {
            std::string rest = b.name.substr(9);
            size_t dot = rest.find('.');
            b.internal = rest.substr(0, dot);
            b.channel = dot == std::string::npos ? "" : rest.substr(dot + 1);
            if (b.internal.empty() || (dot != std::string::npos && b.channel.empty()))
                fail("internal: expected internal:NAME or internal:NAME.CHANNEL, got '" + b.name + "'");
            b.name = "internal";
        } else if (b.name != "visibility" && b.name != "reference" && b.name != "error") {
            fail("unknown buffer '" + b.name + "'");
        }
        b.text = peek();
        ++i;
        if (i < t.size() && t[i].bracket) {
            if (!allowVariants)
                throw InputError(where.str() + ": " + command + ": '" + b.text + "[" + t[i].text + "]': a variant of the "
                                 "step ([KEY=VALUE]) is for expect; a task checks what the student made");
            std::string words = t[i].text;
            for (char& c : words)
                if (c == ',') c = ' ';
            std::istringstream in(words);
            std::string word;
            while (in >> word) {
                size_t eq = word.find('=');
                if (eq == std::string::npos || eq == 0 || eq + 1 == word.size())
                    fail("a variant is [KEY=VALUE ...] (technique=ID, light.size=S or a parameter), got '" + word + "'");
                b.changes.push_back({word.substr(0, eq), word.substr(eq + 1)});
                b.variantKey += (b.variantKey.empty() ? "" : " ") + word;
            }
            if (b.changes.empty()) fail("empty variant '[]'");
            b.text += "[" + b.variantKey + "]";
            ++i;
        }
        return b;
    };
    auto stat = [&]() {
        Stat s;
        s.stat = peek();
        if (s.stat != "min" && s.stat != "max" && s.stat != "mean" && s.stat != "fraction")
            fail("unknown statistic '" + s.stat + "'");
        ++i;
        expect("(");
        std::string inner;
        if (peek() == "diff") {
            ++i;
            expect("(");
            s.buffers.push_back(buffer());
            expect(",");
            s.buffers.push_back(buffer());
            expect(")");
            inner = "diff(" + s.buffers[0].text + ", " + s.buffers[1].text + ")";
        } else {
            s.buffers.push_back(buffer());
            inner = s.buffers[0].text;
        }
        if (s.stat == "fraction") {
            if (!isComparison(peek())) fail("fraction needs a comparison, e.g. fraction(visibility < 0.5), got '" + peek() + "'");
            s.compare = t[i++].text;
            inner += " " + s.compare + " " + t[i < t.size() ? i : i - 1].text;
            s.threshold = number();
        }
        if (peek() == "in") {
            ++i;
            inner += " in";
            while (true) {
                std::string m = peek();
                bool object = m.rfind("object:", 0) == 0;
                std::string shown = m;
                if (object) {
                    std::string n = m.substr(7);
                    char* end = nullptr;
                    long id = std::strtol(n.c_str(), &end, 10);
                    if (n.empty() || *end != '\0' || id < 0 || id > 16777215)
                        fail("object:N needs a whole number N in [0, 2^24 - 1] (an object id), got '" + m + "'");
                } else if (m == "near") {
                    // near(X Y Z, R): the pixels whose surface point lies within R of a world point.
                    ++i;
                    expect("(");
                    glm::vec4 ball;
                    for (int k = 0; k < 3; ++k) ball[k] = float(number());
                    expect(",");
                    ball.w = float(number());
                    if (!(ball.w > 0.0f)) fail("near(X Y Z, R) needs a radius R > 0");
                    if (i >= t.size() || t[i].text != ")") fail("expected ')' after near(X Y Z, R), got '" + peek() + "'");
                    shown = "near(" + shortNumber(ball.x) + " " + shortNumber(ball.y) + " " + shortNumber(ball.z) + ", " +
                            shortNumber(ball.w) + ")";
                    s.near.push_back(ball);
                } else if (m != "all" && m != "lit" && m != "umbra" && m != "penumbra" && m != "pick") {
                    fail("unknown mask '" + m + "'");
                }
                inner += (s.masks.empty() ? " " : " & ") + shown;
                s.masks.push_back(m);
                ++i;
                if (peek() != "&") break;
                ++i;
            }
        }
        expect(")");
        s.text = s.stat + "(" + inner + ")";
        return s;
    };
    if (t.empty()) fail("empty condition");
    while (true) {
        Term term;
        term.lhs = stat();
        if (!isComparison(peek())) fail("expected a comparison < <= > >= after ')', got '" + peek() + "'");
        term.op = t[i++].text;
        term.text = term.lhs.text + " " + term.op + " ";
        if (i < t.size() && t[i].number) {
            term.text += t[i].text;
            term.value = number();
        } else {
            if (i >= t.size() || t[i].bracket || !std::isalpha(static_cast<unsigned char>(t[i].text[0])))
                fail("expected a number or a statistic after '" + term.op + "', got '" + peek() + "'");
            term.rhs = stat();
            term.text += term.rhs->text;
            if (peek() == "+" || peek() == "-") {
                const bool minus = peek() == "-";
                ++i;
                term.text += std::string(minus ? " - " : " + ") + (i < t.size() ? t[i].text : "");
                term.value = number() * (minus ? -1.0 : 1.0);
            }
        }
        terms_.push_back(term);
        if (i == t.size()) break;
        expect("and");
    }
    // What the step's own render must provide before bind() knows the variants.
    for (const Term& term : terms_)
        for (const Stat* s : {&term.lhs, term.rhs ? &*term.rhs : nullptr}) {
            if (!s) continue;
            for (const std::string& m : s->masks) {
                if (m == "lit" || m == "umbra" || m == "penumbra") reads_.reference = true;
                if (m == "near") reads_.positions = true;
            }
            for (const Buffer& b : s->buffers)
                if (b.changes.empty()) {
                    if (b.name == "reference" || b.name == "error") reads_.reference = true;
                    if (b.name == "internal") reads_.internals.insert(b.internal);
                }
        }
}

namespace {

// The step's state with an expectation's changes: technique=ID (its parameters at their defaults),
// light.size=S (light 0) and the current technique's parameters, in the order written.
LessonState variantState(const LessonState& step, const std::vector<std::pair<std::string, std::string>>& changes,
                         const SourceLocation& where, const std::string& command) {
    LessonState s = step;
    for (const auto& [key, value] : changes) {
        if (key == "technique") {
            const TechniqueDesc& desc = requireTechnique(value, where.str());
            s.technique = desc.id;
            s.params = ParamValues(desc);
        } else if (key == "light.size") {
            double v = parseNumber(value, where, command + " [light.size=S]");
            checkLightSize(v, where.str() + ": " + command + ": light.size", value);
            if (s.lights.empty()) throw InputError(where.str() + ": " + command + ": light.size: the scene has no light");
            s.lights[0].size = float(v);
            if (v > 0.0 && s.lights[0].shape == LightShape::Point) s.lights[0].shape = LightShape::Square;
        } else {
            s.params.set(*findTechnique(s.technique), key, value, where.str());
        }
    }
    return s;
}

}  // namespace

void TaskCondition::bind(const LessonState& step) {
    const std::string at = where_.str() + ": " + command_ + ": ";
    variants_.clear();
    for (Term& term : terms_)
        for (Stat* s : {&term.lhs, term.rhs ? &*term.rhs : nullptr}) {
            if (!s) continue;
            if (std::count(s->masks.begin(), s->masks.end(), "pick") && !step.pick)
                throw InputError(at + "the mask 'pick' needs a picked pixel ('pick at X Y Z' in this step or before)");
            for (Buffer& b : s->buffers) {
                const LessonState* state = &step;
                TaskReads* reads = &reads_;
                b.variant = -1;
                if (!b.changes.empty()) {
                    auto it = std::find_if(variants_.begin(), variants_.end(),
                                           [&](const TaskVariant& v) { return v.key == b.variantKey; });
                    if (it == variants_.end()) {
                        TaskVariant v;
                        v.key = b.variantKey;
                        v.changes = b.changes;
                        v.state = variantState(step, b.changes, where_, command_);
                        v.sharesReference = v.state.lights.size() == step.lights.size() &&
                                            std::equal(v.state.lights.begin(), v.state.lights.end(), step.lights.begin(),
                                                       [](const Light& a, const Light& b) { return sameLight(a, b); });
                        variants_.push_back(v);
                        it = variants_.end() - 1;
                    }
                    b.variant = int(it - variants_.begin());
                    state = &it->state;
                    reads = &it->reads;
                    // The reference depends on the scene, the lights and the camera only: a variant
                    // that changes the technique alone reads the step's own.
                    if (b.name == "reference" || b.name == "error") (it->sharesReference ? reads_ : *reads).reference = true;
                }
                if (b.name != "internal") continue;
                // "light1/kernel_size": light 1's internal, as Renderer::writeInternals names it.
                std::string name = b.internal;
                size_t light = 0;
                if (name.rfind("light", 0) == 0 && name.find('/') != std::string::npos) {
                    const std::string n = name.substr(5, name.find('/') - 5);
                    char* end = nullptr;
                    long index = std::strtol(n.c_str(), &end, 10);
                    if (n.empty() || *end != '\0' || index < 1)
                        throw InputError(at + "internal:" + b.internal + ": expected internal:NAME or internal:lightN/NAME (N >= 1)");
                    light = size_t(index);
                    name = name.substr(name.find('/') + 1);
                }
                if (light >= state->lights.size())
                    throw InputError(at + "internal:" + b.internal + ": the scene has " + std::to_string(state->lights.size()) +
                                     " light(s)");
                const TechniqueDesc& desc = *findTechnique(state->technique);
                std::vector<std::string> names;
                for (const InternalDesc& i : desc.internals)
                    if (i.kind == InternalDesc::Kind::Image || i.kind == InternalDesc::Kind::Pyramid) names.push_back(i.name);
                const InternalDesc* internal = desc.findInternal(name);
                if (!internal || (internal->kind != InternalDesc::Kind::Image && internal->kind != InternalDesc::Kind::Pyramid))
                    throw InputError(at + "unknown internal '" + name + "' for technique " + desc.id +
                                     (names.empty() ? " (it has no image internals)" : " (its image internals: " + joinList(names) + ")"));
                if (!internal->appliesWhen.empty() && !Condition(internal->appliesWhen, desc, at).holds(state->params))
                    throw InputError(at + "internal '" + name + "' of " + desc.id + " is written only when " +
                                     internal->appliesWhen + ", not in this step");
                b.channelIndex = -1;
                b.signedValues = internal->signedValues;
                if (!b.channel.empty()) {
                    auto c = std::find(internal->channels.begin(), internal->channels.end(), b.channel);
                    if (c == internal->channels.end())
                        throw InputError(at + "internal '" + name + "' of " + desc.id + " has no channel '" + b.channel +
                                         "' (channels: " + joinList(internal->channels) + ")");
                    b.channelIndex = int(c - internal->channels.begin());
                } else if (s->buffers.size() == 2 && internal->channels.size() > 1) {
                    throw InputError(at + "diff: internal '" + name + "' has " + std::to_string(internal->channels.size()) +
                                     " channels; name one (internal:" + b.internal + "." + internal->channels[0] + ")");
                }
                reads->internals.insert(b.internal);
            }
        }
}

bool TaskCondition::readsReference() const {
    if (reads_.reference) return true;
    for (const TaskVariant& v : variants_)
        if (v.reads.reference) return true;
    return false;
}

// One statistic over the pixels of the image's geometry (never the background) inside the masks,
// or over every texel of an internal that lives in light space. NaN with `problem` set when the
// buffers cannot answer.
double TaskCondition::statistic(const Stat& s, const TaskBuffers& step, const std::vector<TaskBuffers>& variants,
                                std::string& problem) const {
    const std::string at = where_.str() + ": " + command_ + " " + text_ + ": ";
    const size_t n = step.ids.pixelCount();
    struct Source {
        const Buffer* b;
        const TaskBuffers* r;
        const Image* internal = nullptr;
        bool frame = true;
        const Image* ref = nullptr;  // the reference this buffer's render is compared with
    };
    std::vector<Source> sources;
    for (const Buffer& b : s.buffers) {
        if (b.variant >= int(variants.size())) throw InternalError(at + "the variants' buffers are missing");
        Source src{&b, b.variant < 0 ? &step : &variants[size_t(b.variant)]};
        if (b.name == "visibility" && src.r->visibility.pixelCount() != n) throw InternalError(at + "buffers differ in size");
        const TaskBuffers& withReference = b.variant >= 0 && variants_[size_t(b.variant)].sharesReference ? step : *src.r;
        src.ref = &withReference.reference;
        if ((b.name == "reference" || b.name == "error") && src.ref->pixelCount() != n)
            throw InternalError(at + "the reference was not read");
        if (b.name == "internal") {
            auto it = src.r->internals.find(b.internal);
            if (it == src.r->internals.end() || it->second.pixelCount() == 0) {
                problem = "internal '" + b.internal + "' was not written" + (b.variant < 0 ? "" : " in [" + b.variantKey + "]");
                return NAN;
            }
            src.internal = &it->second;
            src.frame = it->second.width == step.ids.width && it->second.height == step.ids.height;
            if (b.channelIndex >= it->second.channels) throw InternalError(at + "internal channel out of range");
        }
        sources.push_back(src);
    }
    double lo = INFINITY, hi = -INFINITY, sum = 0.0;
    size_t count = 0, hits = 0;
    auto add = [&](double v) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        sum += v;
        ++count;
        if (s.stat == "fraction" && compare(v, s.compare, s.threshold)) ++hits;
    };
    // An internal's value counts when finite and not negative (the techniques' -1: no receiver, no
    // blocker, the step did not run).
    // (An internal declared signedValues counts its negative values too: they are data.)
    auto usableIn = [](const Source& src, float v) { return std::isfinite(v) && (v >= 0.0f || src.b->signedValues); };
    if (!sources[0].frame || (sources.size() == 2 && !sources[1].frame)) {
        const Source& src = sources[0];
        const Source& other = src.frame ? sources[1] : src;
        const std::string size = std::to_string(other.internal->width) + "x" + std::to_string(other.internal->height);
        if (sources.size() == 2) {
            problem = "internal '" + other.b->internal + "' is " + size + " texels (light space), not the image's size: "
                      "diff compares pixel by pixel";
            return NAN;
        }
        for (const std::string& m : s.masks)
            if (m != "all") {
                problem = "internal '" + src.b->internal + "' is " + size + " texels (light space), not the image's size: "
                          "the mask '" + m + "' does not apply";
                return NAN;
            }
        const Image& img = *src.internal;
        for (size_t p = 0; p < img.pixelCount(); ++p)
            for (int c = 0; c < img.channels; ++c)
                if ((src.b->channelIndex < 0 || c == src.b->channelIndex) && usableIn(src, img.data[p * size_t(img.channels) + size_t(c)]))
                    add(img.data[p * size_t(img.channels) + size_t(c)]);
    } else {
        std::vector<int> objectIds;  // object:N masks as ids (-1 for the others)
        for (const std::string& m : s.masks) objectIds.push_back(m.rfind("object:", 0) == 0 ? std::stoi(m.substr(7)) : -1);
        const bool picked = std::count(s.masks.begin(), s.masks.end(), "pick") > 0;
        if (picked && !step.pick) {
            problem = "no picked pixel on the image";
            return NAN;
        }
        if (!s.near.empty() && step.positions.pixelCount() != n) throw InternalError(at + "the positions were not read");
        const size_t pickIndex = picked ? size_t(step.pick->y) * size_t(step.ids.width) + size_t(step.pick->x) : 0;
        for (size_t p = 0; p < n; ++p) {
            float id = step.ids.data[p];
            if (id < 0.0f) continue;  // background
            if (picked && p != pickIndex) continue;
            bool inside = true;
            size_t nearIndex = 0;
            for (size_t k = 0; k < s.masks.size() && inside; ++k) {
                const std::string& m = s.masks[k];
                if (objectIds[k] >= 0) {
                    inside = int(id) == objectIds[k];
                } else if (m == "near") {
                    const glm::vec4 ball = s.near[nearIndex++];
                    const glm::vec3 x(step.positions.data[p * 3], step.positions.data[p * 3 + 1], step.positions.data[p * 3 + 2]);
                    inside = glm::length(x - glm::vec3(ball)) <= ball.w;
                } else if (m == "pick") {
                    inside = true;
                } else if (m != "all") {
                    float r = step.reference.data[p];
                    inside = m == "lit"     ? r >= kLitThreshold
                             : m == "umbra" ? r <= kUmbraThreshold
                                            : r > kUmbraThreshold && r < kLitThreshold;
                }
            }
            if (!inside) continue;
            // One value per buffer at this pixel (every channel of an internal without one named).
            double values[2] = {0.0, 0.0};
            bool ok = true;
            for (size_t k = 0; k < sources.size() && ok; ++k) {
                const Source& src = sources[k];
                const std::string& name = src.b->name;
                if (name == "internal") {
                    const Image& img = *src.internal;
                    if (src.b->channelIndex < 0 && sources.size() == 1) {
                        for (int c = 0; c < img.channels; ++c)
                            if (usableIn(src, img.data[p * size_t(img.channels) + size_t(c)])) add(img.data[p * size_t(img.channels) + size_t(c)]);
                        ok = false;  // added channel by channel
                        break;
                    }
                    float v = img.data[p * size_t(img.channels) + size_t(std::max(src.b->channelIndex, 0))];
                    ok = usableIn(src, v);
                    values[k] = v;
                } else {
                    values[k] = name == "visibility" ? src.r->visibility.data[p]
                                : name == "reference" ? src.ref->data[p]
                                                      : std::fabs(double(src.r->visibility.data[p]) - src.ref->data[p]);
                    ok = std::isfinite(values[k]);
                }
            }
            if (!ok) continue;
            add(sources.size() == 2 ? std::fabs(values[0] - values[1]) : values[0]);
        }
    }
    if (count == 0) {
        problem = "no pixel in the mask";
        return NAN;
    }
    return s.stat == "min" ? lo : s.stat == "max" ? hi : s.stat == "mean" ? sum / double(count) : double(hits) / double(count);
}

TaskCondition::Outcome TaskCondition::evaluate(const TaskBuffers& b, const std::vector<TaskBuffers>& variants) const {
    Outcome out;
    out.passed = !terms_.empty();
    if (b.visibility.pixelCount() != b.ids.pixelCount() || (reads_.reference && b.reference.pixelCount() != b.ids.pixelCount()))
        throw InternalError(where_.str() + ": " + command_ + ": buffers differ in size");
    if (variants.size() != variants_.size()) throw InternalError(where_.str() + ": " + command_ + ": the variants' buffers are missing");
    for (const Term& term : terms_) {
        std::string problem;
        double value = statistic(term.lhs, b, variants, problem);
        double need = term.value;
        std::string against;
        if (term.rhs && problem.empty()) {
            double r = statistic(*term.rhs, b, variants, problem);
            need = r + term.value;
            against = term.rhs->text + " = " + shortNumber(r);
        }
        if (!problem.empty()) need = NAN;
        bool ok = problem.empty() && compare(value, term.op, need);
        out.passed = out.passed && ok;
        out.values.push_back(value);
        out.needs.push_back(need);
        out.termPassed.push_back(ok);
        out.problems.push_back(problem);
        std::string line = term.text + ": ";
        if (!problem.empty())
            line += problem;
        else
            line += shortNumber(value) + " (needs " + term.op + " " + shortNumber(need) +
                    (against.empty() ? "" : ", " + against) + ") " + (ok ? "yes" : "not yet");
        out.message += (out.message.empty() ? "" : "\n") + line;
    }
    return out;
}

std::string TaskCondition::failures(const Outcome& o) const { return termValues(o, true); }
std::string TaskCondition::measured(const Outcome& o) const { return termValues(o, false); }

std::string TaskCondition::termValues(const Outcome& o, bool failingOnly) const {
    std::string out;
    for (size_t k = 0; k < terms_.size() && k < o.values.size(); ++k) {
        if (failingOnly && o.termPassed[k]) continue;
        std::string value;
        if (!o.problems[k].empty()) {
            value = o.problems[k];  // "no pixel in the mask", "internal ... was not written"
        } else {
            value = shortNumber(o.values[k]);
            if (terms_[k].rhs || !failingOnly) value += " (needs " + terms_[k].op + " " + shortNumber(o.needs[k]) + ")";
        }
        // One term: its value alone (the condition is printed beside it); several: each named.
        out += (out.empty() ? "" : "; ") + (terms_.size() == 1 ? value : terms_[k].text + ": " + value);
    }
    return out;
}

// ---- parsing --------------------------------------------------------------------------------------------
namespace {

LessonCommand parseCommandLine(const std::string& line, const SourceLocation& where) {
    LessonCommand c;
    c.where = where;
    std::string body = trim(line);
    size_t sp = body.find_first_of(" \t");
    c.name = body.substr(0, sp);
    std::string rest = sp == std::string::npos ? "" : trim(body.substr(sp));
    if (c.name == "try" || c.name == "check" || c.name == "expect") {
        if (rest.empty()) throw InputError(where.str() + ": " + c.name + ": expected text after '" + c.name + "'");
        c.args = {rest};  // the prompt or the condition, whole
    } else if (c.name == "answer") {
        if (rest.empty()) throw InputError(where.str() + ": answer: expected a command, e.g. 'answer set bias_const 1'");
        c.args = {rest};
    } else {
        c.args = splitWords(rest, where);
    }
    return c;
}

// Applies a step's own commands: state commands change `state`; animate, try, check and answer
// fill the step's fields.
void applyStepCommands(LessonStep& step, LessonState& state) {
    std::optional<SourceLocation> tryAt, checkAt;
    std::vector<LessonCommand> answer;
    std::string prompt, condition;
    for (const LessonCommand& c : step.commands) {
        if (c.name == "animate") {
            expectArgs(c, 3, 4, "animate TARGET FROM TO [SECONDS]");
            if (step.animate) throw InputError(c.where.str() + ": animate: a step animates one value (first at line " +
                                               std::to_string(step.animate->where.line) + ")");
            LessonAnimation a;
            a.target = c.args[0];
            a.from = parseNumber(c.args[1], c.where, "animate FROM");
            a.to = parseNumber(c.args[2], c.where, "animate TO");
            if (c.args.size() == 4) {
                a.seconds = parseNumber(c.args[3], c.where, "animate SECONDS");
                if (a.seconds <= 0.0 || a.seconds > 600.0)
                    throw InputError(c.where.str() + ": animate SECONDS: expected a value in (0, 600]");
            }
            a.where = c.where;
            step.animate = a;
        } else if (c.name == "try") {
            if (tryAt) throw InputError(c.where.str() + ": try: a step has one task (first at line " + std::to_string(tryAt->line) + ")");
            tryAt = c.where;
            prompt = c.args[0];
        } else if (c.name == "check") {
            if (checkAt) throw InputError(c.where.str() + ": check: a task has one condition (join terms with 'and')");
            checkAt = c.where;
            condition = c.args[0];
        } else if (c.name == "answer") {
            answer.push_back(parseCommandLine(c.args[0], c.where));
        } else if (c.name == "expect") {
            step.expects.push_back({TaskCondition(c.args[0], c.where, "expect", true), c.where});
        } else {
            applyLessonCommand(state, c);
        }
    }
    for (const char* view : {"shadow-map", "shadow-map-texels"})
        if (state.views.count(view) && !findTechnique(state.technique)->findInternal("shadow_map"))
            throw InputError(step.where.str() + ": the " + view + " view is shown but technique " + state.technique +
                             " has no light-centre shadow map (show it with hard or pcf, or 'hide " + view + "')");
    step.state = state;
    for (LessonExpect& e : step.expects) e.condition.bind(state);
    // Animation targets are checked against the step's technique and light.
    if (step.animate) {
        const LessonAnimation& a = *step.animate;
        const std::string at = a.where.str() + ": animate: ";
        if (a.target.rfind("light.", 0) == 0) {
            const std::string k = a.target.substr(6);
            if (k != "size" && k != "x" && k != "y" && k != "z")
                throw InputError(at + "unknown target '" + a.target + "' (light.size, light.x, light.y, light.z or a parameter)");
            if (k == "size") {
                // The limits of 'light size' (an animation to 1e9 was accepted while 'light size 1e9' was not).
                checkLightSize(a.from, at + "light.size FROM", formatValue(a.from));
                checkLightSize(a.to, at + "light.size TO", formatValue(a.to));
            }
            if (state.lights.empty()) throw InputError(at + "the scene has no light");
        } else {
            const TechniqueDesc& desc = *findTechnique(state.technique);
            const ParamDesc* p = desc.findParam(a.target);
            ParamValues probe = state.params;
            probe.set(desc, a.target, formatValue(a.from), a.where.str());  // unknown key, range
            probe.set(desc, a.target, formatValue(a.to), a.where.str());
            if (p->type != ParamDesc::Type::Float && p->type != ParamDesc::Type::Int)
                throw InputError(at + a.target + " is a " + paramTypeName(p->type) + "; only float and int parameters animate");
        }
    }
    if (tryAt || checkAt || !answer.empty()) {
        SourceLocation at = tryAt ? *tryAt : checkAt ? *checkAt : answer.front().where;
        if (!tryAt) throw InputError(at.str() + ": a task needs 'try TEXT' (what the student is asked to do)");
        if (!checkAt) throw InputError(at.str() + ": try: the task needs 'check CONDITION'");
        if (answer.empty()) throw InputError(at.str() + ": try: the task needs at least one 'answer COMMAND' (its show-me state)");
        LessonTask task;
        task.prompt = prompt;
        task.where = at;
        task.check = TaskCondition(condition, *checkAt);
        task.check.bind(state);
        task.answer = answer;
        LessonState answered = state;
        for (const LessonCommand& c : answer) {
            if (std::find(kStateCommands.begin(), kStateCommands.end(), c.name) == kStateCommands.end())
                throw InputError(c.where.str() + ": answer: expected a state command (" + joinList(kStateCommands) +
                                 "), got '" + c.name + "'");
            applyLessonCommand(answered, c);
        }
        step.task = task;
        step.answerState = answered;
    }
}

bool isFence(const std::string& line) { return trim(line).rfind("```", 0) == 0; }

}  // namespace

Lesson parseLesson(const std::string& text, const std::string& file, const std::string& id) {
    Lesson lesson;
    lesson.id = id;
    lesson.file = file;
    std::vector<std::string> lines;
    {
        std::istringstream in(text);
        std::string line;
        while (std::getline(in, line)) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            lines.push_back(line);
        }
    }
    auto at = [&](size_t index) { return SourceLocation{file, int(index + 1)}; };

    std::vector<LessonCommand> startCommands;
    LessonStep* step = nullptr;
    std::string* narration = &lesson.introduction;
    std::vector<int>* narrationLines = &lesson.introductionLines;
    auto narrate = [&](size_t index) {
        *narration += lines[index] + "\n";
        narrationLines->push_back(int(index + 1));
    };
    bool titled = false;
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string& line = lines[i];
        if (isFence(line)) {
            std::string info = trim(trim(line).substr(3));
            size_t end = i + 1;
            while (end < lines.size() && !isFence(lines[end])) ++end;
            if (end == lines.size()) throw InputError(at(i).str() + ": code block opened here is never closed (```)");
            if (info == "shadowlab") {
                if (!titled) throw InputError(at(i).str() + ": expected the lesson title ('# Title') before any command");
                for (size_t k = i + 1; k < end; ++k) {
                    std::string body = trim(lines[k]);
                    if (body.empty() || body[0] == '#') continue;
                    LessonCommand c = parseCommandLine(body, at(k));
                    (step ? step->commands : startCommands).push_back(c);
                }
            } else {
                for (size_t k = i; k <= end; ++k) narrate(k);
            }
            i = end;
            continue;
        }
        if (line.rfind("# ", 0) == 0) {
            if (titled) throw InputError(at(i).str() + ": a lesson has one title ('# '); steps start with '## '");
            lesson.title = trim(line.substr(2));
            if (lesson.title.empty()) throw InputError(at(i).str() + ": empty title");
            titled = true;
            continue;
        }
        if (line.rfind("## ", 0) == 0) {
            if (!titled) throw InputError(at(i).str() + ": expected the lesson title ('# Title') before the first step");
            lesson.steps.push_back({});
            step = &lesson.steps.back();
            step->title = trim(line.substr(3));
            step->where = at(i);
            if (step->title.empty()) throw InputError(at(i).str() + ": empty step title");
            narration = &step->narration;
            narrationLines = &step->narrationLines;
            continue;
        }
        if (!titled) {
            if (trim(line).empty()) continue;
            throw InputError(at(i).str() + ": expected the lesson title ('# Title') on the first line, got '" + line + "'");
        }
        narrate(i);
    }
    if (!titled) throw InputError(file + ":1: expected the lesson title ('# Title'), the file is empty");
    if (lesson.steps.empty()) throw InputError(file + ":" + std::to_string(lines.size()) + ": a lesson needs at least one step ('## Title')");
    // Leading empty lines and trailing blanks go; each line keeps its source line, and its links
    // are checked (a refused link is an error naming that line).
    auto trimNarration = [&](std::string& s, std::vector<int>& sourceLines) {
        size_t a = s.find_first_not_of("\n");
        s = a == std::string::npos ? "" : s.substr(a);
        sourceLines.erase(sourceLines.begin(), sourceLines.begin() + std::min(sourceLines.size(), a == std::string::npos ? sourceLines.size() : a));
        while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
        sourceLines.resize(s.empty() ? 0 : size_t(std::count(s.begin(), s.end(), '\n')) + 1);
        markdownToHtml(s, file, sourceLines);
    };
    trimNarration(lesson.introduction, lesson.introductionLines);

    // The start: scene first, technique defaults to the first light's technique (else hard), and
    // the reference defaults to its own defaults.
    LessonState state;
    for (const LessonCommand& c : startCommands) {
        if (std::find(kStepCommands.begin(), kStepCommands.end(), c.name) != kStepCommands.end())
            throw InputError(c.where.str() + ": " + c.name + ": only allowed in a step ('## ...'), not in the lesson's start");
        applyLessonCommand(state, c);
        if (c.name == "scene" && state.technique.empty()) {
            const Scene& scene = sceneNamed(state.scene, c.where);
            std::string t = !scene.lights.empty() && !scene.lights[0].technique.empty() ? scene.lights[0].technique : "hard";
            state.technique = requireTechnique(t, c.where.str()).id;
            state.params = ParamValues(*findTechnique(t));
        }
    }
    if (state.scene.empty())
        throw InputError(file + ":" + std::to_string(lesson.steps.front().where.line) +
                         ": the lesson's start (a ```shadowlab block before the first step) must name a scene");
    state.referenceParams = state.referenceTechnique == "reference" && state.referenceParams.values().empty()
                                ? ParamValues(*findTechnique("reference"))
                                : state.referenceParams;
    lesson.start = state;
    for (LessonStep& s : lesson.steps) {
        trimNarration(s.narration, s.narrationLines);
        applyStepCommands(s, state);
        if (s.task) checkInlineLinks(s.task->prompt, s.task->where);
    }
    return lesson;
}

Lesson loadLesson(const std::string& nameOrPath) {
    std::string path, shown, id;
    if (nameOrPath.find('/') != std::string::npos || (nameOrPath.size() > 3 && nameOrPath.substr(nameOrPath.size() - 3) == ".md")) {
        path = shown = nameOrPath;
        id = fs::path(nameOrPath).stem().string();
    } else {
        std::vector<std::string> names = listLessons();
        if (std::find(names.begin(), names.end(), nameOrPath) == names.end())
            throw InputError("unknown lesson '" + nameOrPath + "' (lessons: " + joinList(names) + ")");
        path = projectRoot() + "/lessons/" + nameOrPath + ".md";
        shown = "lessons/" + nameOrPath + ".md";
        id = nameOrPath;
    }
    std::string text;
    try {
        text = readInputFile(path, "lesson file", kMaxTextInputBytes);
    } catch (const InputError& e) {  // named as the user gave it
        std::string message = e.what();
        throw InputError(shown + message.substr(std::min(message.size(), path.size())));
    }
    return parseLesson(text, shown, id);
}

std::vector<std::string> listLessons() {
    std::vector<std::string> out;
    fs::path dir = fs::path(projectRoot()) / "lessons";
    if (!fs::is_directory(dir)) return out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".md" && e.path().filename() != "README.md") out.push_back(e.path().stem().string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace shadowlab
