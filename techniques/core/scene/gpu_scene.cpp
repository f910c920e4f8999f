#include "scene/gpu_scene.h"

#include <algorithm>

namespace shadowlab {

// ---- GPU scene --------------------------------------------------------------------------------------
GpuScene::GpuScene(const Scene& scene) : scene_(scene) {
    for (const Object& object : scene.objects) {
        GpuMesh m;
        std::vector<float> interleaved;
        interleaved.reserve(object.mesh.positions.size() * 6);
        for (size_t i = 0; i < object.mesh.positions.size(); ++i) {
            const glm::vec3& p = object.mesh.positions[i];
            glm::vec3 n = i < object.mesh.normals.size() ? object.mesh.normals[i] : glm::vec3(0, 1, 0);
            interleaved.insert(interleaved.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
        }
        glCreateVertexArrays(1, &m.vao);
        glCreateBuffers(1, &m.vbo);
        glCreateBuffers(1, &m.ebo);
        glNamedBufferStorage(m.vbo, GLsizeiptr(std::max<size_t>(interleaved.size(), 1) * sizeof(float)),
                             interleaved.empty() ? nullptr : interleaved.data(), 0);
        glNamedBufferStorage(m.ebo, GLsizeiptr(std::max<size_t>(object.mesh.indices.size(), 1) * sizeof(uint32_t)),
                             object.mesh.indices.empty() ? nullptr : object.mesh.indices.data(), 0);
        glVertexArrayVertexBuffer(m.vao, 0, m.vbo, 0, 6 * sizeof(float));
        glVertexArrayElementBuffer(m.vao, m.ebo);
        glEnableVertexArrayAttrib(m.vao, 0);
        glEnableVertexArrayAttrib(m.vao, 1);
        glVertexArrayAttribFormat(m.vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribFormat(m.vao, 1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
        glVertexArrayAttribBinding(m.vao, 0, 0);
        glVertexArrayAttribBinding(m.vao, 1, 0);
        m.indexCount = GLsizei(object.mesh.indices.size());
        bytes_ += interleaved.size() * sizeof(float) + object.mesh.indices.size() * sizeof(uint32_t);
        meshes_.push_back(m);
    }
}

GpuScene::~GpuScene() {
    for (GpuMesh& m : meshes_) {
        glDeleteVertexArrays(1, &m.vao);
        glDeleteBuffers(1, &m.vbo);
        glDeleteBuffers(1, &m.ebo);
    }
}

void GpuScene::draw(const ShaderProgram& program, double t, bool castersOnly) const {
    program.use();
    for (size_t i = 0; i < scene_.objects.size(); ++i) {
        const Object& object = scene_.objects[i];
        if (castersOnly && !object.castsShadows) continue;
        if (meshes_[i].indexCount == 0) continue;
        program.set("worldFromObject", object.worldFromObjectAt(t));
        // The material uniforms only where the program declares them (not the shadow-depth program).
        if (program.declares("albedo")) program.set("albedo", object.albedo);
        if (program.declares("objectId")) program.set("objectId", float(object.id));
        if (program.declares("receivesShadows")) program.set("receivesShadows", object.receivesShadows ? 1.0f : 0.0f);
        glBindVertexArray(meshes_[i].vao);
        glDrawElements(GL_TRIANGLES, meshes_[i].indexCount, GL_UNSIGNED_INT, nullptr);
    }
    glBindVertexArray(0);
}

}  // namespace shadowlab
