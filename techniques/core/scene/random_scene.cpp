// Generated scenes (issue 25): "random:SEED" is a scene of casters, a light and a camera drawn from
// a seed, so `auto`'s calibration and its tests can be judged on scenes nobody tuned by hand. The
// same seed gives the same scene on every platform (own PRNG, no std distributions).
#include <cmath>
#include <cstdint>
#include <string>

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

}  // namespace

bool isRandomSceneName(const std::string& name) { return name.rfind("random:", 0) == 0; }

Scene randomScene(const std::string& name) {
    const std::string digits = name.substr(7);
    if (digits.empty() || digits.size() > 19 || digits.find_first_not_of("0123456789") != std::string::npos)
        throw InputError("scene '" + name + "': expected random:SEED with SEED a whole number of at most 19 digits");
    const uint64_t seed = std::stoull(digits);
    Rng rng{seed * 0x2545F4914F6CDD1Dull + 1};
    Scene scene;
    scene.name = "random-" + digits;
    scene.path = name;
    scene.description = "generated scene (seed " + digits + "): casters over a ground quad, one light, one camera";

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
    return scene;
}

}  // namespace shadowlab
