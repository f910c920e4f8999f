// glTF 2.0 (.gltf and .glb) meshes for "gltf" scene objects, read with tinygltf. Everything the
// file says is checked before it is used (indices, accessor ranges, the node tree, extensions,
// the triangle count against the scene limits): a user's file may be wrong, and a bad file must
// give an error naming it, never a crash, a hang or an exhausted machine. The node tree is walked
// with an explicit stack (a 10,000-deep chain is legal), and a node with two parents is refused
// as glTF 2.0 requires (it would otherwise make the walk exponential).
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "error.h"
#include "scene/input_file.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace shadowlab {

namespace {

// Images are irrelevant to shadows: accept and ignore them instead of decoding textures.
bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                 const unsigned char*, int, void*) {
    return true;
}

// File access for buffers and images: only regular files, read in full with a size check (the
// default callback reads a directory as a file of 2^63 bytes: std::bad_alloc), and paths taken as
// they are (the default expands them with wordexp, i.e. shell syntax, from an untrusted file).
bool fileExists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::exists(path, ec);
}

std::string expandPath(const std::string& path, void*) { return path; }

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    // The input gate (scene/input_file.h): a regular file under 2 GiB (beyond what a buffer's
    // byteLength can use), opened once; the reason goes after tinygltf's "File read error : <path> : ".
    try {
        *out = readInputBytes(path, "glTF buffer", kMaxGltfInputBytes);
        return true;
    } catch (const InputError& e) {
        const std::string message = e.what();
        const std::string head = path + ": cannot read the glTF buffer: ";
        if (err) *err += message.rfind(head, 0) == 0 ? message.substr(head.size()) : message;
        return false;
    }
}

bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "shadowlab does not write glTF files";
    return false;
}

// Extensions a file may require without changing its geometry (materials, textures, lights are
// irrelevant to shadows). Any other required extension (KHR_draco_mesh_compression,
// EXT_meshopt_compression, KHR_mesh_quantization, ...) is refused by name.
bool harmlessExtension(const std::string& name) {
    for (const char* prefix : {"KHR_materials_", "KHR_texture_", "EXT_texture_", "KHR_lights_punctual"}) {
        if (name.rfind(prefix, 0) == 0) return true;
    }
    return false;
}

