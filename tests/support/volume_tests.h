// Helpers the penumbra volume tests share (test_pvm.cpp, test_pvmf.cpp): one frame's visibility, the
// RMSE of two visibility images over the pixels a predicate keeps, and a CPU ray/triangle test to
// ray-cast exported volume meshes against what the GPU rasterized.
#pragma once
#include <cmath>
#include <functional>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "graph/renderer.h"
#include "scene/scene.h"

namespace shadowlab::volume_tests {

inline Image renderVisibility(const Scene& scene, const std::string& technique, int size,
                              std::vector<std::pair<std::string, std::string>> sets = {},
                              std::optional<float> lightSize = {}) {
    RenderOptions options;
    options.width = options.height = size;
    options.technique = technique;
    options.sets = std::move(sets);
    options.lightSize = lightSize;
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"visibility"});
    return renderer.visibility();
}

// Over the pixels `inside` keeps (all without it); +inf when it keeps none.
inline double rmse(const Image& a, const Image& b, const std::function<bool(int, int)>& inside = {}) {
    double sq = 0.0;
    size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (inside && !inside(x, y)) continue;
            const double d = double(a.at(x, y)) - b.at(x, y);
            sq += d * d;
            ++n;
        }
    return n ? std::sqrt(sq / double(n)) : INFINITY;
}

// Ray o + t d against the triangle a, b, c (Moller-Trumbore): t > 0, or +inf.
inline float hit(const glm::vec3& o, const glm::vec3& d, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
    const float det = glm::dot(e1, h);
    if (std::abs(det) < 1e-12f) return INFINITY;
    const glm::vec3 s = o - a;
    const float u = glm::dot(s, h) / det;
    if (u < 0.0f || u > 1.0f) return INFINITY;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) / det;
    if (v < 0.0f || u + v > 1.0f) return INFINITY;
    const float t = glm::dot(e2, q) / det;
    return t > 0.0f ? t : INFINITY;
}

}  // namespace shadowlab::volume_tests
