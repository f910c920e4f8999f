// The `raytraced` reference (DESIGN.md section 3, reference 2): visibility by casting M stratified
// rays per pixel to the light with Embree against the real triangles of the shadow casters,
// independent of any shadow-map resolution.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "image/image.h"
#include "scene/scene.h"

namespace shadowlab {

// How far a shadow ray's origin moves off a receiver at p along its normal, in a scene whose
// bounding box has diagonal `sceneDiagonal` (raytracer.cpp says why): the larger of a few ulps of
// the scene's scale and of p's own coordinates. The scene3d view traces its rays with it too.
float shadowRayOffset(float sceneDiagonal, const glm::vec3& p);

// The order a progressive estimate takes M samples in: k -> (k * stride) mod M, the stride coprime to
// M near M / golden ratio, so any prefix spreads over the whole light (the strata are numbered row
// by row: in index order the first samples all sit on one edge). The complete set is all M. The
// window's progressive reference and its progressive ray tracer both take this order.
uint32_t spreadSampleOrder(uint32_t k, uint32_t n);

// The running sums of each pixel's light samples: RayTracer::traceSamples adds a batch of samples
// to them (the window's progressive ray tracer); visibility() is one batch of all M.
struct SampleSums {
    int width = 0, height = 0;
    uint32_t total = 0;    // the samples a complete estimate sums (M; 1 for a point light)
    uint32_t traced = 0;   // the samples added to every pixel so far
    std::vector<double> visible;     // per pixel: the summed weights of the unoccluded samples
    std::vector<double> weight;      // per pixel: the summed weights of the samples traced
    std::vector<uint32_t> occluded;  // per pixel: the samples hidden (by a caster or the tangent plane)
    void reset(int w, int h, uint32_t samples);
    bool complete() const { return total > 0 && traced >= total; }
    // Pixel i's visibility: complete, the stratified sum (exactly 0 or 1 when every sample agrees,
    // as visibility() returns); partial, the unoccluded share of the weight traced so far.
    float value(size_t i) const;
    Image image() const;  // 1 channel, row 0 at the top
};

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

    // Adds samples [first, first + count) of the M per pixel to `sums` (reset to the image's size
    // and M first, or a batch after the last one; samples past M are ignored): sample k is the
    // stratum `spread ? spreadSampleOrder(k, M) : k` of shared::stratifiedSample. Stops early,
    // leaving `sums` partial and `traced` unchanged, once `cancel` is set. The same rays and
    // weights as visibility(): after the batches cover all M, sums.image() equals it (up to the
    // order the doubles were added in, when spread).
    void traceSamples(const Image& positions, const Image& normals, const Light& light, int rays, uint32_t first,
                      uint32_t count, SampleSums& sums, bool spread, const std::atomic<bool>* cancel = nullptr,
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
