#include "graph/resources.h"

#include <algorithm>
#include <sstream>

#include "error.h"

namespace shadowlab {

const char* resourceKindName(ResourceKind kind) {
    switch (kind) {
        case ResourceKind::Texture: return "texture";
        case ResourceKind::Pyramid: return "pyramid";
        case ResourceKind::TextureArray: return "texture array";
        case ResourceKind::StorageBuffer: return "storage buffer";
        case ResourceKind::Mesh: return "mesh";
    }
    return "?";
}

std::string SizeRule::describe() const {
    std::string scale = scaleDown > 1 ? " / " + std::to_string(scaleDown) : "";
    switch (kind) {
        case Kind::Frame: return "frame size" + scale;
        case Kind::ShadowMap: return from + " x " + from;
        case Kind::Fixed: return std::to_string(width) + "x" + std::to_string(height);
        case Kind::Like: return "size of " + from + scale;
    }
    return "?";
}

ResourceDesc visibilityResource() {
    return ResourceDesc::texture("visibility", Format::R32F, SizeRule::frame(),
                                 "this light's visibility v in [0,1] per pixel");
}

size_t MeshData::bytes() const {
    size_t b = positions.size() * sizeof(glm::vec3) + indices.size() * sizeof(uint32_t);
    for (const auto& [name, values] : primitiveAttributes) b += values.size() * sizeof(float);
    return b;
}

std::string meshToPLY(const MeshData& mesh) {
    std::ostringstream out;
    size_t primitives = mesh.primitiveCount();
    const char* element = mesh.verticesPerPrimitive == 2 ? "edge" : "face";
    out << "ply\nformat ascii 1.0\ncomment shadowlab internal\n";
    out << "element vertex " << mesh.positions.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
    out << "element " << element << " " << primitives << "\n";
    if (mesh.verticesPerPrimitive == 2)
        out << "property int vertex1\nproperty int vertex2\n";
    else
        out << "property list uchar int vertex_indices\n";
    for (const auto& [name, values] : mesh.primitiveAttributes) {
        if (values.size() != primitives)
            throw InternalError("mesh attribute '" + name + "' has " + std::to_string(values.size()) + " values for " +
                                std::to_string(primitives) + " primitives");
        out << "property float " << name << "\n";
    }
    out << "end_header\n";
    out.precision(9);
    for (const glm::vec3& p : mesh.positions) out << p.x << " " << p.y << " " << p.z << "\n";
    for (size_t i = 0; i < primitives; ++i) {
        if (mesh.verticesPerPrimitive != 2) out << mesh.verticesPerPrimitive << " ";
        for (int k = 0; k < mesh.verticesPerPrimitive; ++k)
            out << mesh.indices[i * size_t(mesh.verticesPerPrimitive) + size_t(k)] << (k + 1 < mesh.verticesPerPrimitive ? " " : "");
        for (const auto& [name, values] : mesh.primitiveAttributes) out << " " << values[i];
        out << "\n";
    }
    return out.str();
}

size_t Resource::bytes() const {
    switch (desc.kind) {
        case ResourceKind::StorageBuffer: return bufferBytes;
        case ResourceKind::Mesh: return mesh.bytes();
        default: return texture ? texture.bytes() : 0;
    }
}

int Resource::levels() const { return desc.kind == ResourceKind::Pyramid ? texture.levels() : 1; }

ResourcePool::~ResourcePool() {
    for (auto& [name, r] : resources_)
        if (r->buffer) glDeleteBuffers(1, &r->buffer);
    for (auto& [name, r] : spares_)
        if (r->buffer) glDeleteBuffers(1, &r->buffer);
}

void ResourcePool::setSpareBytes(size_t bytes) {
    spareLimit_ = bytes;
    trimSpares();
}

size_t ResourcePool::spareBytes() const {
    size_t total = 0;
    for (const auto& [name, r] : spares_) total += r->bytes();
    return total;
}

void ResourcePool::trimSpares() {
    size_t total = spareBytes();
    while (!spares_.empty() && total > spareLimit_) {
        total -= spares_.front().second->bytes();
        if (spares_.front().second->buffer) glDeleteBuffers(1, &spares_.front().second->buffer);
        spares_.pop_front();
    }
}

static bool sameDeclaration(const ResourceDesc& a, const ResourceDesc& b) {
    return a.kind == b.kind && a.format == b.format && a.levels == b.levels && a.layers == b.layers &&
           a.elementBytes == b.elementBytes && a.filter == b.filter;
}

Resource& ResourcePool::ensure(const std::string& qualifiedName, const ResourceDesc& desc, int width, int height) {
    auto it = resources_.find(qualifiedName);
    if (it != resources_.end() && sameDeclaration(it->second->desc, desc) && it->second->width == width &&
        it->second->height == height)
        return *it->second;
    if (width < 1 || height < 1)
        throw InternalError("resource " + qualifiedName + ": size " + std::to_string(width) + "x" +
                            std::to_string(height) + " from rule '" + desc.size.describe() + "'");
    if (spareLimit_ > 0 && it != resources_.end() && it->second->desc.kind != ResourceKind::Mesh &&
        sameDeclaration(it->second->desc, desc)) {
        spares_.emplace_back(qualifiedName, std::move(it->second));  // another size: kept for a return to it
        resources_.erase(it);
        trimSpares();
    } else {
        release(qualifiedName);
    }
    for (auto s = spares_.begin(); s != spares_.end(); ++s)
        if (s->first == qualifiedName && sameDeclaration(s->second->desc, desc) && s->second->width == width &&
            s->second->height == height) {
            std::unique_ptr<Resource> back = std::move(s->second);
            spares_.erase(s);
            back->desc = desc;
            Resource& ref = *back;
            resources_[qualifiedName] = std::move(back);
            return ref;
        }
    auto r = std::make_unique<Resource>();
    r->desc = desc;
    r->width = width;
    r->height = height;
    switch (desc.kind) {
        case ResourceKind::Texture:
            r->texture = Texture::create2D(width, height, desc.format, 1, desc.filter);
            break;
        case ResourceKind::Pyramid:
            r->texture = Texture::create2D(width, height, desc.format, desc.levels, desc.filter);
            break;
        case ResourceKind::TextureArray:
            r->texture = Texture::createArray(width, height, std::max(desc.layers, 1), desc.format, std::max(desc.levels, 1));
            break;
        case ResourceKind::StorageBuffer: {
            r->bufferBytes = std::max<size_t>(desc.elementBytes * size_t(width) * size_t(height) * size_t(std::max(desc.layers, 1)), 4);
            glCreateBuffers(1, &r->buffer);
            glNamedBufferStorage(r->buffer, GLsizeiptr(r->bufferBytes), nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
            break;
        }
        case ResourceKind::Mesh:
            break;
    }
    Resource& ref = *r;
    resources_[qualifiedName] = std::move(r);
    return ref;
}

Resource* ResourcePool::find(const std::string& qualifiedName) {
    auto it = resources_.find(qualifiedName);
    return it == resources_.end() ? nullptr : it->second.get();
}
const Resource* ResourcePool::find(const std::string& qualifiedName) const {
    auto it = resources_.find(qualifiedName);
    return it == resources_.end() ? nullptr : it->second.get();
}

void ResourcePool::release(const std::string& qualifiedName) {
    auto it = resources_.find(qualifiedName);
    if (it == resources_.end()) return;
    if (it->second->buffer) glDeleteBuffers(1, &it->second->buffer);
    resources_.erase(it);
}

void ResourcePool::releaseAllBut(const std::vector<std::string>& keep) {
    std::vector<std::string> drop;
    for (const auto& [name, r] : resources_)
        if (std::find(keep.begin(), keep.end(), name) == keep.end()) drop.push_back(name);
    for (const std::string& name : drop) release(name);
}

size_t ResourcePool::totalBytes() const {
    size_t total = 0;
    for (const auto& [name, r] : resources_) total += r->bytes();
    return total;
}

nlohmann::json ResourcePool::describe() const {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& [name, r] : resources_) {
        nlohmann::json j{{"name", name},
                         {"kind", resourceKindName(r->desc.kind)},
                         {"size_rule", r->desc.size.describe()},
                         {"width", r->width},
                         {"height", r->height},
                         {"bytes", r->bytes()},
                         {"doc", r->desc.doc}};
        if (r->desc.kind != ResourceKind::Mesh && r->desc.kind != ResourceKind::StorageBuffer)
            j["format"] = formatName(r->desc.format);
        if (r->desc.kind == ResourceKind::Pyramid) j["levels"] = r->levels();
        if (r->desc.kind == ResourceKind::TextureArray) j["layers"] = r->desc.layers;
        if (r->desc.kind == ResourceKind::Mesh) j["primitives"] = r->mesh.primitiveCount();
        out.push_back(j);
    }
    return out;
}

}  // namespace shadowlab
