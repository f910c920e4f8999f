// Scene files: finding them, parsing and validating them (schema: assets/scenes/README.md), and the
// small amount of math the rest of the renderer asks of a scene (transforms over time, bounds).
//
// Validation follows pbrt's habit: every field the file contains is either read or reported, and
// every error names the file and the field path ("objects[2].albedo[1]") with what was expected
// and what was found. JSON syntax errors name the line and column instead.
#include "scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "error.h"

namespace shadowlab {

namespace fs = std::filesystem;
using json = nlohmann::json;

// --- Scene math
// -----------------------------------------------------------------------------------

glm::mat4 Object::worldFromObjectAt(double t) const {
    switch (motion.type) {
        case Motion::Type::None:
            return worldFromObject;
        case Motion::Type::Rotate: {
            // Reduce the angle in double so that long runs keep float precision.
            const double degrees =
                std::fmod(static_cast<double>(motion.degreesPerSecond) * t, 360.0);
            const float angle = glm::radians(static_cast<float>(degrees));
            const glm::mat4 pivotFromObject = glm::translate(glm::mat4(1.0f), -motion.pivot);
            const glm::mat4 rotated = glm::rotate(glm::mat4(1.0f), angle, motion.axis);
            const glm::mat4 worldFromPivot = glm::translate(glm::mat4(1.0f), motion.pivot);
            return worldFromPivot * rotated * pivotFromObject * worldFromObject;
        }
        case Motion::Type::Keyframes: {
            if (motion.keys.empty()) return worldFromObject;
            const auto& keys = motion.keys;
            glm::vec3 offset = keys.front().translate;
            const double period = keys.back().time;
            if (keys.size() > 1 && period > 0.0) {
                // Loop over [0, period): the last key's time is the loop length.
                double local = std::fmod(t, period);
                if (local < 0.0) local += period;
                if (local > keys.front().time) {
                    for (size_t i = 0; i + 1 < keys.size(); ++i) {
                        if (local < keys[i + 1].time) {
                            const double span = keys[i + 1].time - keys[i].time;
                            const float s = static_cast<float>((local - keys[i].time) / span);
                            offset = glm::mix(keys[i].translate, keys[i + 1].translate, s);
                            break;
                        }
                    }
                }
            }
            return glm::translate(glm::mat4(1.0f), offset) * worldFromObject;
        }
    }
    return worldFromObject;
}

const char* lightShapeName(LightShape shape) {
    switch (shape) {
        case LightShape::Point: return "point";
        case LightShape::Square: return "square";
        case LightShape::Disk: return "disk";
        case LightShape::Sphere: return "sphere";
    }
    return "unknown";
}

glm::vec3 Light::right() const { return glm::normalize(glm::cross(direction, up)); }

glm::mat4 Camera::viewFromWorld() const { return glm::lookAt(position, target, up); }

glm::mat4 Camera::clipFromView(float aspect) const {
    return glm::perspective(glm::radians(fovYDegrees), aspect, nearPlane, farPlane);
}

bool Scene::hasMotion() const {
    return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return o.moves(); });
}

Bounds Scene::bounds(double t, bool castersOnly) const {
    Bounds b;
    for (const Object& object : objects) {
        if (castersOnly && !object.castsShadows) continue;
        const glm::mat4 worldFromObject = object.worldFromObjectAt(t);
        for (const glm::vec3& p : object.mesh.positions) {
            b.extend(glm::vec3(worldFromObject * glm::vec4(p, 1.0f)));
        }
    }
    return b;
}

// --- Finding scene files
// ----------------------------------------------------------------------------

std::string projectRoot() {
    if (const char* root = std::getenv("SHADOWLAB_ROOT"); root != nullptr && root[0] != '\0') {
        return root;
    }
#ifdef SHADOWLAB_SOURCE_DIR
    return SHADOWLAB_SOURCE_DIR;
#else
    return ".";
#endif
}

std::vector<std::string> listScenes() {
    std::vector<std::string> names;
    std::error_code ec;
    const fs::path dir = fs::path(projectRoot()) / "assets" / "scenes";
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->path().extension() == ".json" && it->is_regular_file(ec)) {
            names.push_back(it->path().stem().string());
        }
    }
    std::sort(names.begin(), names.end());
    return names;
}

namespace {

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
    std::string out;
    for (size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
    return out;
}

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string resolveScenePath(const std::string& nameOrPath) {
    const bool isPath = nameOrPath.find('/') != std::string::npos || endsWith(nameOrPath, ".json");
    const std::string path =
        isPath ? nameOrPath
               : (fs::path(projectRoot()) / "assets" / "scenes" / (nameOrPath + ".json")).string();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        const std::vector<std::string> known = listScenes();
        throw InputError(path + ": no such scene file (known scenes: " +
                         (known.empty() ? std::string("none") : join(known, ", ")) + ")");
    }
    return path;
}

