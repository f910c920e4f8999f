// The `raytraced` reference (DESIGN.md section 3, reference 2): for every pixel, M shadow rays to
// stratified samples of the light, tested with Embree 3 against the exact triangles of the shadow
// casters. v(p) = sum of the weights of the unoccluded samples in front of p's tangent plane, the
// stratified estimate of the visibility integral (1/A) * integral over the light of V(p, l) dl
// (DESIGN.md section 5: a sample behind the plane is hidden by the receiver's own surface).
//
// Determinism: a pixel's samples depend only on its index (the seed is a hash of it) and its sum is
// taken in sample order, so the output is bit-identical whatever the number of threads and
// whichever thread takes which row.
#include "visibility/raytracer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "error.h"
#include "shared/shared.h"

namespace shadowlab {

static_assert(int(LightShape::Point) == shared::LIGHT_SHAPE_POINT);
static_assert(int(LightShape::Square) == shared::LIGHT_SHAPE_SQUARE);
static_assert(int(LightShape::Disk) == shared::LIGHT_SHAPE_DISK);
static_assert(int(LightShape::Sphere) == shared::LIGHT_SHAPE_SPHERE);

namespace {

// Ray origins move off the receiver, along its normal towards the light sample, by the rounding
// a G-buffer position can carry and no more: rays go only to samples in front of the receiver's
// tangent plane (the visibility convention, shaders/shared/tangent_plane.glsl), so the offset no
// longer has to step over anything, and a caster thinner than the offset lying on the receiver
// would be missed. A position is interpolated from vertices of the scene's size, so its rounding
// is a few float ulps of the scene's scale (2^-23 ~ 1.2e-7 of its bounding-box diagonal: 8 ulps
// here) ...
constexpr float kOffsetFractionOfScene = 1e-6f;
// ... or of the hit's own distance from the origin, whichever is larger (a receiver far from the
// origin compared with the scene's size): ~32 ulps of its largest coordinate. Both scale with the
// scene, so a scene scaled by 1e-3 or 1e4 traces the same shadows (HardCase tests at those scales).
constexpr float kOffsetRelativeToPosition = 4e-6f;
// Rays stop this fraction short of the light sample, so geometry lying in the light's own plane (an
// emitter quad, a lamp housing) does not occlude its own light.
constexpr float kTfarShrink = 1e-5f;

const char* embreeErrorName(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE: return "no error";
        case RTC_ERROR_UNKNOWN: return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
        case RTC_ERROR_CANCELLED: return "cancelled";
    }
    return "unknown error code";
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

float shadowRayOffset(float sceneDiagonal, const glm::vec3& p) {
    float scene = std::isfinite(sceneDiagonal) && sceneDiagonal > 0.0f ? kOffsetFractionOfScene * sceneDiagonal : 0.0f;
    return std::max(scene, kOffsetRelativeToPosition * std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
}

struct RayTracer::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    size_t triangles = 0;
    float sceneDiagonal = 0.0f;  // world units: shadowRayOffset's scale
    unsigned threads = 0;       // 0 = hardware_concurrency()

    // First Embree error message reported through the device callback.
    std::mutex errorMutex;
    std::string firstError;

    static void onError(void* user, RTCError code, const char* message) {
        auto* self = static_cast<Impl*>(user);
        std::lock_guard<std::mutex> lock(self->errorMutex);
        if (self->firstError.empty()) {
            self->firstError = std::string(embreeErrorName(code)) + (message ? std::string(": ") + message : "");
        }
    }

    void check(const char* what) {
        RTCError code = rtcGetDeviceError(device);
        std::lock_guard<std::mutex> lock(errorMutex);
        if (code != RTC_ERROR_NONE || !firstError.empty()) {
            std::string message = firstError.empty() ? embreeErrorName(code) : firstError;
            throw InternalError(std::string("Embree: ") + what + ": " + message);
        }
    }

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

RayTracer::RayTracer(const Scene& scene, double t) : impl_(std::make_unique<Impl>()) {
    Impl& im = *impl_;
    im.device = rtcNewDevice(nullptr);
    if (!im.device) {
        throw InternalError(std::string("Embree: cannot create a device: ") + embreeErrorName(rtcGetDeviceError(nullptr)));
    }
    rtcSetDeviceErrorFunction(im.device, &Impl::onError, &im);

    im.scene = rtcNewScene(im.device);
    im.check("rtcNewScene");
    // Robust (watertight) traversal: a ray through the shared edge of two triangles of a closed
    // mesh (the diagonal of the occluder plate's face) must not slip between them.
    rtcSetSceneFlags(im.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);

    for (const Object& object : scene.objects) {
        if (!object.castsShadows || object.mesh.triangleCount() == 0) continue;
        const Mesh& mesh = object.mesh;
        const glm::mat4 worldFromObject = object.worldFromObjectAt(t);
        for (uint32_t index : mesh.indices) {
            if (index >= mesh.positions.size()) {
                throw InternalError("RayTracer: object \"" + object.name + "\" has vertex index " + std::to_string(index) +
                                    " but " + std::to_string(mesh.positions.size()) + " positions");
            }
        }
        RTCGeometry geometry = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        im.check("rtcNewGeometry");
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                     3 * sizeof(float), mesh.positions.size()));
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(unsigned), mesh.triangleCount()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geometry);
            im.check("rtcSetNewGeometryBuffer");
            throw InternalError("Embree: rtcSetNewGeometryBuffer returned no buffer");
        }
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            glm::vec3 world = glm::vec3(worldFromObject * glm::vec4(mesh.positions[i], 1.0f));
            vertices[3 * i + 0] = world.x;
            vertices[3 * i + 1] = world.y;
            vertices[3 * i + 2] = world.z;
        }
        std::copy(mesh.indices.begin(), mesh.indices.begin() + 3 * mesh.triangleCount(), indices);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(im.scene, geometry);
        rtcReleaseGeometry(geometry);
        im.check("adding a triangle mesh");
        im.triangles += mesh.triangleCount();
    }
    rtcCommitScene(im.scene);
    im.check("building the BVH");

    Bounds bounds = scene.bounds(t);
    if (!bounds.empty()) {
        float diagonal = glm::length(bounds.hi - bounds.lo);
        if (std::isfinite(diagonal) && diagonal > 0.0f) im.sceneDiagonal = diagonal;
    }
}

