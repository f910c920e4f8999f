// The window's progressive reference: the `reference` technique's N stratified light samples, run a
// few per frame instead of all in one frame (which froze the window for a minute on llvmpipe).
// Each sample is the `hard` technique with every light moved to its sample point (the same points
// and weights as techniques/reference: shared::stratifiedSample with seed light index + 1); the
// visibility and the linear shaded image are added with the sample's weight into float textures on
// the GPU (shaders/window/accumulate.frag), so a sample costs one `hard` frame and no read-back.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "shared/shared.h"
#include "visibility/raytracer.h"
#include "window/window.h"

namespace shadowlab {

bool sameLight(const Light& a, const Light& b) {
    return a.shape == b.shape && a.position == b.position && a.direction == b.direction && a.up == b.up &&
           a.size == b.size && a.color == b.color && a.intensity == b.intensity && a.castsShadows == b.castsShadows;
}

bool sameCamera(const Camera& a, const Camera& b) {
    return a.position == b.position && a.target == b.target && a.up == b.up && a.fovYDegrees == b.fovYDegrees &&
           a.nearPlane == b.nearPlane && a.farPlane == b.farPlane;
}

void ProgressiveSource::restarted() {
    static uint64_t next = 0;  // the GL thread's: sources restart there
    generation_ = ++next;
}

void ProgressiveReference::cancel() {
    renderer_.reset();
    scene_ = nullptr;
    done_ = total_ = 0;
    restarted();
}

bool ProgressiveReference::isDepthParam(const std::string& key) {
    return key == "sm_size" || key == "bias_const" || key == "bias_slope" || key == "plane_test";
}

void ProgressiveReference::sync(const Scene& scene, const Camera& camera, const std::vector<Light>& lights, int width,
                                int height, double time, int samples, const std::map<std::string, std::string>& depthParams) {
    bool same = renderer_ && scene_ == &scene && sameCamera(camera, camera_) && width == width_ && height == height_ &&
                time == time_ && samples == total_ && lights.size() == lights_.size() && depthParams == depthParams_;
    for (size_t i = 0; same && i < lights.size(); ++i) same = sameLight(lights[i], lights_[i]);
    if (same) return;
    restarted();
    if (!renderer_ || scene_ != &scene || depthParams != depthParams_) {
        depthParams_ = depthParams;
        renderer_.reset();
        RenderOptions options;
        options.width = width;
        options.height = height;
        options.spareBytes = kSpareBytes;
        options.technique = "hard";
        // Each sample's hard frame tests depth as `reference` does: its shadow-map settings (size,
        // biases, the tangent-plane test) as the step or the panel set them, else its defaults, so
        // the sum converges to what `reference` renders with the same settings.
        const TechniqueDesc& reference = requireTechnique("reference", "progressive reference");
        for (const char* key : {"sm_size", "bias_const", "bias_slope", "plane_test"}) {
            const ParamDesc* p = reference.findParam(key);
            if (!p) continue;
            auto set = depthParams.find(key);
            char value[32];
            std::snprintf(value, sizeof value, "%g", p->defaultValue);
            options.sets.emplace_back(key, set != depthParams.end() ? set->second : std::string(value));
        }
        options.cpuClock = true;
        renderer_ = std::make_unique<Renderer>(scene, options);
        // One frame now, in slices as its samples run (the window makes this renderer at scene
        // load): its shadow map's first allocation and draw and llvmpipe's variants of its programs
        // for a scissored draw (0.1 s each on plant) would otherwise land in the first sample's frame.
        renderer_->refineFrame(0, {"image", "visibility"}, 1e9);
    }
    if (renderer_->width() != width || renderer_->height() != height) renderer_->resize(width, height);
    renderer_->setCamera(camera);
    if (!imageSum_ || imageSum_.width() != width || imageSum_.height() != height) {
        imageSum_ = Texture::create2D(width, height, Format::RGBA32F);
        visibilitySum_ = Texture::create2D(width, height, Format::R32F);
        sums_ = Framebuffer({&imageSum_, &visibilitySum_}, nullptr);
    }
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(sums_.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(sums_.id(), GL_COLOR, 1, zero);
    scene_ = &scene;
    camera_ = camera;
    lights_ = lights;
    width_ = width;
    height_ = height;
    time_ = time;
    total_ = samples;
    done_ = 0;
    weightSum_ = 0.0;
    sampleStarted_ = false;
}

int ProgressiveReference::step(double budgetMs) {
    if (!renderer_ || complete()) return 0;
    auto start = std::chrono::steady_clock::now();
    auto spentMs = [&] {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    };
    int ran = 0;
    while (done_ < total_) {
        if (!sampleStarted_) {
            // Every light at sample done_ (each light its own stratification seed, as the technique).
            sampleWeight_ = 0.0;
            for (size_t i = 0; i < lights_.size(); ++i) {
                const Light& l = lights_[i];
                glm::vec3 sample = shared::stratifiedSample(spreadSampleOrder(uint32_t(done_), uint32_t(total_)),
                                                            uint32_t(total_), uint32_t(i + 1));
                Light at = l;
                if (!l.isPoint())
                    at.position = shared::lightSamplePosition(l.position, l.right(), l.up, int(l.shape), l.size,
                                                              glm::vec2(sample.x, sample.y));
                renderer_->setLight(i, at);
                sampleWeight_ += sample.z;
            }
            sampleWeight_ /= double(std::max<size_t>(1, lights_.size()));
            sampleStarted_ = true;
            sampleMs_ = 0.0;
        }
        // The sample's hard frame in slices of what is left of the budget (at a size where one
        // sample exceeds the frame budget it spans frames; the window's UI keeps its rate).
        auto t0 = std::chrono::steady_clock::now();
        const double progress = renderer_->refineFrame(int(time_ * 30.0 + 0.5), {"image", "visibility"},  // t = frame / 30
                                                       std::max(0.5, budgetMs - spentMs()));
        glFinish();
        sampleMs_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (progress < 1.0) break;
        if (!accumulate_.id()) accumulate_ = ShaderProgram("common/fullscreen.vert", "window/accumulate.frag");
        PipelineState::additiveBlend().apply();
        accumulate_.use();
        glBindTextureUnit(0, renderer_->imageTexture().id());
        glBindTextureUnit(1, renderer_->pool().find("frame/visibility")->texture.id());
        accumulate_.set("image", 0);
        accumulate_.set("visibility", 1);
        accumulate_.set("weight", float(sampleWeight_));
        sums_.bind(width_, height_);
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glFinish();  // the sample's cost lands here, not in the next frame
        weightSum_ += sampleWeight_;
        ++done_;
        ++ran;
        sampleStarted_ = false;
        lastSampleMs_ = sampleMs_;
        if (spentMs() + lastSampleMs_ > budgetMs) break;
    }
    return ran;
}

Image ProgressiveReference::visibility() const {
    Image out = readTexture(visibilitySum_, 1);
    float norm = normalization();
    for (float& v : out.data) v *= norm;
    return out;
}

}  // namespace shadowlab