// --- Parsing: JSON text to a DOM, with field paths for the errors nlohmann reports
// --------------------

// nlohmann quotes the text it read before the error ("last read: '<text>'"), which can be a whole
// base64 buffer: keep only its end, where the error is.
std::string shortenLastRead(std::string detail) {
    const std::string marker = "last read: '";
    const size_t start = detail.find(marker);
    if (start == std::string::npos) return detail;
    const size_t from = start + marker.size();
    size_t end = detail.find("'; expected", from);
    if (end == std::string::npos) end = detail.rfind('\'');
    const size_t keep = 40;
    if (end != std::string::npos && end > from + keep + 3)
        detail.replace(from, end - keep - from, "...");
    return detail;
}

namespace {

std::string formatNumber(double x) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.9g", x);
    return buffer;
}

// What a JSON value is, for "got ..." in messages.
std::string describe(const json& v) {
    switch (v.type()) {
        case json::value_t::null: return "null";
        case json::value_t::boolean: return v.get<bool>() ? "true" : "false";
        case json::value_t::number_integer: return std::to_string(v.get<int64_t>());
        case json::value_t::number_unsigned: return std::to_string(v.get<uint64_t>());
        case json::value_t::number_float: return formatNumber(v.get<double>());
        case json::value_t::string: {
            std::string s = json(v).dump();
            if (s.size() > 60) s = s.substr(0, 56) + "...\"";
            return "the string " + s;
        }
        case json::value_t::array: return "an array of " + std::to_string(v.size()) + " elements";
        case json::value_t::object: return "an object";
        default: return "an unsupported value";
    }
}

// Builds the DOM like nlohmann::json::parse, and also tracks the path of the value being read, so
// that a number that overflows to infinity (which nlohmann reports without a place) and a field
// given twice (which nlohmann silently collapses) are reported by field path.
class TrackingSax : public nlohmann::json_sax<json> {
public:
    enum class Failure { None, Syntax, NonFinite, Duplicate, TooDeep };
    Failure failure = Failure::None;
    size_t byte = 0;        // Syntax: 1-based offset of the last character read
    std::string detail;     // Syntax: nlohmann's explanation; NonFinite: the token
    std::string path;       // NonFinite, Duplicate, TooDeep: where
    static constexpr size_t kMaxDepth = 64;

    explicit TrackingSax(json& result) : dom_(result, false) {}

    bool null() override { return value() && dom_.null(); }
    bool boolean(bool v) override { return value() && dom_.boolean(v); }
    bool number_integer(number_integer_t v) override { return value() && dom_.number_integer(v); }
    bool number_unsigned(number_unsigned_t v) override {
        return value() && dom_.number_unsigned(v);
    }
    bool number_float(number_float_t v, const string_t& s) override {
        return value() && dom_.number_float(v, s);
    }
    bool string(string_t& v) override { return value() && dom_.string(v); }
    bool binary(binary_t& v) override { return value() && dom_.binary(v); }
    bool start_object(std::size_t n) override {
        if (!value() || !push(false)) return false;
        return dom_.start_object(n);
    }
    bool key(string_t& k) override {
        Frame& frame = stack_.back();
        frame.key = k;
        if (!frame.keys.insert(k).second) {
            failure = Failure::Duplicate;
            path = currentPath(false);
            return false;
        }
        return dom_.key(k);
    }
    bool end_object() override {
        stack_.pop_back();
        return dom_.end_object();
    }
    bool start_array(std::size_t n) override {
        if (!value() || !push(true)) return false;
        return dom_.start_array(n);
    }
    bool end_array() override {
        stack_.pop_back();
        return dom_.end_array();
    }
    bool parse_error(std::size_t position, const std::string& lastToken,
                     const nlohmann::detail::exception& ex) override {
        if (ex.id == 406) {  // out_of_range.406: "number overflow", i.e. the value is +-inf
            failure = Failure::NonFinite;
            detail = lastToken;
            path = currentPath(true);
        } else {
            failure = Failure::Syntax;
            byte = position;
            detail = ex.what();
            // Drop nlohmann's "[json.exception.parse_error.101] parse error at line 2, column 8: "
            // prefix: the caller prints its own place.
            if (const size_t column = detail.find("column "); column != std::string::npos) {
                if (const size_t colon = detail.find(": ", column); colon != std::string::npos) {
                    detail = detail.substr(colon + 2);
                }
            } else if (const size_t bracket = detail.find("] "); bracket != std::string::npos) {
                detail = detail.substr(bracket + 2);
            }
        }
        return false;
    }

private:
    struct Frame {
        bool isArray = false;
        long index = -1;  // arrays: index of the current element
        std::string key;  // objects: key of the current field
        std::set<std::string> keys;
    };