std::string withCommas(uint64_t n) {
    std::string digits = std::to_string(n), out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
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
            const tinygltf::Primitive& prim = mesh.primitives[p];
            if (prim.extensions.count("KHR_draco_mesh_compression")) {
                // Draco is only used, not required: the primitive must carry uncompressed data too.
                try {
                    appendMesh(out, primitive(prim, what), worldFromMesh);
                } catch (const InputError& e) {
                    throw InputError(std::string(e.what()) +
                                     " (this primitive is Draco-compressed, KHR_draco_mesh_compression, which "
                                     "shadowlab does not support, and its uncompressed fallback is not usable)");
                }
                continue;
            }
            appendMesh(out, primitive(prim, what), worldFromMesh);
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

    // Checks the file before anything is built: required extensions, the node tree (every node
    // has at most one parent, scene roots have none, no node is a root twice) and the roots to walk.
    void checkExtensions() const {
        for (const std::string& name : model_.extensionsRequired) {
            if (harmlessExtension(name)) continue;
            fail("requires the extension " + name + ", which shadowlab does not support" +
                 (name == "KHR_draco_mesh_compression"
                      ? " (Draco-compressed meshes: re-export the model without compression)"
                      : ""));
        }
    }

    std::vector<int> roots() {
        const size_t n = model_.nodes.size();
        parent_.assign(n, -1);
        for (size_t i = 0; i < n; ++i) {
            for (int child : model_.nodes[i].children) {
                if (child < 0 || static_cast<size_t>(child) >= n) {
                    fail("nodes[" + std::to_string(i) + "].children: node " + std::to_string(child) +
                         " does not exist");
                }
                int& p = parent_[static_cast<size_t>(child)];
                if (p >= 0) {
                    // Also a child listed twice by the same node ("two parents" that are one node).
                    fail("nodes[" + std::to_string(child) + "] has two parents (nodes[" + std::to_string(p) +
                         "] and nodes[" + std::to_string(i) +
                         "]); glTF 2.0 allows one (a node tree, not a graph)");
                }
                p = static_cast<int>(i);
            }
        }
        std::vector<int> out;
        if (!model_.scenes.empty()) {
            // The default scene, or scene 0 when the file names none.
            const int scene = model_.defaultScene >= 0 && static_cast<size_t>(model_.defaultScene) <
                                                              model_.scenes.size()
                                  ? model_.defaultScene
                                  : 0;
            const std::string what = "scenes[" + std::to_string(scene) + "].nodes";
            std::set<int> seen;
            for (int root : model_.scenes[static_cast<size_t>(scene)].nodes) {
                if (root < 0 || static_cast<size_t>(root) >= n) {
                    fail(what + ": node " + std::to_string(root) + " does not exist");
                }
                if (!seen.insert(root).second) fail(what + ": nodes[" + std::to_string(root) + "] is listed twice");
                if (parent_[static_cast<size_t>(root)] >= 0) {
                    fail(what + ": nodes[" + std::to_string(root) + "] is a scene root but also a child of nodes[" +
                         std::to_string(parent_[static_cast<size_t>(root)]) + "]; glTF 2.0 roots have no parent");
                }
                out.push_back(root);
            }
        } else {
            // No scenes: every node that is nobody's child is a root.
            for (size_t i = 0; i < n; ++i) {
                if (parent_[i] < 0) out.push_back(static_cast<int>(i));
            }
        }
        // With one parent per node and parentless roots, a walk from the roots meets no cycle; a
        // cycle elsewhere (unreachable, every member with a parent) is reported all the same.
        std::vector<char> reached(n, 0);
        std::vector<int> stack(out.begin(), out.end());
        while (!stack.empty()) {
            const int i = stack.back();
            stack.pop_back();
            reached[static_cast<size_t>(i)] = 1;
            for (int child : model_.nodes[static_cast<size_t>(i)].children) stack.push_back(child);
        }
        // Unreached nodes: follow each parent chain once (0 unvisited, 1 on the chain being
        // followed, 2 done); meeting the current chain again is a cycle. O(number of nodes).
        std::vector<char> state(n, 0);
        std::vector<size_t> chainOf(n, 0);
        for (size_t i = 0; i < n; ++i) {
            if (reached[i] || state[i] != 0) continue;
            int p = static_cast<int>(i);
            std::vector<int> chain;
            while (p >= 0 && state[static_cast<size_t>(p)] == 0) {
                state[static_cast<size_t>(p)] = 1;
                chainOf[static_cast<size_t>(p)] = i;
                chain.push_back(p);
                p = parent_[static_cast<size_t>(p)];
            }
            if (p >= 0 && state[static_cast<size_t>(p)] == 1 && chainOf[static_cast<size_t>(p)] == i) {
                fail("nodes[" + std::to_string(p) + "] is its own ancestor (cycle in the node tree)");
            }
            for (int c : chain) state[static_cast<size_t>(c)] = 2;
        }
        return out;
    }

    // Triangles of one instance of mesh `meshIndex`, from the accessor counts (nothing is read).
    uint64_t meshTriangles(int meshIndex) {
        if (meshIndex < 0 || static_cast<size_t>(meshIndex) >= model_.meshes.size()) {
            fail("mesh " + std::to_string(meshIndex) + " does not exist");
        }
        if (meshTriangles_.empty()) meshTriangles_.assign(model_.meshes.size(), -1);
        int64_t& cached = meshTriangles_[static_cast<size_t>(meshIndex)];
        if (cached >= 0) return static_cast<uint64_t>(cached);
        uint64_t total = 0;
        for (const tinygltf::Primitive& primitive : model_.meshes[static_cast<size_t>(meshIndex)].primitives) {
            int accessor = primitive.indices;
            if (accessor < 0) {
                const auto position = primitive.attributes.find("POSITION");
                accessor = position == primitive.attributes.end() ? -1 : position->second;
            }
            if (accessor >= 0 && static_cast<size_t>(accessor) < model_.accessors.size()) {
                total += model_.accessors[static_cast<size_t>(accessor)].count / 3;
            }
        }
        cached = static_cast<int64_t>(total);
        return total;
    }

    // Visits every node reachable from `roots` with its world transform, depth first, without
    // recursion. visit(nodeIndex, node, worldFromNode).
    template <class Visit>
    void walk(const std::vector<int>& roots, bool transforms, Visit visit) const {
        struct Item {
            int node;
            glm::mat4 worldFromParent;
        };
        std::vector<Item> stack;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::mat4(1.0f)});
        while (!stack.empty()) {
            const Item item = stack.back();
            stack.pop_back();
            const tinygltf::Node& node = model_.nodes[static_cast<size_t>(item.node)];
            const glm::mat4 worldFromNode =
                transforms ? item.worldFromParent * localTransform(node, item.node) : glm::mat4(1.0f);
            visit(item.node, node, worldFromNode);
            for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, worldFromNode});
        }
    }

    uint64_t triangles() {
        checkExtensions();
        const std::vector<int> rootNodes = roots();
        uint64_t total = 0;
        if (model_.nodes.empty()) {
            for (size_t m = 0; m < model_.meshes.size(); ++m) total += meshTriangles(static_cast<int>(m));
        }
        walk(rootNodes, false, [&](int, const tinygltf::Node& node, const glm::mat4&) {
            if (node.mesh >= 0) total += meshTriangles(node.mesh);
        });
        return total;
    }

    Mesh all(const SceneLimits& limits, std::vector<std::string>* warnings) {
        const uint64_t needed = triangles();
        if (needed > limits.maxTriangles) {
            fail("would need " + std::to_string(needed) + " triangles (" + withCommas(needed) + ", about " +
                 describeBytes(double(needed) * double(kBytesPerTriangle)) + " of memory), over the limit of " +
                 std::to_string(limits.maxTriangles) + " triangles (--max-triangles N raises it)");
        }
        Mesh out;
        const std::vector<int> rootNodes = roots();
        if (model_.nodes.empty()) {
            // No nodes at all: take every mesh as it is.
            for (size_t m = 0; m < model_.meshes.size(); ++m) {
                addMesh(out, static_cast<int>(m), glm::mat4(1.0f));
            }
        }
        size_t skinned = 0, morphed = 0;
        int firstSkinned = -1, firstMorphed = -1;
        walk(rootNodes, true, [&](int index, const tinygltf::Node& node, const glm::mat4& worldFromNode) {
            if (node.mesh < 0) return;
            if (node.skin >= 0 && skinned++ == 0) firstSkinned = index;
            const tinygltf::Mesh& mesh = model_.meshes.at(static_cast<size_t>(node.mesh));
            const bool hasTargets = std::any_of(mesh.primitives.begin(), mesh.primitives.end(),
                                                [](const tinygltf::Primitive& p) { return !p.targets.empty(); });
            if (hasTargets && morphed++ == 0) firstMorphed = node.mesh;
            addMesh(out, node.mesh, worldFromNode);
        });
        if (warnings && skinned > 0) {
            warnings->push_back(path_ + ": nodes[" + std::to_string(firstSkinned) + "]" +
                                (skinned > 1 ? " and " + std::to_string(skinned - 1) + " other node(s) have" : " has") +
                                " a skin; skinning is not supported, so the mesh is drawn in its rest pose");
        }
        if (warnings && morphed > 0) {
            warnings->push_back(path_ + ": meshes[" + std::to_string(firstMorphed) + "]" +
                                (morphed > 1 ? " and " + std::to_string(morphed - 1) + " other instance(s) have" : " has") +
                                " morph targets; morphing is not supported, so the mesh is drawn in its rest pose");
        }
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
    std::vector<int> parent_;
    std::vector<int64_t> meshTriangles_;
};

}  // namespace

