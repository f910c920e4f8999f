// The scene-file schema (assets/scenes/README.md): camera, lights, objects, transforms, motion and
// generators, read from JSON through the validated reader (json_reader.h). Every field a file
// contains is either read or reported, and every error names the file and the field path
// ("objects[2].albedo[1]") and its line, with what was expected and what was found. Loading has two
// steps: every object is read and validated and its triangle count computed first; only when the
// total is within the scene limits (SceneLimits) are the meshes built.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <map>

#include "error.h"
#include "scene/input_file.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace shadowlab {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

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

Camera readCamera(const JsonReader& r, const json& v, const std::string& path) {
    const JsonFields f(r, v, path, {"position", "target", "up", "fov_deg", "near", "far"});
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
               JsonReader::describeVec(camera.target));
    }
    if (parallel(view, camera.up)) {
        r.fail(f.path("up"), "a vector not parallel to the view direction (target - position)",
               JsonReader::describeVec(camera.up));
    }
    return camera;
}

Light readLight(const JsonReader& r, const json& v, const std::string& path, size_t index) {
    const std::string type = r.peekOneOf(v, path, "type", {"square", "point", "disk", "sphere"});
    std::vector<std::string> allowed = {"name",  "type",      "position",      "direction", "up",
                                        "color", "intensity", "casts_shadows", "technique"};
    if (type == "square") allowed.push_back("width");
    if (type == "disk" || type == "sphere") allowed.push_back("radius");
    const JsonFields f(r, v, path, allowed);

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
                                     JsonReader::describeVec(light.direction),
                   JsonReader::describeVec(up));
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

