// glTF 2.0 (.gltf and .glb) meshes for "gltf" scene objects, read with tinygltf. Everything the
// file says is checked before it is used (indices, accessor ranges, node cycles): a user's file
// may be wrong, and a bad file must give an error naming it, never a crash.
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "error.h"
#include "json_reader.h"
#include "scene.h"

namespace shadowlab {

namespace {

// Images are irrelevant to shadows: accept and ignore them instead of decoding textures.
bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                 const unsigned char*, int, void*) {
    return true;
}

class GltfReader {
public:
    GltfReader(const std::string& path, const tinygltf::Model& model)
        : path_(path), model_(model) {}

    [[noreturn]] void fail(const std::string& message) const {
        throw InputError(path_ + ": " + message);
    }

    // The bytes of accessor `index`, after checking that they lie inside their buffer.
    struct View {
        const unsigned char* data = nullptr;
        size_t stride = 0;
        size_t count = 0;
        int componentType = 0;
        int components = 0;
    };
    View view(int index, const std::string& what) const {
        if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size()) {
            fail(what + ": accessor " + std::to_string(index) + " does not exist");
        }
        const tinygltf::Accessor& accessor = model_.accessors[static_cast<size_t>(index)];
        const std::string name = what + " (accessor " + std::to_string(index) + ")";
        if (accessor.sparse.isSparse) fail(name + ": sparse accessors are not supported");
        if (accessor.bufferView < 0 ||
            static_cast<size_t>(accessor.bufferView) >= model_.bufferViews.size()) {
            fail(name + ": has no valid bufferView");
        }
        const tinygltf::BufferView& bufferView =
            model_.bufferViews[static_cast<size_t>(accessor.bufferView)];
        if (bufferView.buffer < 0 ||
            static_cast<size_t>(bufferView.buffer) >= model_.buffers.size()) {
            fail(name + ": bufferView " + std::to_string(accessor.bufferView) +
                 " has no valid buffer");
        }
        const tinygltf::Buffer& buffer = model_.buffers[static_cast<size_t>(bufferView.buffer)];
        const int componentSize =
            tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType));
        const int components =
            tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
        if (componentSize <= 0 || components <= 0) fail(name + ": unknown component type or type");
        const size_t elementSize =
            static_cast<size_t>(componentSize) * static_cast<size_t>(components);
        const size_t stride = bufferView.byteStride != 0 ? bufferView.byteStride : elementSize;
        if (stride < elementSize) fail(name + ": byteStride is smaller than one element");
        if (bufferView.byteOffset > buffer.data.size() ||
            bufferView.byteLength > buffer.data.size() - bufferView.byteOffset) {
            fail(name + ": bufferView " + std::to_string(accessor.bufferView) +
                 " lies outside its buffer");
        }
        const size_t available = bufferView.byteLength;
        // Bytes needed: byteOffset + stride * (count - 1) + elementSize, written to avoid overflow.
        if (accessor.count > 0) {
            const bool fits = accessor.byteOffset <= available &&
                              elementSize <= available - accessor.byteOffset &&
                              (accessor.count - 1) <=
                                  (available - accessor.byteOffset - elementSize) / stride;
            if (!fits) fail(name + ": " + std::to_string(accessor.count) +
                            " elements do not fit in bufferView " +
                            std::to_string(accessor.bufferView));
        }
        View v;
        v.data = buffer.data.data() + bufferView.byteOffset + accessor.byteOffset;
        v.stride = stride;
        v.count = accessor.count;
        v.componentType = accessor.componentType;
        v.components = components;
        return v;
    }

    std::vector<glm::vec3> readVec3(int index, const std::string& what) const {
        const View v = view(index, what);
        if (v.components != 3 || v.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
            fail(what + " (accessor " + std::to_string(index) + "): expected VEC3 of FLOAT");
        }
        std::vector<glm::vec3> out(v.count);
        for (size_t i = 0; i < v.count; ++i) {
            float xyz[3];
            std::memcpy(xyz, v.data + i * v.stride, sizeof xyz);
            out[i] = glm::vec3(xyz[0], xyz[1], xyz[2]);
            if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) {
                fail(what + " (accessor " + std::to_string(index) + "): element " +
                     std::to_string(i) + " is not finite");
            }
        }
        return out;
    }

    std::vector<uint32_t> readIndices(int index, size_t vertexCount,
                                      const std::string& what) const {
        const View v = view(index, what);
        if (v.components != 1) fail(what + ": expected SCALAR indices");
        std::vector<uint32_t> out(v.count);
        for (size_t i = 0; i < v.count; ++i) {
            const unsigned char* p = v.data + i * v.stride;
            // Reads one index stored as T (memcpy: glTF data need not be aligned).
            auto as = [p](auto zero) {
                decltype(zero) x;
                std::memcpy(&x, p, sizeof x);
                return int64_t(x);
            };
            int64_t value = 0;
            switch (v.componentType) {
                case TINYGLTF_COMPONENT_TYPE_BYTE: value = as(int8_t()); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: value = as(uint8_t()); break;
                case TINYGLTF_COMPONENT_TYPE_SHORT: value = as(int16_t()); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: value = as(uint16_t()); break;
                case TINYGLTF_COMPONENT_TYPE_INT: value = as(int32_t()); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: value = as(uint32_t()); break;
                default: fail(what + ": indices must be integers");
            }
            if (value < 0 || static_cast<uint64_t>(value) >= vertexCount) {
                fail(what + ": index " + std::to_string(value) + " at position " +
                     std::to_string(i) + " is out of range (" + std::to_string(vertexCount) +
                     " vertices)");
            }
            out[i] = static_cast<uint32_t>(value);
        }
        return out;
    }

    // One primitive in mesh space.
    Mesh primitive(const tinygltf::Primitive& primitive, const std::string& what) const {
        const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
        if (mode != TINYGLTF_MODE_TRIANGLES) {
            fail(what + ": primitive mode must be TRIANGLES (4), got " + std::to_string(mode) +
                 " (points, lines, strips and fans are not supported)");
        }
        const auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end()) fail(what + ": has no POSITION attribute");
        Mesh mesh;
        mesh.positions = readVec3(position->second, what + ".POSITION");
        if (primitive.indices >= 0) {
            mesh.indices = readIndices(primitive.indices, mesh.positions.size(), what + ".indices");
        } else {
            mesh.indices.resize(mesh.positions.size());
            for (size_t i = 0; i < mesh.indices.size(); ++i)
                mesh.indices[i] = static_cast<uint32_t>(i);
        }
        if (mesh.indices.size() % 3 != 0) {
            fail(what + ": " + std::to_string(mesh.indices.size()) +
                 " indices is not a whole number of triangles");
        }
        const auto normal = primitive.attributes.find("NORMAL");
        if (normal != primitive.attributes.end()) {
            mesh.normals = readVec3(normal->second, what + ".NORMAL");
            if (mesh.normals.size() != mesh.positions.size()) {
                fail(what + ": NORMAL and POSITION have different counts");
            }
        } else {
            computeSmoothNormals(mesh);
        }
        return mesh;
    }

    void addMesh(Mesh& out, int meshIndex, const glm::mat4& worldFromMesh) const {
        if (meshIndex < 0 || static_cast<size_t>(meshIndex) >= model_.meshes.size()) {
            fail("mesh " + std::to_string(meshIndex) + " does not exist");
        }
        const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(meshIndex)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const std::string what =
                "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(p) + "]";
            appendMesh(out, primitive(mesh.primitives[p], what), worldFromMesh);
        }
    }

    glm::mat4 localTransform(const tinygltf::Node& node, int index) const {
        const std::string what = "nodes[" + std::to_string(index) + "]";
        glm::dmat4 m(1.0);
        if (!node.matrix.empty()) {
            if (node.matrix.size() != 16) fail(what + ".matrix: expected 16 numbers");
            m = glm::make_mat4(node.matrix.data());  // column-major in both glTF and GLM
        } else {
            glm::dvec3 t(0.0), s(1.0);
            glm::dquat r(1.0, 0.0, 0.0, 0.0);
            if (!node.translation.empty()) {
                if (node.translation.size() != 3) fail(what + ".translation: expected 3 numbers");
                t = glm::make_vec3(node.translation.data());
            }
            if (!node.rotation.empty()) {
                if (node.rotation.size() != 4) fail(what + ".rotation: expected 4 numbers");
                // glTF stores (x, y, z, w); glm::dquat's constructor takes (w, x, y, z).
                r = glm::normalize(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1],
                                              node.rotation[2]));
            }
            if (!node.scale.empty()) {
                if (node.scale.size() != 3) fail(what + ".scale: expected 3 numbers");
                s = glm::make_vec3(node.scale.data());
            }
            // glTF: M = T * R * S.
            m = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(r) *
                glm::scale(glm::dmat4(1.0), s);
        }
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) {
                if (!std::isfinite(m[c][r])) fail(what + ": transform is not finite");
            }
        }
        return glm::mat4(m);
    }

    void addNode(Mesh& out, int index, const glm::mat4& worldFromParent,
                 std::vector<bool>& onPath) const {
        if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size()) {
            fail("node " + std::to_string(index) + " does not exist");
        }
        if (onPath[static_cast<size_t>(index)]) {
            fail("nodes[" + std::to_string(index) +
                 "] is its own ancestor (cycle in the node tree)");
        }
        onPath[static_cast<size_t>(index)] = true;
        const tinygltf::Node& node = model_.nodes[static_cast<size_t>(index)];
        const glm::mat4 worldFromNode = worldFromParent * localTransform(node, index);
        if (node.mesh >= 0) addMesh(out, node.mesh, worldFromNode);
        for (int child : node.children) addNode(out, child, worldFromNode, onPath);
        onPath[static_cast<size_t>(index)] = false;
    }

    Mesh all() const {
        Mesh out;
        std::vector<bool> onPath(model_.nodes.size(), false);
        std::vector<int> roots;
        if (!model_.scenes.empty()) {
            // The default scene, or scene 0 when the file names none.
            const int scene = model_.defaultScene >= 0 && static_cast<size_t>(model_.defaultScene) <
                                                              model_.scenes.size()
                                  ? model_.defaultScene
                                  : 0;
            roots = model_.scenes[static_cast<size_t>(scene)].nodes;
        } else if (!model_.nodes.empty()) {
            // No scenes: every node that is nobody's child is a root.
            std::vector<bool> isChild(model_.nodes.size(), false);
            for (const tinygltf::Node& node : model_.nodes) {
                for (int child : node.children) {
                    if (child >= 0 && static_cast<size_t>(child) < isChild.size()) {
                        isChild[static_cast<size_t>(child)] = true;
                    }
                }
            }
            for (size_t i = 0; i < model_.nodes.size(); ++i) {
                if (!isChild[i]) roots.push_back(static_cast<int>(i));
            }
        } else {
            // No nodes at all: take every mesh as it is.
            for (size_t m = 0; m < model_.meshes.size(); ++m) {
                addMesh(out, static_cast<int>(m), glm::mat4(1.0f));
            }
        }
        for (int root : roots) addNode(out, root, glm::mat4(1.0f), onPath);
        if (out.triangleCount() == 0) fail("contains no triangles");
        for (const glm::vec3& p : out.positions) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                fail("a transformed vertex position is not finite");
            }
        }
        return out;
    }

private:
    const std::string& path_;
    const tinygltf::Model& model_;
};

}  // namespace

Mesh loadGltfMesh(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such glTF file");
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension != ".gltf" && extension != ".glb") {
        throw InputError(path + ": expected a .gltf or .glb file, got extension '" + extension +
                         "'");
    }

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(ignoreImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = false;
    try {
        ok = extension == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                 : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    } catch (const std::exception& e) {
        err = e.what();
        ok = false;
    }
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        // tinygltf passes on nlohmann's "[json.exception.parse_error.101] " tag: drop the tag.
        if (err.rfind("[json.exception.", 0) == 0 && err.find("] ") != std::string::npos) {
            err = err.substr(err.find("] ") + 2);
        }
        err = shortenLastRead(err);
        if (err.size() > 500) err = err.substr(0, 497) + "...";
        throw InputError(path + ": cannot read glTF: " + (err.empty() ? "unknown error" : err));
    }
    return GltfReader(path, model).all();
}

}  // namespace shadowlab
