// Resources declared by passes and owned by the pass graph's pool (Falcor's reflect(), Filament's
// frame-graph resources). A pass names each texture, pyramid, texture array, storage buffer or mesh
// it creates, with its format, a size rule and a one-line doc; the pool allocates it when the
// declaration first applies, reallocates it when its size rule resolves differently (sm_size
// changed, the window resized), frees it when it no longer applies, and reports its memory.
#pragma once
#include <glm/glm.hpp>
#include <deque>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gl/util.h"
#include "image/image.h"

namespace shadowlab {

enum class ResourceKind { Texture, Pyramid, TextureArray, StorageBuffer, Mesh };
const char* resourceKindName(ResourceKind kind);

// How big a resource is.
struct SizeRule {
    enum class Kind { Frame, ShadowMap, Fixed, Like };
    Kind kind = Kind::Frame;
    int width = 1, height = 1;  // Fixed
    std::string from;           // ShadowMap: the parameter holding the side ("sm_size"); Like: a resource
    int scaleDown = 1;          // Frame, Like: each side divided by this, rounded up

    static SizeRule frame(int scaleDown = 1) { return {Kind::Frame, 1, 1, "", scaleDown}; }
    static SizeRule shadowMap(const std::string& param = "sm_size") { return {Kind::ShadowMap, 1, 1, param, 1}; }
    static SizeRule fixed(int w, int h) { return {Kind::Fixed, w, h, "", 1}; }
    static SizeRule like(const std::string& resource, int scaleDown = 1) { return {Kind::Like, 1, 1, resource, scaleDown}; }
    std::string describe() const;
};

struct ResourceDesc {
    std::string name;
    ResourceKind kind = ResourceKind::Texture;
    Format format = Format::R32F;
    SizeRule size;
    int levels = 1;           // Pyramid: 0 = the full chain down to 1x1
    int layers = 1;           // TextureArray
    size_t elementBytes = 0;  // StorageBuffer: bytes per element; width x height x layers elements
    std::string doc;
    std::string appliesWhen;  // "" = always; a condition on the technique's parameters
    GLenum filter = GL_NEAREST;
    // StorageBuffer: an append list whose order is the GPU's (an atomic counter hands out the
    // slots), read by passes whose result does not depend on it; --check-reuse compares it as a
    // multiset of 32-bit words.
    bool unordered = false;
    // StorageBuffer: the creating pass's working memory, rewritten from scratch by every execution
    // (spsm's lists of undecided pixels): it does not keep refineFrame from running the pass in
    // bands, each band filling it anew; a reader (a counter) sees the last execution's.
    bool scratch = false;

    static ResourceDesc texture(const std::string& name, Format format, SizeRule size, const std::string& doc) {
        ResourceDesc d;
        d.name = name;
        d.format = format;
        d.size = size;
        d.doc = doc;
        return d;
    }
};

// The frame-size R32F visibility buffer every technique writes (DESIGN.md section 3).
ResourceDesc visibilityResource();

// A triangle mesh or line set with per-primitive attributes (wedges, penumbra volumes, silhouette
// edges, back-projected contour edges): CPU-side, written to PLY with its attributes.
struct MeshData {
    int verticesPerPrimitive = 3;  // 3: triangles; 2: lines
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;  // verticesPerPrimitive per primitive
    std::vector<std::pair<std::string, std::vector<float>>> primitiveAttributes;  // one value per primitive
    size_t primitiveCount() const { return verticesPerPrimitive ? indices.size() / size_t(verticesPerPrimitive) : 0; }
    size_t bytes() const;
};
// ASCII PLY (vertices, faces or edges, each attribute a property of the face/edge element).
std::string meshToPLY(const MeshData& mesh);

// One allocated resource.
struct Resource {
    ResourceDesc desc;
    int width = 0, height = 0;
    Texture texture;       // Texture, Pyramid, TextureArray
    GLuint buffer = 0;     // StorageBuffer
    size_t bufferBytes = 0;
    MeshData mesh;         // Mesh
    size_t bytes() const;
    int levels() const;
};

class ResourcePool {
public:
    ResourcePool() = default;
    ~ResourcePool();
    ResourcePool(const ResourcePool&) = delete;
    ResourcePool& operator=(const ResourcePool&) = delete;

    // Allocates `qualifiedName` ("L0/shadow_map") for a resolved size, reusing the existing object when
    // its declaration and size are unchanged. Returns the resource.
    Resource& ensure(const std::string& qualifiedName, const ResourceDesc& desc, int width, int height);
    Resource* find(const std::string& qualifiedName);
    const Resource* find(const std::string& qualifiedName) const;
    void release(const std::string& qualifiedName);
    // Frees every resource whose name is not in `keep`.
    void releaseAllBut(const std::vector<std::string>& keep);
    size_t totalBytes() const;  // the live resources (not the spares)
    // Keeps what a change of size replaces, up to `bytes` in all (the oldest dropped first), and
    // hands it back when its name, declaration and size are asked for again: the window's drag
    // renderer changes its divisor as the frames' cost moves, and allocating a frame-size float
    // texture costs ~20 ms on llvmpipe (a resize of the drag renderer, 40 ms at 512x304). 0, the
    // default: nothing kept.
    void setSpareBytes(size_t bytes);
    size_t spareBytes() const;  // what the spares hold now
    nlohmann::json describe() const;  // [{name, kind, format, size, levels, layers, bytes, doc}]
    const std::map<std::string, std::unique_ptr<Resource>>& all() const { return resources_; }

private:
    void trimSpares();
    std::map<std::string, std::unique_ptr<Resource>> resources_;
    std::deque<std::pair<std::string, std::unique_ptr<Resource>>> spares_;  // oldest first
    size_t spareLimit_ = 0;
};

}  // namespace shadowlab
