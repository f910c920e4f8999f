// Procedural scene generators ("generator" objects in scene files). Both are deterministic: they
// draw from splitmix64 and map bits to floats themselves, because std:: distributions may give
// different numbers on different standard libraries and the golden images must not change.
#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/scene.h"

namespace shadowlab {

namespace {

// splitmix64 (Steele, Lea, Flood 2014): a tiny, well-mixed 64-bit generator.
class SplitMix64 {
public:
    explicit SplitMix64(uint64_t seed) : state_(seed) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1): the top 24 bits, exactly representable in a float.
    float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    int index(int n) { return static_cast<int>((next() >> 33) % static_cast<uint64_t>(n)); }

private:
    uint64_t state_;
};

// A frame whose y axis is `axis` (unit): used to stand a stem along its direction.
glm::mat4 frameAlong(const glm::vec3& origin, const glm::vec3& axis) {
    const glm::vec3 helper = std::abs(axis.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 x = glm::normalize(glm::cross(helper, axis));
    const glm::vec3 z = glm::cross(x, axis);
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(x, 0.0f);
    m[1] = glm::vec4(axis, 0.0f);
    m[2] = glm::vec4(z, 0.0f);
    m[3] = glm::vec4(origin, 1.0f);
    return m;
}

}  // namespace

uint64_t estimatePlantTriangles(const PlantParams& params) {
    // The pot (a 24-segment cylinder), the stems (boxes) and two triangles per leaf, as below.
    const uint64_t stems = static_cast<uint64_t>(std::clamp(params.leaves / 40, 3, 24));
    return estimateCylinderTriangles(24) + 12 * stems + 2 * static_cast<uint64_t>(std::max(params.leaves, 0));
}

uint64_t estimateComplexTriangles(const ComplexParams& params) {
    return 12 * static_cast<uint64_t>(std::max(params.count, 0));
}

// A potted plant like buades2015's "plant" scene: a pot, a few stems fanning out from it, and many
// small diamond-shaped leaves hanging off the stems at random orientations. Thin, numerous,
// overlapping occluders: the case where blocker averaging and occluder fusion go wrong.
Mesh generatePlant(uint64_t seed, const PlantParams& params) {
    SplitMix64 rng(seed);
    Mesh mesh;
    const float height = params.height, spread = params.spread;

    // Pot: a cylinder standing on y = 0.
    const float potRadius = 0.25f * std::min(spread, height);
    const float potHeight = 0.2f * height;
    appendMesh(mesh, makeCylinder(potRadius, potHeight, 24),
           glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.5f * potHeight, 0.0f)));

    // Stems: from the pot's top towards tips spread over the foliage volume.
    const int stemCount = std::clamp(params.leaves / 40, 3, 24);
    const float stemWidth = 0.02f * height;
    std::vector<glm::vec3> stemBase(stemCount), stemTip(stemCount);
    for (int s = 0; s < stemCount; ++s) {
        const float azimuth = glm::two_pi<float>() * (static_cast<float>(s) + rng.uniform()) /
                              static_cast<float>(stemCount);
        const float reach = spread * rng.uniform(0.3f, 1.0f);
        stemBase[s] = glm::vec3(rng.uniform(-0.5f, 0.5f) * potRadius, potHeight,
                                rng.uniform(-0.5f, 0.5f) * potRadius);
        stemTip[s] = glm::vec3(reach * std::cos(azimuth), height * rng.uniform(0.6f, 1.0f),
                               reach * std::sin(azimuth));
        const glm::vec3 along = stemTip[s] - stemBase[s];
        const float length = glm::length(along);
        appendMesh(mesh, makeBox(glm::vec3(stemWidth, length, stemWidth)),
               frameAlong(stemBase[s] + 0.5f * along, along / length));
    }

    // Leaves: a diamond (two triangles) attached to a stem, pointing outwards and somewhat up,
    // rolled at random about its own axis.
    const float leafLength = 0.12f * std::max(height, spread);
    for (int l = 0; l < params.leaves; ++l) {
        const int s = rng.index(stemCount);
        const glm::vec3 attach = glm::mix(stemBase[s], stemTip[s], rng.uniform(0.25f, 1.0f));
        const float azimuth = glm::two_pi<float>() * rng.uniform();
        const float elevation = glm::radians(rng.uniform(-35.0f, 60.0f));
        const glm::vec3 axis(std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                             std::cos(elevation) * std::sin(azimuth));
        const glm::vec3 side0 = glm::normalize(glm::cross(axis, glm::vec3(0, 1, 0)));
        const glm::vec3 side1 = glm::cross(axis, side0);
        const float roll = glm::two_pi<float>() * rng.uniform();
        const glm::vec3 across = std::cos(roll) * side0 + std::sin(roll) * side1;
        const float length = leafLength * rng.uniform(0.7f, 1.3f);
        const float width = 0.45f * length;

        const glm::vec3 base = attach;
        const glm::vec3 tip = attach + length * axis;
        const glm::vec3 left = attach + 0.5f * length * axis + 0.5f * width * across;
        const glm::vec3 right = attach + 0.5f * length * axis - 0.5f * width * across;
        const glm::vec3 normal = glm::normalize(glm::cross(right - base, tip - base));
        const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
        for (const glm::vec3& p : {base, right, tip, left}) {
            mesh.positions.push_back(p);
            mesh.normals.push_back(normal);
        }
        mesh.indices.insert(mesh.indices.end(),
                            {first, first + 1, first + 2, first + 0, first + 2, first + 3});
    }
    return mesh;
}

// High depth complexity for scaling tests (buades2015 Fig. 11): `count` boxes of random size and
// yaw scattered through [-extent, extent]^2 x [0, height], so many surfaces line up along any ray.
Mesh generateComplex(uint64_t seed, const ComplexParams& params) {
    SplitMix64 rng(seed);
    Mesh mesh;
    const float extent = params.extent, height = params.height;
    // Typical box size: boxes would tile the xz square about once at full size.
    const float cell = 2.0f * extent / std::sqrt(static_cast<float>(params.count));
    for (int i = 0; i < params.count; ++i) {
        const glm::vec3 size(std::min(cell * rng.uniform(0.3f, 1.0f), extent),
                             std::min(cell * rng.uniform(0.3f, 2.0f), height),
                             std::min(cell * rng.uniform(0.3f, 1.0f), extent));
        // Keep the yawed box inside the region: its footprint fits in a circle of this radius.
        const float footprint = 0.5f * std::sqrt(size.x * size.x + size.z * size.z);
        const float room = std::max(0.0f, extent - footprint);
        const glm::vec3 centre(rng.uniform(-room, room),
                               rng.uniform(0.5f * size.y, height - 0.5f * size.y),
                               rng.uniform(-room, room));
        const float yaw = glm::two_pi<float>() * rng.uniform();
        const glm::mat4 worldFromBox = glm::rotate(glm::translate(glm::mat4(1.0f), centre), yaw,
                                                   glm::vec3(0, 1, 0));
        appendMesh(mesh, makeBox(size), worldFromBox);
    }
    return mesh;
}

}  // namespace shadowlab