glm::mat4 readTransform(const JsonReader& r, const json& v, const std::string& path) {
    const JsonFields f(r, v, path, {"translate", "rotate_deg", "scale"});
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

Motion readMotion(const JsonReader& r, const json& v, const std::string& path) {
    const std::string type = r.peekOneOf(v, path, "type", {"rotate", "keyframes"});
    Motion motion;
    if (type == "rotate") {
        const JsonFields f(r, v, path, {"type", "axis", "pivot", "degrees_per_second"});
        motion.type = Motion::Type::Rotate;
        if (const json* a = f.find("axis"))
            motion.axis = glm::normalize(r.nonZeroVec3(*a, f.path("axis")));
        if (const json* p = f.find("pivot")) motion.pivot = r.vec3(*p, f.path("pivot"));
        motion.degreesPerSecond = static_cast<float>(
            r.number(f.require("degrees_per_second", "a number"), f.path("degrees_per_second")));
        return motion;
    }
    const JsonFields f(r, v, path, {"type", "keys"});
    motion.type = Motion::Type::Keyframes;
    const json& keys = f.require("keys", "an array of keys {\"time\", \"translate\"}");
    if (!keys.is_array() || keys.empty()) {
        r.fail(f.path("keys"), "a non-empty array of keys {\"time\", \"translate\"}",
               describeJson(keys));
    }
    for (size_t i = 0; i < keys.size(); ++i) {
        const JsonFields k(r, keys[i], elementPath(f.path("keys"), i), {"time", "translate"});
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

int segmentsField(const JsonReader& r, const JsonFields& f) {
    if (const json* s = f.find("segments"))
        return static_cast<int>(r.integer(*s, f.path("segments"), 3, 1024));
    return 32;
}

float positiveField(const JsonReader& r, const JsonFields& f, const std::string& key) {
    return static_cast<float>(
        r.number(f.require(key, "a number > 0"), f.path(key), "a number > 0", kPositive));
}

// An object read and validated, its mesh not built yet: `triangles` is what build() will make.
struct PendingObject {
    Object object;
    uint64_t triangles = 0;
    std::function<Mesh()> build;
};

void readGenerator(const JsonReader& r, const JsonFields& f, PendingObject& pending) {
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
        const JsonFields p(r, params ? *params : empty, paramsPath, {"leaves", "height", "spread"});
        PlantParams plant;
        plant.leaves = static_cast<int>(p.integer("leaves", plant.leaves, 1, 20000));
        plant.height = static_cast<float>(p.number("height", plant.height, inRange(1e-3, 1000.0)));
        plant.spread = static_cast<float>(p.number("spread", plant.spread, inRange(1e-3, 1000.0)));
        pending.triangles = estimatePlantTriangles(plant);
        pending.build = [seed, plant] { return generatePlant(seed, plant); };
        return;
    }
    if (generator == "complex") {
        const JsonFields p(r, params ? *params : empty, paramsPath, {"count", "extent", "height"});
        ComplexParams complex;
        complex.count = static_cast<int>(p.integer("count", complex.count, 1, 100000));
        complex.extent = static_cast<float>(p.number("extent", complex.extent, inRange(1e-3, 1e4)));
        complex.height = static_cast<float>(p.number("height", complex.height, inRange(1e-3, 1e4)));
        pending.triangles = estimateComplexTriangles(complex);
        pending.build = [seed, complex] { return generateComplex(seed, complex); };
        return;
    }
    r.fail(f.path("generator"), "\"plant\" or \"complex\"", describeJson(g));
}

PendingObject readObject(const JsonReader& r, const json& v, const std::string& path, size_t index,
                         const fs::path& sceneDir, const SceneLimits& limits, std::vector<std::string>& warnings) {
    const std::string type = r.peekOneOf(v, path, "type", {"plane", "quad", "box", "sphere", "cylinder", "disk", "gltf", "generator"});
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
    const JsonFields f(r, v, path, concat(common, kTypeFields.at(type)));

    PendingObject pending;
    Object& object = pending.object;
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
        pending.triangles = 2;
        pending.build = [size] { return makeQuad(size, size); };
    } else if (type == "quad") {
        const json& s = f.require("size", "an array of 2 numbers > 0 ([size x, size z])");
        if (!s.is_array() || s.size() != 2) {
            r.fail(f.path("size"), "an array of 2 numbers > 0 ([size x, size z])", describeJson(s));
        }
        const float sx =
            static_cast<float>(r.number(s[0], elementPath(f.path("size"), 0), "a number > 0", kPositive));
        const float sz =
            static_cast<float>(r.number(s[1], elementPath(f.path("size"), 1), "a number > 0", kPositive));
        pending.triangles = 2;
        pending.build = [sx, sz] { return makeQuad(sx, sz); };
    } else if (type == "box") {
        const glm::vec3 size = r.vec3(f.require("size", "an array of 3 numbers > 0"), f.path("size"),
                                      "a number > 0", kPositive);
        pending.triangles = 12;
        pending.build = [size] { return makeBox(size); };
    } else if (type == "sphere") {
        const float radius = positiveField(r, f, "radius");
        const int segments = segmentsField(r, f);
        pending.triangles = estimateSphereTriangles(segments);
        pending.build = [radius, segments] { return makeSphere(radius, segments); };
    } else if (type == "cylinder") {
        const float radius = positiveField(r, f, "radius");
        const float height = positiveField(r, f, "height");
        const int segments = segmentsField(r, f);
        pending.triangles = estimateCylinderTriangles(segments);
        pending.build = [radius, height, segments] { return makeCylinder(radius, height, segments); };
    } else if (type == "disk") {
        const float radius = positiveField(r, f, "radius");
        const int segments = segmentsField(r, f);
        pending.triangles = estimateDiskTriangles(segments);
        pending.build = [radius, segments] { return makeDisk(radius, segments); };
    } else if (type == "gltf") {
        const std::string expected = "a .gltf or .glb path relative to the scene file";
        const std::string file = r.string(f.require("file", expected), f.path("file"), expected);
        if (file.empty()) r.fail(f.path("file"), expected, "an empty string");
        const fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : sceneDir / file;
        object.source = "gltf:" + file;
        const std::string gltf = resolved.lexically_normal().string();
        const std::string place = r.place(f.path("file"));
        try {
            pending.triangles = estimateGltfTriangles(gltf);
        } catch (const InputError& e) {
            throw InputError(place + ": " + e.what());
        }
        pending.build = [gltf, place, limits, &warnings] {
            try {
                std::vector<std::string> gltfWarnings;
                Mesh mesh = loadGltfMesh(gltf, limits, &gltfWarnings);
                for (const std::string& w : gltfWarnings) warnings.push_back(place + ": " + w);
                return mesh;
            } catch (const InputError& e) {
                throw InputError(place + ": " + e.what());
            }
        };
    } else {
        readGenerator(r, f, pending);
        object.source = "generator:" + f.find("generator")->get<std::string>();
    }

    if (const json* t = f.find("transform")) {
        object.worldFromObject = readTransform(r, *t, f.path("transform"));
        // Extreme but individually valid numbers can still combine into an unusable transform:
        // checked on the vertices once the mesh is built.
        const glm::mat4 worldFromObject = object.worldFromObject;
        const std::string transformPath = f.path("transform");
        pending.build = [&r, worldFromObject, transformPath, build = std::move(pending.build)] {
            Mesh mesh = build();
            const float det = glm::determinant(glm::mat3(worldFromObject));
            bool finite = std::isfinite(det) && std::abs(det) > 1e-30f;
            for (const glm::vec3& p : mesh.positions) {
                const glm::vec4 w = worldFromObject * glm::vec4(p, 1.0f);
                finite = finite && std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z);
            }
            if (!finite) {
                r.fail(transformPath, "a transform that keeps the object finite and invertible",
                       "one that does not (determinant " + formatNumber(det) + ")");
            }
            return mesh;
        };
    }
    if (const json* a = f.find("albedo"))
        object.albedo = r.vec3(*a, f.path("albedo"), "a number in [0, 1]", kUnit);
    if (const json* c = f.find("casts_shadows"))
        object.castsShadows = r.boolean(*c, f.path("casts_shadows"));
    if (const json* c = f.find("receives_shadows"))
        object.receivesShadows = r.boolean(*c, f.path("receives_shadows"));
    if (const json* m = f.find("motion")) object.motion = readMotion(r, *m, f.path("motion"));
    return pending;
}