    bool value() {
        if (!stack_.empty() && stack_.back().isArray) ++stack_.back().index;
        return true;
    }
    bool push(bool isArray) {
        if (stack_.size() >= kMaxDepth) {
            failure = Failure::TooDeep;
            path = currentPath(false);
            return false;
        }
        stack_.push_back(Frame{isArray, -1, {}, {}});
        return true;
    }
    // The path of the value being read; `pending` when its value event has not arrived yet (an
    // array's next element then has index + 1).
    std::string currentPath(bool pending) const {
        std::string out;
        for (size_t i = 0; i < stack_.size(); ++i) {
            const Frame& f = stack_[i];
            if (f.isArray) {
                const long index = f.index + ((pending && i + 1 == stack_.size()) ? 1 : 0);
                out += "[" + std::to_string(index) + "]";
            } else {
                out += (out.empty() ? "" : ".") + f.key;
            }
        }
        return out;
    }

    nlohmann::detail::json_sax_dom_parser<json> dom_;
    std::vector<Frame> stack_;
};

std::string placeName(const std::string& path) { return path.empty() ? "(top level)" : path; }

json parseJson(const std::string& file, const std::string& text) {
    json result;
    TrackingSax sax(result);
    bool ok = false;
    try {
        ok = json::sax_parse(text, &sax, json::input_format_t::json, true);
    } catch (const std::exception& e) {
        throw InputError(file + ": malformed JSON: " + e.what());
    }
    if (ok) return result;
    switch (sax.failure) {
        case TrackingSax::Failure::NonFinite:
            throw InputError(file + ": " + placeName(sax.path) +
                             ": expected a finite number, got " + sax.detail);
        case TrackingSax::Failure::Duplicate:
            throw InputError(file + ": " + placeName(sax.path) +
                             ": expected each field at most once, got it a second time");
        case TrackingSax::Failure::TooDeep:
            throw InputError(file + ": " + placeName(sax.path) + ": expected at most " +
                             std::to_string(TrackingSax::kMaxDepth) +
                             " levels of nesting, got more");
        default: {
            // nlohmann's byte is the 1-based offset of the last character it read (one past the
            // end at end of input); the error is at that character.
            const size_t index = std::min(sax.byte > 0 ? sax.byte - 1 : 0, text.size());
            size_t line = 1, lineStart = 0;
            for (size_t i = 0; i < index; ++i) {
                if (text[i] == '\n') {
                    ++line;
                    lineStart = i + 1;
                }
            }
            const size_t column = index - lineStart + 1;
            throw InputError(file + ":" + std::to_string(line) + ":" + std::to_string(column) +
                             ": malformed JSON: " + shortenLastRead(sax.detail));
        }
    }
}

// --- Validation: reading the DOM into a Scene
// ---------------------------------------------------------