namespace {

// Parses the file with tinygltf (no images decoded, only regular files read). InputError naming
// the file on failure.
void parseGltf(const std::string& path, tinygltf::Model& model) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(path, ec))) {
        // The real-mesh test set is fetched, not shipped: say what makes it.
        const bool realMesh = fs::path(path).lexically_normal().parent_path().filename() == "real" &&
                              fs::path(path).lexically_normal().parent_path().parent_path().filename() == "models";
        throw InputError(path + ": no such glTF file" +
                         (realMesh ? std::string(" (the real-mesh test set: scripts/fetch-meshes.sh makes it, "
                                                 "assets/models/README.md)")
                                   : std::string()));
    }
    std::string extension = fs::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension != ".gltf" && extension != ".glb") {
        throw InputError(path + ": expected a .gltf or .glb file, got extension '" + extension +
                         "'");
    }
    // The input gate: a regular file under 2 GiB, opened once, read whole; tinygltf parses the bytes.
    const std::vector<unsigned char> bytes = readInputBytes(path, "glTF file", kMaxGltfInputBytes);
    if (bytes.empty()) throw InputError(path + ": cannot read glTF: Empty file.");
    const std::string baseDir = fs::path(path).parent_path().string();

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(ignoreImage, nullptr);
    loader.SetFsCallbacks(tinygltf::FsCallbacks{fileExists, expandPath, readWholeFile, writeWholeFile, nullptr});
    std::string err, warn;
    bool ok = false;
    try {
        ok = extension == ".glb"
                 ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), baseDir)
                 : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                              unsigned(bytes.size()), baseDir);
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
}

}  // namespace

std::string describeBytes(double bytes) {
    char text[64];
    if (bytes >= 1e9) std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
    else if (bytes >= 1e6) std::snprintf(text, sizeof text, "%.0f MB", bytes / 1e6);
    else std::snprintf(text, sizeof text, "%.0f KB", bytes / 1e3);
    return text;
}

uint64_t estimateGltfTriangles(const std::string& path) {
    tinygltf::Model model;
    parseGltf(path, model);
    return GltfReader(path, model).triangles();
}

Mesh loadGltfMesh(const std::string& path, const SceneLimits& limits, std::vector<std::string>* warnings) {
    tinygltf::Model model;
    parseGltf(path, model);
    return GltfReader(path, model).all(limits, warnings);
}

}  // namespace shadowlab
