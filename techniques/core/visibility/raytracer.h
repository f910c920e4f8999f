// The `raytraced` reference (DESIGN.md section 3, reference 2): visibility by casting M stratified
// rays per pixel to the light with Embree against the real triangles of the shadow casters,
// independent of any shadow-map resolution.
#pragma once
#include <functional>
#include <memory>

#include "image/image.h"
#include "scene/scene.h"

namespace shadowlab {

// How far a shadow ray's origin moves off a receiver at p along its normal, in a scene whose
// bounding box has diagonal `sceneDiagonal` (raytracer.cpp says why): the larger of a few ulps of
// the scene's scale and of p's own coordinates. The scene3d view traces its rays with it too.
float shadowRayOffset(float sceneDiagonal, const glm::vec3& p);

class RayTracer {
public:
    // Builds an Embree scene of the world-space triangles of every object that casts shadows, at
    // time t.
    RayTracer(const Scene& scene, double t);
    ~RayTracer();
    RayTracer(const RayTracer&) = delete;
    RayTracer& operator=(const RayTracer&) = delete;

    // Visibility in [0,1] of `light` at every pixel of `positions` (3+ channels, world position;
    // NaN = background, visibility 1), with `normals` (3+ channels, unit world normal): a sample
    // behind the receiver's tangent plane is occluded without a ray (the visibility convention,
    // shaders/shared/tangent_plane.glsl), and ray origins move off the surface along the normal by
    // shadowRayOffset. `rays` = M stratified samples of the light per pixel
    // (shaders/shared/light_sampling.glsl, seeded per pixel); a point light uses one ray at its
    // centre whatever M. progress(done, total) is called now and then when set.
    Image visibility(const Image& positions, const Image& normals, const Light& light, int rays,
                     const std::function<void(size_t, size_t)>& progress = {}) const;

    size_t triangleCount() const;

    // Worker threads for visibility(): 0 (the default) = std::thread::hardware_concurrency().
    // The result is bit-identical for every count; benchmarks fix it to compare timings.
    void setThreadCount(unsigned threads);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace shadowlab