std::string sub(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}
std::string at(const std::string& path, size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}
    const std::string& file() const { return file_; }

    [[noreturn]] void fail(const std::string& path, const std::string& expected,
                           const std::string& got) const {
        throw InputError(file_ + ": " + placeName(path) + ": expected " + expected + ", got " +
                         got);
    }

    void requireObject(const json& v, const std::string& path) const {
        if (!v.is_object()) fail(path, "an object", describe(v));
    }

    template <class Predicate>
    double number(const json& v, const std::string& path, const std::string& expected,
                  Predicate valid) const {
        if (!v.is_number()) fail(path, expected, describe(v));
        const double x = v.get<double>();
        if (!std::isfinite(x)) fail(path, "a finite number", formatNumber(x));
        // Scenes are stored in floats: a number that overflows or flushes to zero there is wrong.
        const float f = static_cast<float>(x);
        if (!std::isfinite(f) || (x != 0.0 && std::abs(f) < std::numeric_limits<float>::min())) {
            fail(path, "a number representable as a float (1.2e-38 <= |x| <= 3.4e38, or 0)",
                 formatNumber(x));
        }
        if (!valid(x)) fail(path, expected, formatNumber(x));
        return x;
    }
    double number(const json& v, const std::string& path) const {
        return number(v, path, "a number", [](double) { return true; });
    }

    int64_t integer(const json& v, const std::string& path, int64_t lo, int64_t hi) const {
        const std::string expected =
            "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        if (v.is_number_integer()) {
            if (v.is_number_unsigned() && v.get<uint64_t>() > static_cast<uint64_t>(hi)) {
                fail(path, expected, describe(v));
            }
            const int64_t x = v.get<int64_t>();
            if (x < lo || x > hi) fail(path, expected, describe(v));
            return x;
        }
        // 32.0 is an integer too; 32.5 is not.
        const double x = number(v, path, expected, [&](double d) {
            return d == std::floor(d) && d >= static_cast<double>(lo) &&
                   d <= static_cast<double>(hi);
        });
        return static_cast<int64_t>(x);
    }

    template <class Predicate>
    glm::vec3 vec3(const json& v, const std::string& path, const std::string& expectedEach,
                   Predicate valid) const {
        if (!v.is_array() || v.size() != 3) {
            fail(path, "an array of 3 numbers (each " + expectedEach + ")", describe(v));
        }
        glm::vec3 out;
        for (size_t i = 0; i < 3; ++i) {
            out[static_cast<int>(i)] =
                static_cast<float>(number(v[i], at(path, i), expectedEach, valid));
        }
        return out;
    }
    glm::vec3 vec3(const json& v, const std::string& path) const {
        return vec3(v, path, "a number", [](double) { return true; });
    }
    glm::vec3 nonZeroVec3(const json& v, const std::string& path) const {
        const glm::vec3 x = vec3(v, path);
        if (!(glm::length(x) > 1e-12f)) fail(path, "a non-zero vector", describeVec(x));
        return x;
    }

    std::string string(const json& v, const std::string& path, const std::string& expected) const {
        if (!v.is_string()) fail(path, expected, describe(v));
        return v.get<std::string>();
    }
    bool boolean(const json& v, const std::string& path) const {
        if (!v.is_boolean()) fail(path, "true or false", describe(v));
        return v.get<bool>();
    }

    static std::string describeVec(const glm::vec3& x) {
        return "[" + formatNumber(x.x) + ", " + formatNumber(x.y) + ", " + formatNumber(x.z) + "]";
    }

private:
    std::string file_;
};

// A JSON object whose fields are all known: constructing it reports the first unknown field.
class Fields {
public:
    Fields(const Reader& reader, const json& v, std::string path, std::vector<std::string> allowed)
        : reader_(reader), v_(v), path_(std::move(path)), allowed_(std::move(allowed)) {
        reader_.requireObject(v_, path_);
        for (const auto& item : v_.items()) {
            if (std::find(allowed_.begin(), allowed_.end(), item.key()) == allowed_.end()) {
                reader_.fail(sub(path_, item.key()), "one of the fields " + join(allowed_, ", "),
                             "an unknown field \"" + item.key() + "\"");
            }
        }
    }
    const std::string& path() const { return path_; }
    std::string path(const std::string& key) const { return sub(path_, key); }
    const json* find(const std::string& key) const {
        const auto it = v_.find(key);
        return it == v_.end() ? nullptr : &*it;
    }
    const json& require(const std::string& key, const std::string& expected) const {
        const json* v = find(key);
        if (v == nullptr) reader_.fail(path(key), expected, "nothing (the field is required)");
        return *v;
    }

private:
    const Reader& reader_;
    const json& v_;
    std::string path_;
    std::vector<std::string> allowed_;
};

// The "type" of a light, object or motion, read before the other fields because it decides which
// fields are allowed.
std::string peekType(const Reader& r, const json& v, const std::string& path,
                     const std::vector<std::string>& types) {
    r.requireObject(v, path);
    std::vector<std::string> quoted;
    for (const std::string& t : types) quoted.push_back("\"" + t + "\"");
    const std::string expected = "one of " + join(quoted, ", ");
    const auto it = v.find("type");
    if (it == v.end()) r.fail(sub(path, "type"), expected, "nothing (the field is required)");
    const std::string type = r.string(*it, sub(path, "type"), expected);
    if (std::find(types.begin(), types.end(), type) == types.end()) {
        r.fail(sub(path, "type"), expected, describe(*it));
    }
    return type;
}

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

bool parallel(const glm::vec3& a, const glm::vec3& b) {
    return glm::length(glm::cross(glm::normalize(a), glm::normalize(b))) < 1e-4f;
}

const auto kPositive = [](double x) { return x > 0.0; };
const auto kNonNegative = [](double x) { return x >= 0.0; };
const auto kUnit = [](double x) { return x >= 0.0 && x <= 1.0; };

