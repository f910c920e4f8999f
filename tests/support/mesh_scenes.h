// Test scenes and sinks shared by the silhouette techniques' tests (ssv, pvm): a one-mesh glTF
// under square-occluder's light and camera (open, non-manifold and degenerate meshes), and an
// InternalSink keeping the internals in memory.
#pragma once
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "graph/internals.h"
#include "image/image.h"

namespace shadowlab::testing {

// A glTF of one mesh (positions, 32-bit indices) with its buffer in a .bin beside it.
inline std::string writeGltf(const std::string& stem, const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices) {
    const std::string dir = std::string(SHADOWLAB_TEST_TMP) + "/mesh-gltf";
    std::filesystem::create_directories(dir);
    const size_t pb = positions.size() * sizeof(glm::vec3), ib = indices.size() * sizeof(uint32_t);
    {
        std::ofstream bin(dir + "/" + stem + ".bin", std::ios::binary);
        bin.write(reinterpret_cast<const char*>(positions.data()), std::streamsize(pb));
        bin.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(ib));
    }
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& q : positions) {
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    nlohmann::json j = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
        {"buffers", {{{"byteLength", pb + ib}, {"uri", stem + ".bin"}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", pb}},
                         {{"buffer", 0}, {"byteOffset", pb}, {"byteLength", ib}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", positions.size()}, {"type", "VEC3"},
                        {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}},
                       {{"bufferView", 1}, {"componentType", 5125}, {"count", indices.size()}, {"type", "SCALAR"}}}}};
    std::ofstream(dir + "/" + stem + ".gltf") << j.dump(1);
    // The scene: square-occluder's floor, light and camera, the mesh as the only caster.
    const std::string scene = dir + "/" + stem + ".json";
    std::ofstream(scene) << R"({"name": ")" << stem << R"(",
  "camera": {"position": [0, 6, 6], "target": [0, 0, 0], "fov_deg": 45, "near": 0.1, "far": 50},
  "lights": [{"name": "key", "type": "square", "position": [0, 4, 0], "direction": [0, -1, 0], "width": 1}],
  "objects": [
    {"name": "floor", "type": "quad", "size": [8, 8], "casts_shadows": false},
    {"name": ")" << stem << R"(", "type": "gltf", "file": ")" << dir + "/" + stem + ".gltf" << R"("}]})";
    return scene;
}

// Keeps the internals in memory.
struct Collected : InternalSink {
    std::map<std::string, Image> images;
    std::map<std::string, MeshData> meshes;
    void image(const std::string& name, const Image& image, const std::string&, const std::string&, int) override {
        images[prefix_ + name] = image;
    }
    void mesh(const std::string& name, const MeshData& mesh, const std::string&, const std::string&) override {
        meshes[prefix_ + name] = mesh;
    }
    void json(const std::string&, const nlohmann::json&, const std::string&, const std::string&) override {}
};

}  // namespace shadowlab::testing
