// `raytraced` in the window: the technique's M stratified rays per pixel (RayTracer, the same rays,
// seeds and weights as `render --technique raytraced`), traced on a worker thread in batches of rays
// per pixel, so the UI keeps its rate while the estimate sharpens (issue 18, item 4).
//
//   GL thread                                   worker thread
//   restart: G-buffer (slices of the budget),
//            positions and normals read back -> builds the BVH (or reuses it: same scene, time)
//                                              batch: samples [k, k + n) of every pixel and light,
//                                                     in spreadSampleOrder (any prefix covers the
//                                                     light), added to SampleSums
//   a finished batch: every light's estimate <- publishes each light's estimate
//   uploaded, shaded by Renderer::shadeWith
//   in bands of rows (slices of the budget)
//
// The first batch is one ray per pixel (a picture at once), the next ones sized to ~0.2 s of the
// worker's time. Complete, each light's estimate is SampleSums::image() over all M, which equals
// RayTracer::visibility up to the order its doubles were added in. The worker traces with one
// thread at nice 10: the machine has two cores and the GL thread renders the UI on the other.
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "gl/loader.h"

#include "error.h"
#include "visibility/raytracer.h"
#include "window/window.h"

namespace shadowlab {

namespace {

constexpr double kBatchMs = 200.0;  // the worker's time per batch after the first (one ray per pixel)

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

uint32_t samplesOf(const Light& light, int rays) { return light.isPoint() ? 1u : uint32_t(std::max(rays, 1)); }

}  // namespace

struct ProgressiveRaytrace::Job {
    // Inputs, fixed before the worker starts.
    const Scene* scene = nullptr;
    double time = 0.0;
    std::vector<Light> lights;
    int rays = 1;
    int width = 0, height = 0;
    std::unique_ptr<float[]> rawPositions, rawNormals;  // the G-buffer's RGBA32F rows, GL's order (bottom first)
    Image positions, normals;                     // made from them by the worker
    std::shared_ptr<const RayTracer> tracer;  // the last job's, when the scene and time are the same
    // The worker's output, under `mutex`.
    std::atomic<bool> cancel{false}, finished{false};
    std::mutex mutex;
    std::vector<Image> estimate;  // per light (empty: casts no shadow)
    int traced = 0;               // rays per pixel in `estimate`
    uint64_t published = 0;       // batches published
    double batchMs = 0.0;
    std::string error;
    std::shared_ptr<const RayTracer> built;  // the BVH the worker traced against
};

namespace {

void runJob(const std::shared_ptr<ProgressiveRaytrace::Job>& jobPointer);

}  // namespace

ProgressiveRaytrace::ProgressiveRaytrace() = default;

ProgressiveRaytrace::~ProgressiveRaytrace() { cancel(); }

void ProgressiveRaytrace::stopWorker(bool wait) {
    if (job_) job_->cancel = true;
    if (worker_.joinable()) retired_.emplace_back(job_, std::move(worker_));
    job_.reset();
    // A worker stops at its next row; one still building a BVH finishes that first. Join the
    // finished ones, and all of them when the scene they read is about to go (`wait`).
    for (auto it = retired_.begin(); it != retired_.end();) {
        if (wait || it->first->finished) {
            it->second.join();
            it = retired_.erase(it);
        } else {
            ++it;
        }
    }
}

void ProgressiveRaytrace::cancel() {
    stopWorker(true);
    renderer_.reset();
    tracer_.reset();
    scene_ = nullptr;
    shown_ = total_ = 0;
    started_ = false;
    readRows_ = 0;
    shadeRows_ = 0;
    live_ = false;
    restarted();
}

void ProgressiveRaytrace::pause() {
    if (!live_) return;
    stopWorker(false);
    restarted();
    shown_ = 0;
    started_ = false;
    readRows_ = 0;
    shadeRows_ = 0;
    live_ = false;
}

void ProgressiveRaytrace::resizeRenderer(int width, int height) {
    if (!renderer_ || live_ || (renderer_->width() == width && renderer_->height() == height)) return;
    renderer_->resize(width, height);
}

bool ProgressiveRaytrace::matches(const Scene& scene, const Camera& camera, const std::vector<Light>& lights, int width,
                                  int height, double time, int rays) const {
    bool same = renderer_ && live_ && scene_ == &scene && sameCamera(camera, camera_) && width == width_ && height == height_ &&
                time == time_ && rays == rays_ && lights.size() == lights_.size();
    for (size_t i = 0; same && i < lights.size(); ++i) same = sameLight(lights[i], lights_[i]);
    return same;
}

void ProgressiveRaytrace::pauseIfStale(const Scene& scene, const Camera& camera, const std::vector<Light>& lights,
                                       int width, int height, double time, int rays) {
    if (live_ && !matches(scene, camera, lights, width, height, time, rays)) pause();
}

void ProgressiveRaytrace::sync(const Scene& scene, const Camera& camera, const std::vector<Light>& lights, int width,
                               int height, double time, int rays) {
    if (matches(scene, camera, lights, width, height, time, rays)) return;
    if (rays < 1) throw InputError("raytraced: rays must be at least 1, got " + std::to_string(rays));
    if (scene_ != &scene) cancel();  // joins every worker reading the old scene
    stopWorker(false);
    restarted();
    if (!renderer_) {
        RenderOptions options;
        options.width = width;
        options.height = height;
        options.spareBytes = kSpareBytes;
        options.technique = "hard";  // only its G-buffer and shading run (shadeWith)
        options.cpuClock = true;
        renderer_ = std::make_unique<Renderer>(scene, options);
    }
    if (renderer_->width() != width || renderer_->height() != height) renderer_->resize(width, height);
    renderer_->setCamera(camera);
    for (size_t i = 0; i < lights.size(); ++i) renderer_->setLight(i, lights[i]);
    if (scene_ != &scene || time != time_) tracer_.reset();
    scene_ = &scene;
    camera_ = camera;
    lights_ = lights;
    width_ = width;
    height_ = height;
    time_ = time;
    rays_ = rays;
    total_ = 1;
    for (const Light& l : lights)
        if (l.castsShadows) total_ = std::max(total_, int(samplesOf(l, rays)));
    shown_ = 0;
    started_ = false;
    readRows_ = 0;
    shadeRows_ = 0;
    live_ = true;
}

int ProgressiveRaytrace::step(double budgetMs) {
    if (!active() || complete()) return 0;
    const int frame = int(time_ * 30.0 + 0.5);  // t = frame / 30, as the reference
    if (!started_) {
        // The G-buffer in slices, then its positions and normals read back in bands of rows (a
        // whole read-back of two float images cost ~0.2 s on llvmpipe at 774x557), each call
        // within the budget; the worker starts once every row is in.
        const auto t0 = std::chrono::steady_clock::now();
        if (readRows_ == 0 && renderer_->refineFrame(frame, {"gbuffer"}, std::max(0.5, budgetMs)) < 1.0) return 0;
        const Texture& position = renderer_->pool().find("frame/gbuffer.position")->texture;
        const Texture& normal = renderer_->pool().find("frame/gbuffer.normal")->texture;
        const size_t rowFloats = size_t(width_) * 4;
        if (readRows_ == 0) {  // uninitialised: the pages are first touched by the bands' reads
            rawPositions_.reset(new float[rowFloats * size_t(height_)]);
            rawNormals_.reset(new float[rowFloats * size_t(height_)]);
        }
        while (readRows_ < height_) {
            const double left = budgetMs - msSince(t0);
            if (left <= 0.0 && readRows_ > 0) return 0;
            const int rows = std::clamp(msPerRow_ > 0.0 ? int(left / msPerRow_) : 16, 1, height_ - readRows_);
            const auto r0 = std::chrono::steady_clock::now();
            const GLsizei bytes = GLsizei(rowFloats * size_t(rows) * sizeof(float));
            resetPackState();  // into client memory, whatever a VTK view left bound
            glGetTextureSubImage(position.id(), 0, 0, readRows_, 0, width_, rows, 1, GL_RGBA, GL_FLOAT, bytes,
                                 &rawPositions_[rowFloats * size_t(readRows_)]);
            glGetTextureSubImage(normal.id(), 0, 0, readRows_, 0, width_, rows, 1, GL_RGBA, GL_FLOAT, bytes,
                                 &rawNormals_[rowFloats * size_t(readRows_)]);
            msPerRow_ = msSince(r0) / double(rows);
            readRows_ += rows;
        }
        // Converted on the worker (as Renderer::positions() and normals(): 3 channels, row 0 at the
        // top, NaN on the background, whose rays are not traced: lit). ~50 ms here at 774x557.
        auto job = std::make_shared<Job>();
        job->scene = scene_;
        job->time = time_;
        job->lights = lights_;
        job->rays = rays_;
        job->width = width_;
        job->height = height_;
        job->rawPositions = std::move(rawPositions_);
        job->rawNormals = std::move(rawNormals_);
        job->tracer = tracer_;
        job_ = job;
        worker_ = std::thread([job] { runJob(job); });
        started_ = true;
        return 0;
    }
    if (shadeRows_ == 0) {  // a finished batch: every light's estimate uploaded, then shaded in bands
        std::vector<Image> estimate;
        {
            std::lock_guard<std::mutex> lock(job_->mutex);
            if (!job_->error.empty()) {
                std::fprintf(stderr, "shadowlab window: raytraced: %s\n", job_->error.c_str());
                job_->error.clear();
                return 0;
            }
            if (job_->built) tracer_ = job_->built;
            if (job_->traced == shown_) return 0;
            estimate.swap(job_->estimate);
            shading_ = job_->traced;
            lastBatchMs_ = job_->batchMs;
        }
        shadeInputs_.assign(lights_.size(), nullptr);
        lightVisibility_.resize(lights_.size());
        for (size_t i = 0; i < lights_.size(); ++i) {
            if (i >= estimate.size() || estimate[i].data.empty()) continue;
            Texture& t = lightVisibility_[i];
            if (!t || t.width() != width_ || t.height() != height_) t = Texture::create2D(width_, height_, Format::R32F);
            uploadTexture(t, 0, 0, estimate[i]);  // ~0.5 ms a light at 1024x608
            shadeInputs_[i] = &t;
        }
    }
    // The shading in bands of rows within the budget (a whole shading cost ~15 ms at 1024x608 with
    // the worker on the other core), at least 16 rows a call. Until the last band the image is the
    // new batch below and the last one above: two estimates of the same picture, and done() still
    // says the last one (the view is composed again only when done() changes).
    const auto t0 = std::chrono::steady_clock::now();
    for (bool first = true; shadeRows_ < height_; first = false) {
        const double left = budgetMs - msSince(t0);
        if (left <= 0.0 && !first) return 0;
        const int rows = std::clamp(msPerShadeRow_ > 0.0 ? int(left / msPerShadeRow_) : 32, 16, height_ - shadeRows_);
        const auto r0 = std::chrono::steady_clock::now();
        renderer_->shadeWith(frame, shadeInputs_, shadeRows_, shadeRows_ + rows);
        glFinish();
        msPerShadeRow_ = msSince(r0) / double(rows);
        shadeRows_ += rows;
    }
    shadeRows_ = 0;
    shown_ = shading_;
    return 1;
}

void ProgressiveRaytrace::finish() {
    while (active() && !complete()) {
        if (step(1e9) == 0 && started_) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (job_ && job_->finished && job_->traced == shown_ && !complete()) break;  // failed (said on stderr)
    }
}

Image ProgressiveRaytrace::visibility() const { return renderer_->visibility(); }
const Texture& ProgressiveRaytrace::imageSum() const { return renderer_->imageTexture(); }
const Texture& ProgressiveRaytrace::visibilitySum() const {
    return renderer_->pool().find("frame/visibility")->texture;
}

namespace {

void runJob(const std::shared_ptr<ProgressiveRaytrace::Job>& jobPointer) {
    ProgressiveRaytrace::Job& job = *jobPointer;
    // Below the GL thread: on two cores the UI keeps one (the nice value is the thread's on Linux,
    // and RayTracer's own thread inherits it).
    setpriority(PRIO_PROCESS, pid_t(syscall(SYS_gettid)), 10);
    try {
        job.positions = Image(job.width, job.height, 3);
        job.normals = Image(job.width, job.height, 3);
        const size_t rowFloats = size_t(job.width) * 4;
        for (int y = 0; y < job.height; ++y) {
            const float* p = &job.rawPositions[size_t(job.height - 1 - y) * rowFloats];
            const float* n = &job.rawNormals[size_t(job.height - 1 - y) * rowFloats];
            float* po = &job.positions.data[size_t(y) * size_t(job.width) * 3];
            float* no = &job.normals.data[size_t(y) * size_t(job.width) * 3];
            for (int x = 0; x < job.width; ++x, p += 4, n += 4, po += 3, no += 3) {
                const bool background = p[3] == 0.0f;
                for (int c = 0; c < 3; ++c) {
                    po[c] = background ? NAN : p[c];
                    no[c] = background ? NAN : n[c];
                }
            }
        }
        job.rawPositions.reset();
        job.rawNormals.reset();
        std::shared_ptr<const RayTracer> tracer = job.tracer;
        if (!tracer) {
            auto built = std::make_shared<RayTracer>(*job.scene, job.time);
            built->setThreadCount(1);
            tracer = built;
        }
        {
            std::lock_guard<std::mutex> lock(job.mutex);
            job.built = tracer;
        }
        const int width = job.positions.width, height = job.positions.height;
        std::vector<SampleSums> sums(job.lights.size());
        uint32_t most = 1;
        for (size_t i = 0; i < job.lights.size(); ++i) {
            sums[i].reset(width, height, samplesOf(job.lights[i], job.rays));
            if (job.lights[i].castsShadows) most = std::max(most, sums[i].total);
        }
        uint32_t first = 0, count = 1;
        while (first < most && !job.cancel) {
            auto t0 = std::chrono::steady_clock::now();
            for (size_t i = 0; i < job.lights.size() && !job.cancel; ++i) {
                if (!job.lights[i].castsShadows || first >= sums[i].total) continue;
                tracer->traceSamples(job.positions, job.normals, job.lights[i], job.rays, first,
                                     std::min(count, sums[i].total - first), sums[i], true, &job.cancel);
            }
            if (job.cancel) break;
            const double ms = msSince(t0);
            first = std::min(most, first + count);
            std::vector<Image> estimate(job.lights.size());
            for (size_t i = 0; i < job.lights.size(); ++i)
                if (job.lights[i].castsShadows) estimate[i] = sums[i].image();
            {
                std::lock_guard<std::mutex> lock(job.mutex);
                job.estimate.swap(estimate);
                job.traced = int(first);
                job.batchMs = ms;
                ++job.published;
            }
            // The next batch: ~kBatchMs of tracing at this batch's cost per ray per pixel.
            const double perSample = ms / double(count);
            count = uint32_t(std::clamp(kBatchMs / std::max(perSample, 1e-3), 1.0, double(most - first + 1)));
        }
    } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(job.mutex);
        job.error = e.what();
    }
    job.finished = true;
}

}  // namespace

double ProgressiveRaytrace::lastSampleMs() const { return lastBatchMs_; }

}  // namespace shadowlab