Camera readCamera(const Reader& r, const json& v, const std::string& path) {
    const Fields f(r, v, path, {"position", "target", "up", "fov_deg", "near", "far"});
    Camera camera;
    camera.position = r.vec3(f.require("position", "an array of 3 numbers"), f.path("position"));
    camera.target = r.vec3(f.require("target", "an array of 3 numbers"), f.path("target"));
    if (const json* up = f.find("up")) camera.up = r.nonZeroVec3(*up, f.path("up"));
    if (const json* fov = f.find("fov_deg")) {
        camera.fovYDegrees = static_cast<float>(
            r.number(*fov, f.path("fov_deg"), "a number in (0, 180)",
                     [](double x) { return x > 0.0 && x < 180.0; }));
    }
    if (const json* near = f.find("near")) {
        camera.nearPlane =
            static_cast<float>(r.number(*near, f.path("near"), "a number > 0", kPositive));
    }
    if (const json* far = f.find("far")) {
        camera.farPlane =
            static_cast<float>(r.number(*far, f.path("far"), "a number > 0", kPositive));
    }
    if (!(camera.farPlane > camera.nearPlane)) {
        r.fail(f.path("far"), "a number greater than near (" + formatNumber(camera.nearPlane) + ")",
               formatNumber(camera.farPlane));
    }
    const glm::vec3 view = camera.target - camera.position;
    if (!(glm::length(view) > 1e-12f)) {
        r.fail(f.path("target"), "a point different from the camera position",
               Reader::describeVec(camera.target));
    }
    if (parallel(view, camera.up)) {
        r.fail(f.path("up"), "a vector not parallel to the view direction (target - position)",
               Reader::describeVec(camera.up));
    }
    return camera;
}

Light readLight(const Reader& r, const json& v, const std::string& path, size_t index) {
    const std::string type = peekType(r, v, path, {"square", "point", "disk", "sphere"});
    std::vector<std::string> allowed = {"name",  "type",      "position",      "direction", "up",
                                        "color", "intensity", "casts_shadows", "technique"};
    if (type == "square") allowed.push_back("width");
    if (type == "disk" || type == "sphere") allowed.push_back("radius");
    const Fields f(r, v, path, allowed);

    Light light;
    light.name = "light" + std::to_string(index);
    if (const json* name = f.find("name")) light.name = r.string(*name, f.path("name"), "a string");
    light.shape = type == "square" ? LightShape::Square
                  : type == "point" ? LightShape::Point
                  : type == "disk"  ? LightShape::Disk
                                    : LightShape::Sphere;
    light.position = r.vec3(f.require("position", "an array of 3 numbers"), f.path("position"));
    glm::vec3 direction(0, -1, 0);
    if (const json* d = f.find("direction")) direction = r.nonZeroVec3(*d, f.path("direction"));
    light.direction = glm::normalize(direction);

    // The in-plane axis: Gram-Schmidt against the direction. When the file gives none and the
    // default (0, 0, -1) is parallel to the direction, (0, 1, 0) is used instead.
    glm::vec3 up(0, 0, -1);
    if (const json* u = f.find("up")) {
        up = r.nonZeroVec3(*u, f.path("up"));
        if (parallel(up, light.direction)) {
            r.fail(f.path("up"), "a vector not parallel to direction " +
                                     Reader::describeVec(light.direction),
                   Reader::describeVec(up));
        }
    } else if (parallel(up, light.direction)) {
        up = glm::vec3(0, 1, 0);
    }
    light.up = glm::normalize(up - glm::dot(up, light.direction) * light.direction);

    if (type == "square") {
        light.size = static_cast<float>(
            r.number(f.require("width", "a number >= 0 (the light's width w_l)"), f.path("width"),
                     "a number >= 0", kNonNegative));
    } else if (type == "disk" || type == "sphere") {
        light.size = static_cast<float>(r.number(f.require("radius", "a number >= 0"),
                                                 f.path("radius"), "a number >= 0", kNonNegative));
    } else {
        light.size = 0.0f;
    }
    if (const json* c = f.find("color"))
        light.color = r.vec3(*c, f.path("color"), "a number >= 0", kNonNegative);
    if (const json* i = f.find("intensity")) {
        light.intensity =
            static_cast<float>(r.number(*i, f.path("intensity"), "a number >= 0", kNonNegative));
    }
    if (const json* c = f.find("casts_shadows"))
        light.castsShadows = r.boolean(*c, f.path("casts_shadows"));
    if (const json* t = f.find("technique")) {
        light.technique = r.string(*t, f.path("technique"), "a technique id (a string)");
    }
    return light;
}

