// Generated scenes (issue 25): "random:SEED" is a scene of casters, a light and a camera drawn from
// a seed, so `auto`'s calibration and its tests can be judged on scenes nobody tuned by hand. The
// same seed gives the same scene on every platform (own PRNG, no std distributions).
// "random:SEED:mesh=NAME" is the same scene with one real mesh of the test set
// (assets/models/README.md) added as a further caster, placed from its own stream of the seed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "error.h"
#include "scene/scene.h"

namespace shadowlab {

namespace {

// splitmix64: a small PRNG whose output is fixed by the seed alone.
struct Rng {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(next() >> 11) * 0x1.0p-53; }
    int integer(int lo, int hi) { return lo + int(next() % uint64_t(hi - lo + 1)); }
};

glm::mat4 translateRotateY(const glm::vec3& t, float radians) {
    glm::mat4 m(1.0f);
    const float c = std::cos(radians), s = std::sin(radians);
    m[0] = glm::vec4(c, 0, -s, 0);
    m[2] = glm::vec4(s, 0, c, 0);
    m[3] = glm::vec4(t, 1.0f);
    return m;
}

const char* const kSyntax = "random:SEED or random:SEED:mesh=NAME";

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

// The options after "random:SEED": ":mesh=NAME" (at most once) is the only one.
std::string parseMeshOption(const std::string& name, const std::string& options) {
    std::string mesh;
    size_t at = 0;
    while (at < options.size()) {
        const size_t end = std::min(options.find(':', at + 1), options.size());
        const std::string option = options.substr(at + 1, end - at - 1);  // after the ':'
        at = end;
        if (option.rfind("mesh=", 0) != 0)
            throw InputError("scene '" + name + "': expected " + kSyntax + ", got the option '" + option +
                             "' (the only option is mesh=NAME)");
        if (!mesh.empty()) throw InputError("scene '" + name + "': mesh= given twice, expected " + kSyntax);
        mesh = option.substr(5);
        const std::vector<std::string>& known = realMeshNames();
        if (std::find(known.begin(), known.end(), mesh) == known.end())
            throw InputError("scene '" + name + "': mesh=" + (mesh.empty() ? "(nothing)" : mesh) +
                             ": expected one of the real meshes " + joined(known) + " (assets/models/README.md)");
    }
    return mesh;
}

// The real mesh as caster `id`: on the ground (the converter puts its bottom on y = 0) within the
// casters' square, turned about y and scaled from 1.5 to 0.9 .. 1.8 units, all from `rng`.
Object realMeshCaster(const std::string& mesh, int id, Rng& rng, const SceneLimits& limits) {
    const std::string path = realMeshPath(mesh);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(path + ": no such glTF file, expected the real mesh '" + mesh +
                         "' (made by scripts/fetch-meshes.sh, which the test build runs; assets/models/README.md)");
    Object o;
    o.id = id;
    o.name = mesh;
    o.source = "gltf:" + path;
    o.mesh = loadGltfMesh(path, limits);
    const glm::vec3 at(float(rng.uniform(-1.5, 1.5)), 0.0f, float(rng.uniform(-1.5, 1.5)));
    const float yaw = float(rng.uniform(0.0, 6.2831853));
    const float scale = float(rng.uniform(0.6, 1.2));
    o.worldFromObject = translateRotateY(at, yaw) * glm::mat4(glm::mat3(scale));
    o.albedo = glm::vec3(float(rng.uniform(0.4, 0.9)), float(rng.uniform(0.4, 0.9)), float(rng.uniform(0.4, 0.9)));
    return o;
}

}  // namespace

const std::vector<std::string>& realMeshNames() {
    // The table of scripts/fetch-meshes.sh, sorted (tests/core/test_scene.cpp compares the two).
    static const std::vector<std::string> names = {"boeing", "bunny", "chinese-dragon", "elephant-holes",
                                                   "snowden", "stanford-dragon", "teapot"};
    return names;
}

std::string realMeshPath(const std::string& name) {
    return (std::filesystem::path(projectRoot()) / "assets" / "models" / "real" / (name + ".gltf")).string();
}

bool isRandomSceneName(const std::string& name) { return name.rfind("random:", 0) == 0; }