RayTracer::~RayTracer() = default;

size_t RayTracer::triangleCount() const { return impl_->triangles; }

void RayTracer::setThreadCount(unsigned threads) { impl_->threads = threads; }

uint32_t spreadSampleOrder(uint32_t k, uint32_t n) {
    if (n <= 1) return 0;
    uint32_t stride = std::max(1u, uint32_t(double(n) * 0.6180339887));
    while (std::gcd(stride, n) != 1) ++stride;
    return uint32_t((uint64_t(k) * stride) % n);
}

void SampleSums::reset(int w, int h, uint32_t samples) {
    width = w;
    height = h;
    total = samples;
    traced = 0;
    const size_t n = size_t(w) * size_t(h);
    visible.assign(n, 0.0);
    weight.assign(n, 0.0);
    occluded.assign(n, 0u);
}

float SampleSums::value(size_t i) const {
    if (traced == 0) return 1.0f;
    // All samples agree: exactly 0 or 1, without the rounding of the summed weights.
    if (occluded[i] == 0) return 1.0f;
    if (occluded[i] >= traced) return 0.0f;
    if (complete()) return float(std::clamp(visible[i], 0.0, 1.0));
    return weight[i] > 0.0 ? float(std::clamp(visible[i] / weight[i], 0.0, 1.0)) : 1.0f;
}

Image SampleSums::image() const {
    Image out(width, height, 1, 1.0f);
    for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = value(i);
    return out;
}