glm::mat4 readTransform(const Reader& r, const json& v, const std::string& path) {
    const Fields f(r, v, path, {"translate", "rotate_deg", "scale"});
    glm::vec3 translate(0.0f), rotateDegrees(0.0f), scale(1.0f);
    if (const json* t = f.find("translate")) translate = r.vec3(*t, f.path("translate"));
    if (const json* a = f.find("rotate_deg")) rotateDegrees = r.vec3(*a, f.path("rotate_deg"));
    if (const json* s = f.find("scale")) {
        const auto nonZero = [](double x) { return x != 0.0; };
        if (s->is_array()) {
            scale = r.vec3(*s, f.path("scale"), "a non-zero number", nonZero);
        } else {
            scale = glm::vec3(static_cast<float>(
                r.number(*s, f.path("scale"), "a non-zero number or an array of 3", nonZero)));
        }
    }
    // worldFromObject = T * Rz * Ry * Rx * S: scale first, then rotate about x, y, z, then move.
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translate);
    m = glm::rotate(m, glm::radians(rotateDegrees.z), glm::vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(rotateDegrees.y), glm::vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rotateDegrees.x), glm::vec3(1, 0, 0));
    return glm::scale(m, scale);
}

Motion readMotion(const Reader& r, const json& v, const std::string& path) {
    const std::string type = peekType(r, v, path, {"rotate", "keyframes"});
    Motion motion;
    if (type == "rotate") {
        const Fields f(r, v, path, {"type", "axis", "pivot", "degrees_per_second"});
        motion.type = Motion::Type::Rotate;
        if (const json* a = f.find("axis"))
            motion.axis = glm::normalize(r.nonZeroVec3(*a, f.path("axis")));
        if (const json* p = f.find("pivot")) motion.pivot = r.vec3(*p, f.path("pivot"));
        motion.degreesPerSecond = static_cast<float>(
            r.number(f.require("degrees_per_second", "a number"), f.path("degrees_per_second")));
        return motion;
    }
    const Fields f(r, v, path, {"type", "keys"});
    motion.type = Motion::Type::Keyframes;
    const json& keys = f.require("keys", "an array of keys {\"time\", \"translate\"}");
    if (!keys.is_array() || keys.empty()) {
        r.fail(f.path("keys"), "a non-empty array of keys {\"time\", \"translate\"}",
               describe(keys));
    }
    for (size_t i = 0; i < keys.size(); ++i) {
        const Fields k(r, keys[i], at(f.path("keys"), i), {"time", "translate"});
        Motion::Key key{};
        key.time =
            static_cast<float>(r.number(k.require("time", "a number >= 0 (seconds)"),
                                        k.path("time"), "a number >= 0 (seconds)", kNonNegative));
        if (i > 0 && !(key.time > motion.keys.back().time)) {
            r.fail(k.path("time"),
                   "a time greater than the previous key's (" +
                       formatNumber(motion.keys.back().time) + ")",
                   formatNumber(key.time));
        }
        key.translate =
            r.vec3(k.require("translate", "an array of 3 numbers"), k.path("translate"));
        motion.keys.push_back(key);
    }
    return motion;
}

int segmentsField(const Reader& r, const Fields& f) {
    if (const json* s = f.find("segments"))
        return static_cast<int>(r.integer(*s, f.path("segments"), 3, 1024));
    return 32;
}

float positiveField(const Reader& r, const Fields& f, const std::string& key) {
    return static_cast<float>(
        r.number(f.require(key, "a number > 0"), f.path(key), "a number > 0", kPositive));
}

Mesh readGenerator(const Reader& r, const Fields& f) {
    const json& g = f.require("generator", "\"plant\" or \"complex\"");
    const std::string generator = r.string(g, f.path("generator"), "\"plant\" or \"complex\"");
    uint64_t seed = 1;
    if (const json* s = f.find("seed")) {
        if (s->is_number_unsigned()) {
            seed = s->get<uint64_t>();
        } else {
            seed = static_cast<uint64_t>(
                r.integer(*s, f.path("seed"), -(int64_t(1) << 53), int64_t(1) << 53));
        }
    }
    const json empty = json::object();
    const json* params = f.find("params");
    const std::string paramsPath = f.path("params");
    if (generator == "plant") {
        const Fields p(r, params ? *params : empty, paramsPath, {"leaves", "height", "spread"});
        PlantParams plant;
        if (const json* x = p.find("leaves"))
            plant.leaves = static_cast<int>(r.integer(*x, p.path("leaves"), 1, 20000));
        if (const json* x = p.find("height")) {
            plant.height =
                static_cast<float>(r.number(*x, p.path("height"), "a number in [0.001, 1000]",
                                            [](double h) { return h >= 1e-3 && h <= 1000.0; }));
        }
        if (const json* x = p.find("spread")) {
            plant.spread =
                static_cast<float>(r.number(*x, p.path("spread"), "a number in [0.001, 1000]",
                                            [](double h) { return h >= 1e-3 && h <= 1000.0; }));
        }
        return generatePlant(seed, plant);
    }
    if (generator == "complex") {
        const Fields p(r, params ? *params : empty, paramsPath, {"count", "extent", "height"});
        ComplexParams complex;
        if (const json* x = p.find("count"))
            complex.count = static_cast<int>(r.integer(*x, p.path("count"), 1, 100000));
        if (const json* x = p.find("extent")) {
            complex.extent =
                static_cast<float>(r.number(*x, p.path("extent"), "a number in [0.001, 10000]",
                                            [](double e) { return e >= 1e-3 && e <= 1e4; }));
        }
        if (const json* x = p.find("height")) {
            complex.height =
                static_cast<float>(r.number(*x, p.path("height"), "a number in [0.001, 10000]",
                                            [](double e) { return e >= 1e-3 && e <= 1e4; }));
        }
        return generateComplex(seed, complex);
    }
    r.fail(f.path("generator"), "\"plant\" or \"complex\"", describe(g));
}