Scene randomScene(const std::string& name, const SceneLimits& limits) {
    const size_t optionsAt = std::min(name.find(':', 7), name.size());
    const std::string digits = name.substr(7, optionsAt - 7);
    if (digits.empty() || digits.size() > 19 || digits.find_first_not_of("0123456789") != std::string::npos)
        throw InputError("scene '" + name + "': expected " + kSyntax + " with SEED a whole number of at most 19 digits");
    const std::string mesh = parseMeshOption(name, name.substr(optionsAt));
    const uint64_t seed = std::stoull(digits);
    Rng rng{seed * 0x2545F4914F6CDD1Dull + 1};
    Scene scene;
    scene.name = "random-" + digits + (mesh.empty() ? "" : "-" + mesh);
    scene.path = name;
    scene.description = "generated scene (seed " + digits + "): casters over a ground quad, one light, one camera" +
                        (mesh.empty() ? std::string() : ", and the real mesh '" + mesh + "'");

    Object ground;
    ground.name = "ground";
    ground.source = "quad";
    ground.id = 0;
    ground.mesh = makeQuad(12.0f, 12.0f);
    ground.castsShadows = false;
    scene.objects.push_back(ground);

    const int casters = rng.integer(1, 5);
    for (int i = 0; i < casters; ++i) {
        Object o;
        o.id = i + 1;
        const int kind = rng.integer(0, 3);
        const float s = float(rng.uniform(0.25, 1.2));
        float halfHeight = 0.5f * s;
        switch (kind) {
            case 0:
                o.source = "box";
                o.mesh = makeBox({s, float(rng.uniform(0.1, 1.0)) * s + 0.02f, float(rng.uniform(0.4, 1.0)) * s});
                halfHeight = 0.5f * s;
                break;
            case 1:
                o.source = "sphere";
                o.mesh = makeSphere(0.5f * s, 32);
                break;
            case 2:
                o.source = "cylinder";
                o.mesh = makeCylinder(0.3f * s, s, 24);
                break;
            default:  // a thin plate: the soft-shadow papers' favourite occluder
                o.source = "box";
                o.mesh = makeBox({s, 0.02f, s});
                halfHeight = 0.01f;
                break;
        }
        o.name = o.source + std::to_string(i + 1);
        // Half of them touch the ground (contact shadows), the others float up to 2 units above it.
        const float lift = rng.uniform(0.0, 1.0) < 0.5 ? 0.0f : float(rng.uniform(0.1, 2.0));
        const glm::vec3 at(float(rng.uniform(-1.8, 1.8)), halfHeight + lift, float(rng.uniform(-1.8, 1.8)));
        o.worldFromObject = translateRotateY(at, float(rng.uniform(0.0, 3.14159)));
        o.albedo = glm::vec3(float(rng.uniform(0.4, 0.9)), float(rng.uniform(0.4, 0.9)), float(rng.uniform(0.4, 0.9)));
        scene.objects.push_back(o);
    }

    Light light;
    light.name = "key";
    const double pick = rng.uniform(0.0, 1.0);
    light.shape = pick < 0.7 ? LightShape::Square : pick < 0.85 ? LightShape::Disk : LightShape::Sphere;
    light.position = glm::vec3(float(rng.uniform(-2.0, 2.0)), float(rng.uniform(3.5, 7.0)), float(rng.uniform(-2.0, 2.0)));
    const glm::vec3 aim(float(rng.uniform(-0.5, 0.5)), 0.0f, float(rng.uniform(-0.5, 0.5)));
    light.direction = glm::normalize(aim - light.position);
    light.up = glm::normalize(glm::cross(glm::vec3(1, 0, 0), light.direction));
    const float width = float(rng.uniform(0.2, 2.0));
    light.size = light.shape == LightShape::Square ? width : 0.5f * width;
    scene.lights.push_back(light);

    const double azimuth = rng.uniform(0.0, 6.2831853), elevation = rng.uniform(0.45, 1.0), distance = rng.uniform(5.5, 9.0);
    scene.camera.target = glm::vec3(0.0f, 0.4f, 0.0f);
    scene.camera.position = scene.camera.target + float(distance) * glm::vec3(float(std::cos(elevation) * std::cos(azimuth)),
                                                                            float(std::sin(elevation)),
                                                                            float(std::cos(elevation) * std::sin(azimuth)));
    if (!mesh.empty()) {
        // Its own stream of the seed, drawn last: random:SEED's casters, light and camera stay as
        // they are without the mesh (auto's calibration and tests name seeds).
        Rng meshRng{seed * 0x9E6C63D0676A9A99ull + 7};
        scene.objects.push_back(realMeshCaster(mesh, casters + 1, meshRng, limits));
    }
    return scene;
}

}  // namespace shadowlab