Image RayTracer::visibility(const Image& positions, const Image& normals, const Light& light, int rays,
                            const std::function<void(size_t, size_t)>& progress) const {
    SampleSums sums;
    const uint32_t samples = light.isPoint() ? 1u : uint32_t(std::max(rays, 1));
    sums.reset(positions.width, positions.height, samples);
    traceSamples(positions, normals, light, rays, 0, samples, sums, false, nullptr, progress);
    return sums.image();
}

void RayTracer::traceSamples(const Image& positions, const Image& normals, const Light& light, int rays,
                             uint32_t first, uint32_t count, SampleSums& sums, bool spread,
                             const std::atomic<bool>* cancel, const std::function<void(size_t, size_t)>& progress) const {
    if (positions.channels < 3 || normals.channels < 3) {
        throw InternalError("RayTracer::visibility: positions and normals need 3+ channels, got " +
                            std::to_string(positions.channels) + " and " + std::to_string(normals.channels));
    }
    if (positions.width != normals.width || positions.height != normals.height) {
        throw InternalError("RayTracer::visibility: positions " + std::to_string(positions.width) + "x" +
                            std::to_string(positions.height) + " vs normals " + std::to_string(normals.width) + "x" +
                            std::to_string(normals.height));
    }
    if (rays < 1) {
        throw InputError("raytraced: rays must be at least 1, got " + std::to_string(rays));
    }

    const int width = positions.width;
    const int height = positions.height;
    const bool point = light.isPoint();
    const uint32_t samples = point ? 1u : uint32_t(rays);
    if (sums.width != width || sums.height != height || sums.total != samples) {
        throw InternalError("RayTracer::traceSamples: sums of " + std::to_string(sums.width) + "x" +
                            std::to_string(sums.height) + " with M = " + std::to_string(sums.total) + " for " +
                            std::to_string(width) + "x" + std::to_string(height) + " with M = " + std::to_string(samples));
    }
    if (first != sums.traced) {
        throw InternalError("RayTracer::traceSamples: batch from sample " + std::to_string(first) + " after " +
                            std::to_string(sums.traced) + " traced");
    }
    if (first >= samples) return;
    const uint32_t last = uint32_t(std::min<uint64_t>(uint64_t(first) + count, samples));
    const int shape = int(light.shape);
    const glm::vec3 centre = light.position;
    const glm::vec3 right = point ? glm::vec3(0.0f) : light.right();
    const glm::vec3 up = light.up;
    const float sceneDiagonal = impl_->sceneDiagonal;
    RTCScene scene = impl_->scene;

    // One pixel's samples [first, last): the weights of those no caster hides, added to its sums.
    auto shadePixel = [&](RTCIntersectContext& context, int x, int y) {
        const size_t index = size_t(y) * width + x;
        const glm::vec3 p(positions.at(x, y, 0), positions.at(x, y, 1), positions.at(x, y, 2));
        if (!finite3(p)) return;  // background (DESIGN.md section 6): no sample is hidden
        glm::vec3 n(normals.at(x, y, 0), normals.at(x, y, 1), normals.at(x, y, 2));
        const bool hasNormal = finite3(n) && glm::dot(n, n) > 0.0f;
        if (hasNormal) n = glm::normalize(n);
        const float offset = shadowRayOffset(sceneDiagonal, p);
        // The seed is a hash of the pixel index: noise is uncorrelated between pixels yet fixed.
        const uint32_t seed = shared::pcgHash(uint32_t(index));

        double visible = sums.visible[index], traced = sums.weight[index];
        uint32_t occluded = sums.occluded[index];
        for (uint32_t k = first; k < last; ++k) {
            const uint32_t i = spread ? spreadSampleOrder(k, samples) : k;
            glm::vec3 sample = centre;
            float weight = 1.0f;
            if (!point) {
                glm::vec3 uvw = shared::stratifiedSample(i, samples, seed);
                sample = shared::lightSamplePosition(centre, right, up, shape, light.size, glm::vec2(uvw.x, uvw.y));
                weight = uvw.z;
            }
            traced += weight;
            glm::vec3 toLight = sample - p;
            // The visibility convention: a sample behind the receiver's tangent plane is hidden by
            // the receiver's own surface; no ray is cast for it.
            if (hasNormal && !shared::inFrontOfTangentPlane(p, n, sample)) {
                ++occluded;
                continue;
            }
            // Offset the origin along the normal, to the side the sample is on, so the ray leaves
            // the receiver's own surface; without a normal, step towards the sample.
            glm::vec3 side = hasNormal ? n : glm::normalize(toLight);
            glm::vec3 origin = p + offset * side;
            glm::vec3 direction = sample - origin;
            float distance = glm::length(direction);
            if (!(distance > 0.0f) || !std::isfinite(distance)) {
                visible += weight;  // the receiver sits on the light sample: nothing in between
                continue;
            }
            direction /= distance;

            RTCRay ray{};
            ray.org_x = origin.x;
            ray.org_y = origin.y;
            ray.org_z = origin.z;
            ray.tnear = 0.0f;
            ray.dir_x = direction.x;
            ray.dir_y = direction.y;
            ray.dir_z = direction.z;
            ray.time = 0.0f;
            ray.tfar = distance * (1.0f - kTfarShrink);
            ray.mask = 0xFFFFFFFFu;
            ray.id = 0;
            ray.flags = 0;
            rtcOccluded1(scene, &context, &ray);
            if (ray.tfar == -std::numeric_limits<float>::infinity()) {
                ++occluded;
            } else {
                visible += weight;
            }
        }
        sums.visible[index] = visible;
        sums.weight[index] = traced;
        sums.occluded[index] = occluded;
    };

    const size_t total = size_t(width) * height;
    std::atomic<int> nextRow{0};
    std::atomic<size_t> donePixels{0};
    std::atomic<int> workersLeft{0};
    std::mutex mutex;
    std::condition_variable finished;
    std::exception_ptr failure;

    auto worker = [&]() {
        try {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            for (int y = nextRow++; y < height; y = nextRow++) {
                if (cancel && cancel->load(std::memory_order_relaxed)) {
                    nextRow = height;  // the batch is abandoned: the others stop too
                    break;
                }
                for (int x = 0; x < width; ++x) shadePixel(context, x, y);
                donePixels += size_t(width);
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex);
            if (!failure) failure = std::current_exception();
            nextRow = height;  // stop the others
        }
        {
            std::lock_guard<std::mutex> lock(mutex);
            --workersLeft;
        }
        finished.notify_all();
    };

    const unsigned requested = impl_->threads ? impl_->threads : std::thread::hardware_concurrency();
    const unsigned threadCount = std::max(1u, std::min(requested, unsigned(std::max(height, 1))));
    workersLeft = int(threadCount);
    std::vector<std::thread> threads;
    threads.reserve(threadCount);
    for (unsigned i = 0; i < threadCount; ++i) threads.emplace_back(worker);
    std::exception_ptr progressFailure;
    {
        // The caller's progress callback runs on the calling thread only. If it throws (a cancel
        // button), the workers are stopped and joined before the exception goes on.
        std::unique_lock<std::mutex> lock(mutex);
        while (workersLeft > 0) {
            finished.wait_for(lock, std::chrono::milliseconds(200));
            if (progress && workersLeft > 0 && !progressFailure) {
                size_t done = donePixels;
                lock.unlock();
                try {
                    progress(done, total);
                } catch (...) {
                    progressFailure = std::current_exception();
                    nextRow = height;
                }
                lock.lock();
            }
        }
    }
    for (std::thread& thread : threads) thread.join();
    if (progressFailure) std::rethrow_exception(progressFailure);
    if (failure) std::rethrow_exception(failure);
    RTCError code = rtcGetDeviceError(impl_->device);
    if (code != RTC_ERROR_NONE) {
        throw InternalError(std::string("Embree: tracing shadow rays: ") + embreeErrorName(code));
    }
    if (cancel && cancel->load()) return;  // partial: `traced` says the batch did not land
    sums.traced = last;
    if (progress) progress(total, total);
}

}  // namespace shadowlab