Object readObject(const Reader& r, const json& v, const std::string& path, size_t index,
                  const fs::path& sceneDir) {
    const std::string type = peekType(
        r, v, path, {"plane", "quad", "box", "sphere", "cylinder", "disk", "gltf", "generator"});
    const std::vector<std::string> common = {"name",   "id",           "type",
                                             "transform", "albedo",    "casts_shadows",
                                             "receives_shadows", "motion"};
    static const std::map<std::string, std::vector<std::string>> kTypeFields = {
        {"plane", {"size"}},
        {"quad", {"size"}},
        {"box", {"size"}},
        {"sphere", {"radius", "segments"}},
        {"cylinder", {"radius", "height", "segments"}},
        {"disk", {"radius", "segments"}},
        {"gltf", {"file"}},
        {"generator", {"generator", "seed", "params"}},
    };
    const Fields f(r, v, path, concat(common, kTypeFields.at(type)));

    Object object;
    object.name = type + std::to_string(index);
    if (const json* name = f.find("name"))
        object.name = r.string(*name, f.path("name"), "a string");
    object.id = static_cast<int>(index);
    if (const json* id = f.find("id"))
        object.id = static_cast<int>(r.integer(*id, f.path("id"), 0, (1 << 24) - 1));
    object.source = type;

    if (type == "plane") {
        float size = 1000.0f;
        if (const json* s = f.find("size"))
            size = static_cast<float>(r.number(*s, f.path("size"), "a number > 0", kPositive));
        object.mesh = makeQuad(size, size);
    } else if (type == "quad") {
        const json& s = f.require("size", "an array of 2 numbers > 0 ([size x, size z])");
        if (!s.is_array() || s.size() != 2) {
            r.fail(f.path("size"), "an array of 2 numbers > 0 ([size x, size z])", describe(s));
        }
        const float sx =
            static_cast<float>(r.number(s[0], at(f.path("size"), 0), "a number > 0", kPositive));
        const float sz =
            static_cast<float>(r.number(s[1], at(f.path("size"), 1), "a number > 0", kPositive));
        object.mesh = makeQuad(sx, sz);
    } else if (type == "box") {
        object.mesh = makeBox(r.vec3(f.require("size", "an array of 3 numbers > 0"), f.path("size"),
                                     "a number > 0", kPositive));
    } else if (type == "sphere") {
        object.mesh = makeSphere(positiveField(r, f, "radius"), segmentsField(r, f));
    } else if (type == "cylinder") {
        const float radius = positiveField(r, f, "radius");
        const float height = positiveField(r, f, "height");
        object.mesh = makeCylinder(radius, height, segmentsField(r, f));
    } else if (type == "disk") {
        object.mesh = makeDisk(positiveField(r, f, "radius"), segmentsField(r, f));
    } else if (type == "gltf") {
        const std::string expected = "a .gltf or .glb path relative to the scene file";
        const std::string file = r.string(f.require("file", expected), f.path("file"), expected);
        if (file.empty()) r.fail(f.path("file"), expected, "an empty string");
        const fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : sceneDir / file;
        object.source = "gltf:" + file;
        try {
            object.mesh = loadGltfMesh(resolved.lexically_normal().string());
        } catch (const InputError& e) {
            throw InputError(r.file() + ": " + f.path("file") + ": " + e.what());
        }
    } else {
        object.mesh = readGenerator(r, f);
        object.source = "generator:" + f.find("generator")->get<std::string>();
    }

    if (const json* t = f.find("transform")) {
        object.worldFromObject = readTransform(r, *t, f.path("transform"));
        // Extreme but individually valid numbers can still combine into an unusable transform.
        const float det = glm::determinant(glm::mat3(object.worldFromObject));
        bool finite = std::isfinite(det) && std::abs(det) > 1e-30f;
        for (const glm::vec3& p : object.mesh.positions) {
            const glm::vec4 w = object.worldFromObject * glm::vec4(p, 1.0f);
            finite = finite && std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z);
        }
        if (!finite) {
            r.fail(f.path("transform"), "a transform that keeps the object finite and invertible",
                   "one that does not (determinant " + formatNumber(det) + ")");
        }
    }
    if (const json* a = f.find("albedo"))
        object.albedo = r.vec3(*a, f.path("albedo"), "a number in [0, 1]", kUnit);
    if (const json* c = f.find("casts_shadows"))
        object.castsShadows = r.boolean(*c, f.path("casts_shadows"));
    if (const json* c = f.find("receives_shadows"))
        object.receivesShadows = r.boolean(*c, f.path("receives_shadows"));
    if (const json* m = f.find("motion")) object.motion = readMotion(r, *m, f.path("motion"));
    return object;
}