Scene readScene(const JsonReader& r, const json& root, const std::string& path, const SceneLimits& limits) {
    const JsonFields f(r, root, "", {"name", "description", "camera", "ambient", "lights", "objects"});
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
        r.fail("lights", "an array of at least one light", describeJson(lights));
    for (size_t i = 0; i < lights.size(); ++i)
        scene.lights.push_back(readLight(r, lights[i], elementPath("lights", i), i));

    // An empty scene (no objects) is allowed: it is one of the hard cases.
    const json& objects = f.require("objects", "an array of objects");
    if (!objects.is_array()) r.fail("objects", "an array of objects", describeJson(objects));
    const fs::path sceneDir = fs::path(path).parent_path();
    std::map<int, size_t> idOwner;
    std::vector<PendingObject> pending;
    uint64_t triangles = 0;
    size_t largest = 0;
    for (size_t i = 0; i < objects.size(); ++i) {
        pending.push_back(
            readObject(r, objects[i], elementPath("objects", i), i, sceneDir, limits, scene.warnings));
        const Object& object = pending.back().object;
        triangles += pending.back().triangles;
        if (pending.back().triangles > pending[largest].triangles) largest = i;
        const auto [it, inserted] = idOwner.emplace(object.id, i);
        if (!inserted) {
            const bool explicitId = objects[i].contains("id");
            r.fail(fieldPath(elementPath("objects", i), "id"), "an id no other object uses",
                   std::to_string(object.id) +
                       (explicitId ? "" : " (the default: the object's index)") +
                       ", which objects[" + std::to_string(it->second) + "] already has");
        }
    }
    // Everything is valid: check the size of the whole scene before building any mesh.
    if (triangles > limits.maxTriangles) {
        const PendingObject& big = pending[largest];
        throw InputError(
            path + ": the scene would need " + std::to_string(triangles) + " triangles (about " +
            describeBytes(double(triangles) * double(kBytesPerTriangle)) + " of memory) for " +
            std::to_string(pending.size()) + " object(s), the largest " + elementPath("objects", largest) + " \"" +
            big.object.name + "\" with " + std::to_string(big.triangles) + "; that is over the limit of " +
            std::to_string(limits.maxTriangles) + " triangles (--max-triangles N raises it)");
    }
    for (PendingObject& p : pending) {
        p.object.mesh = p.build();
        p.build = nullptr;  // frees what the builder holds
        scene.objects.push_back(std::move(p.object));
    }
    return scene;
}

}  // namespace

