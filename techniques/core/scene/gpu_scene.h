// The scene's meshes on the GPU: uploaded once; draw() binds each object's transform at time t.
#pragma once
#include <vector>

#include "gl/util.h"
#include "scene/scene.h"

namespace shadowlab {

class GpuScene {
public:
    explicit GpuScene(const Scene& scene);
    ~GpuScene();
    GpuScene(const GpuScene&) = delete;
    GpuScene& operator=(const GpuScene&) = delete;
    // Sets uniforms worldFromObject, albedo, objectId, receivesShadows on `program` per object
    // (those the program declares).
    void draw(const ShaderProgram& program, double t, bool castersOnly) const;
    size_t bytes() const { return bytes_; }

private:
    const Scene& scene_;
    struct GpuMesh {
        GLuint vao = 0, vbo = 0, ebo = 0;
        GLsizei indexCount = 0;
    };
    std::vector<GpuMesh> meshes_;
    size_t bytes_ = 0;
};

}  // namespace shadowlab