Scene readScene(const Reader& r, const json& root, const std::string& path) {
    const Fields f(r, root, "", {"name", "description", "camera", "ambient", "lights", "objects"});
    Scene scene;
    scene.path = path;
    scene.name = fs::path(path).stem().string();
    if (const json* n = f.find("name")) {
        scene.name = r.string(*n, "name", "a non-empty string");
        if (scene.name.empty()) r.fail("name", "a non-empty string", "an empty string");
    }
    if (const json* d = f.find("description"))
        scene.description = r.string(*d, "description", "a string");
    scene.camera = readCamera(r, f.require("camera", "an object"), "camera");
    if (const json* a = f.find("ambient")) {
        scene.ambient = static_cast<float>(r.number(*a, "ambient", "a number in [0, 1]", kUnit));
    }

    const json& lights = f.require("lights", "an array of at least one light");
    if (!lights.is_array() || lights.empty())
        r.fail("lights", "an array of at least one light", describe(lights));
    for (size_t i = 0; i < lights.size(); ++i)
        scene.lights.push_back(readLight(r, lights[i], at("lights", i), i));

    // An empty scene (no objects) is allowed: it is one of the hard cases.
    const json& objects = f.require("objects", "an array of objects");
    if (!objects.is_array()) r.fail("objects", "an array of objects", describe(objects));
    const fs::path sceneDir = fs::path(path).parent_path();
    std::map<int, size_t> idOwner;
    for (size_t i = 0; i < objects.size(); ++i) {
        Object object = readObject(r, objects[i], at("objects", i), i, sceneDir);
        const auto [it, inserted] = idOwner.emplace(object.id, i);
        if (!inserted) {
            const bool explicitId = objects[i].contains("id");
            r.fail(sub(at("objects", i), "id"), "an id no other object uses",
                   std::to_string(object.id) +
                       (explicitId ? "" : " (the default: the object's index)") +
                       ", which objects[" + std::to_string(it->second) + "] already has");
        }
        scene.objects.push_back(std::move(object));
    }
    return scene;
}

}  // namespace

Scene loadScene(const std::string& nameOrPath) {
    const std::string path = resolveScenePath(nameOrPath);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) throw InputError(path + ": cannot read the scene file");
    const json root = parseJson(path, text.str());
    return readScene(Reader(path), root, path);
}

// --- Export
// -------------------------------------------------------------------------------------------

void writeTrianglesOBJ(const Scene& scene, double t, const std::string& path) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing");
    char line[128];
    std::snprintf(line, sizeof line, "%.9g", t);
    out << "# shadowlab scene " << scene.name << ", world-space triangles at t = " << line << "\n";
    size_t base = 1;  // OBJ indices are 1-based and global over the file
    for (const Object& object : scene.objects) {
        std::string name = object.name;
        std::replace_if(
            name.begin(), name.end(), [](unsigned char c) { return std::isspace(c); }, '_');
        out << "o " << (name.empty() ? "object" : name) << "\n";
        const glm::mat4 worldFromObject = object.worldFromObjectAt(t);
        for (const glm::vec3& p : object.mesh.positions) {
            const glm::vec3 w = glm::vec3(worldFromObject * glm::vec4(p, 1.0f));
            std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", w.x, w.y, w.z);
            out << line;
        }
        for (size_t i = 0; i + 2 < object.mesh.indices.size(); i += 3) {
            out << "f " << base + object.mesh.indices[i] << ' ' << base + object.mesh.indices[i + 1]
                << ' ' << base + object.mesh.indices[i + 2] << '\n';
        }
        base += object.mesh.positions.size();
    }
    out.flush();
    if (!out) throw InputError(path + ": write failed");
}

}  // namespace shadowlab