Scene sceneAroundGltf(const std::string& path, const SceneLimits& limits) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(path + ": no such file");
    Scene scene;
    scene.name = fs::path(path).stem().string();
    scene.path = path;
    scene.description = "glTF file " + path + " on a ground quad under a square light";
    Object model;
    model.name = scene.name;
    model.source = "gltf:" + path;
    model.id = 1;
    model.mesh = loadGltfMesh(path, limits);
    if (model.mesh.indices.empty()) throw InputError(path + ": the glTF file holds no triangles");
    Bounds b;
    for (const glm::vec3& p : model.mesh.positions) b.extend(p);
    glm::vec3 centre = 0.5f * (b.lo + b.hi);
    float extent = std::max({b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z, 1e-3f});
    // Scaled to 2 world units, standing on the ground at the origin.
    float scale = 2.0f / extent;
    model.worldFromObject = glm::mat4(1.0f);
    model.worldFromObject[0][0] = model.worldFromObject[1][1] = model.worldFromObject[2][2] = scale;
    model.worldFromObject[3] = glm::vec4(-scale * centre.x, -scale * b.lo.y, -scale * centre.z, 1.0f);
    Object ground;
    ground.name = "ground";
    ground.source = "quad";
    ground.id = 0;
    ground.mesh = makeQuad(8.0f, 8.0f);
    ground.castsShadows = false;
    scene.objects = {ground, model};
    Light light;
    light.name = "key";
    light.position = {0.5f, 5.0f, 0.5f};
    light.size = 1.0f;
    scene.lights = {light};
    scene.camera.position = {0.0f, 3.5f, 6.0f};
    scene.camera.target = {0.0f, 0.8f, 0.0f};
    return scene;
}

Scene loadScene(const std::string& nameOrPath, const SceneLimits& limits) {
    auto endsWith = [&](const char* suffix) {
        const std::string s(suffix);
        return nameOrPath.size() >= s.size() && nameOrPath.compare(nameOrPath.size() - s.size(), s.size(), s) == 0;
    };
    if (endsWith(".gltf") || endsWith(".glb")) return sceneAroundGltf(nameOrPath, limits);
    if (isRandomSceneName(nameOrPath)) return randomScene(nameOrPath, limits);
    const std::string path = resolveScenePath(nameOrPath);
    // Through the input gate (scene/input_file.h): a regular file of at most 256 MB (far beyond any
    // scene: geometry comes from primitives, generators and glTF), opened once.
    const std::string text = readInputFile(path, "scene file", kMaxSceneInputBytes);
    if (text.empty()) throw InputError(path + ": the file is empty, expected a JSON scene object");
    const JsonDocument document = JsonDocument::fromString(path, text);
    // Messages name the file, the line and the field path ("scene.json:12: objects[2].size[1]: ...").
    const JsonReader reader(document, JsonReader::Lines::Named);
    return readScene(reader, document.root(), path, limits);
}


}  // namespace shadowlab
