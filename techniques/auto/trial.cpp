// `auto`'s trials (trial.h): a setting and the ray-traced reference rendered on one light at the
// trial size, and the error between them, cached.
#include "auto/trial.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include "graph/renderer.h"
#include "image/metrics.h"

namespace shadowlab {

namespace {

// The GL state a trial's renders change and its caller may rely on (the window draws its panels
// after a choice made between two frames).
class SavedGlState {
public:
    SavedGlState() {
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_);
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_);
        glGetIntegerv(GL_VIEWPORT, viewport_);
        glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
        depth_ = glIsEnabled(GL_DEPTH_TEST);
        blend_ = glIsEnabled(GL_BLEND);
        scissor_ = glIsEnabled(GL_SCISSOR_TEST);
        cull_ = glIsEnabled(GL_CULL_FACE);
    }
    ~SavedGlState() {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_));
        glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_));
        glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
        glUseProgram(GLuint(program_));
        auto set = [](GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); };
        set(GL_DEPTH_TEST, depth_);
        set(GL_BLEND, blend_);
        set(GL_SCISSOR_TEST, scissor_);
        set(GL_CULL_FACE, cull_);
    }
    SavedGlState(const SavedGlState&) = delete;
    SavedGlState& operator=(const SavedGlState&) = delete;

private:
    GLint draw_ = 0, read_ = 0, viewport_[4] = {0, 0, 1, 1}, program_ = 0;
    GLboolean depth_ = GL_FALSE, blend_ = GL_FALSE, scissor_ = GL_FALSE, cull_ = GL_FALSE;
};

struct Trial {
    Image reference;
    std::vector<uint8_t> penumbra;
    std::map<std::string, MeasuredError> errors;  // by CalibrationSetting::describe()
    // shadow_ms at the trial size of settings timed side by side, by the list of their names
    std::map<std::string, std::vector<double>> timings;
    std::unique_ptr<Renderer> renderer;  // the settings' (while a choice measures)
    std::string rendererSetting;         // the setting it is set to
    int frame = 0;                       // its frames rendered so far (a timed frame's pass times are its own)
    uint64_t lastUse = 0;
};

std::mutex mutex;
std::map<uint64_t, Trial> trials;
uint64_t uses = 0;
// Views whose errors are kept: each holds a trial-size reference and its penumbra mask (at most
// 65536 floats and bytes, 0.33 MB), so at most about 10 MB; enough for every scene of assets/ with
// its lights' trials (the soak's rounds measure nothing again).
constexpr size_t kKeptTrials = 32;

uint64_t trialKey(const TrialInputs& in, const TrialSize& size) {
    uint64_t key = sceneContentKey(*in.scene, in.time);
    for (const Light& l : in.lights) key = mixLightKey(key, l);
    key = mixKey(key, uint64_t(in.light));
    for (int c = 0; c < 3; ++c) {
        key = mixKey(key, in.camera.position[c]);
        key = mixKey(key, in.camera.target[c]);
        key = mixKey(key, in.camera.up[c]);
    }
    key = mixKey(key, in.camera.fovYDegrees);
    key = mixKey(key, in.camera.nearPlane);
    key = mixKey(key, in.camera.farPlane);
    key = mixKey(key, uint64_t(size.width) * 8192 + uint64_t(size.height));
    return key;
}

// A renderer of `technique` on the scene with only light `in.light` casting shadows; the others light
// the scene unshadowed (v = 1 for them), so v's error is this light's error weighted by its share
// E_l / sum E_k of the light at each pixel (shade.frag): its part of the frame's error.
std::unique_ptr<Renderer> trialRenderer(const TrialInputs& in, const TrialSize& size, const std::string& technique,
                                        const std::vector<std::pair<std::string, std::string>>& sets) {
    RenderOptions o;
    o.width = size.width;
    o.height = size.height;
    o.technique = technique;
    o.sets = sets;
    o.reuse = false;  // every pass runs every frame: the timed frames time them all (as the bench)
    o.cpuClock = true;
    auto r = std::make_unique<Renderer>(*in.scene, o);
    for (size_t i = 0; i < in.lights.size() && i < in.scene->lights.size(); ++i) {
        Light l = in.lights[i];
        if (int(i) != in.light) l.castsShadows = false;  // runs nothing, v_l = 1
        r->setLight(i, l);
    }
    r->setCamera(in.camera);
    return r;
}

// Renders frame `frame` of `r` at the trial's time (a frame's index numbers its pass times).
void renderAt(Renderer& r, double time, int frame) {
    r.setTime(time);
    r.renderFrame(frame, {"visibility"});
}

}  // namespace

TrialSize trialSize(int width, int height) {
    TrialSize s{std::max(width, 1), std::max(height, 1)};
    const double pixels = double(s.width) * double(s.height);
    if (pixels <= double(kTrialPixels)) return s;
    const double scale = std::sqrt(double(kTrialPixels) / pixels);
    s.width = std::max(1, int(std::floor(s.width * scale)));
    s.height = std::max(1, int(std::floor(s.height * scale)));
    return s;
}

nlohmann::json TrialLog::toJson() const {
    return {{"size", {width, height}},
            {"reference", "raytraced rays=" + std::to_string(kTrialRays)},
            {"settings_measured", measured},
            {"settings_timed", timed},
            {"settings_reused", reused},
            {"reference_made", referenceMade},
            {"ms", ms}};
}

namespace {

// The view's trial (its reference made when missing); the caller holds `mutex`.
Trial& viewTrial(const TrialInputs& in, const TrialSize& size, TrialLog& log) {
    const uint64_t key = trialKey(in, size);
    auto it = trials.find(key);
    if (it == trials.end()) {
        if (trials.size() >= kKeptTrials) {  // the least recently used goes
            auto oldest = std::min_element(trials.begin(), trials.end(), [](const auto& a, const auto& b) {
                return a.second.lastUse < b.second.lastUse;
            });
            trials.erase(oldest);
        }
        Trial t;
        auto reference = trialRenderer(in, size, "raytraced", {{"rays", std::to_string(kTrialRays)}});
        renderAt(*reference, in.time, 0);
        t.reference = reference->visibility();
        t.penumbra = penumbraMask(t.reference);
        it = trials.emplace(key, std::move(t)).first;
        log.referenceMade = true;
    }
    it->second.lastUse = ++uses;
    return it->second;
}

// Sets the trial's renderer to `setting`; true when it changed (its next frame allocates).
bool useSetting(Trial& t, const TrialInputs& in, const TrialSize& size, const CalibrationSetting& setting) {
    const std::string name = setting.describe();
    if (t.renderer && t.rendererSetting == name) return false;
    if (!t.renderer) {
        t.renderer = trialRenderer(in, size, setting.technique, setting.sets);
    } else {
        t.renderer->setTechnique(setting.technique);
        for (const auto& [k, v] : setting.sets) t.renderer->setParam(k, v, -1, "calibration setting " + name);
    }
    t.rendererSetting = name;
    return true;
}

}  // namespace

MeasuredError measureSettingError(const TrialInputs& in, const CalibrationSetting& setting, TrialLog& log) {
    const TrialSize size = trialSize(in.width, in.height);
    log.width = size.width;
    log.height = size.height;
    const std::string name = setting.describe();
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = trials.find(trialKey(in, size)); it != trials.end()) {
        if (auto e = it->second.errors.find(name); e != it->second.errors.end()) {
            it->second.lastUse = ++uses;
            ++log.reused;
            return e->second;
        }
    }
    const auto t0 = std::chrono::steady_clock::now();
    SavedGlState saved;
    Trial& t = viewTrial(in, size, log);
    useSetting(t, in, size, setting);
    renderAt(*t.renderer, in.time, t.frame++);
    const Image v = t.renderer->visibility();
    MeasuredError e;
    e.rmse = computeMetrics(v, t.reference).rmse;
    const Metrics penumbra = computeMetrics(v, t.reference, &t.penumbra);
    e.rmsePenumbra = penumbra.pixels > 0 && std::isfinite(penumbra.rmse) ? penumbra.rmse : 0.0;
    ++log.measured;
    t.errors[name] = e;
    log.ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return e;
}

std::vector<double> timeSettingsSideBySide(const TrialInputs& in, const std::vector<CalibrationSetting>& settings,
                                           TrialLog& log) {
    const TrialSize size = trialSize(in.width, in.height);
    log.width = size.width;
    log.height = size.height;
    std::string key;
    for (const CalibrationSetting& s : settings) key += s.describe() + "\n";
    std::lock_guard<std::mutex> lock(mutex);
    const auto t0 = std::chrono::steady_clock::now();
    SavedGlState saved;
    Trial& t = viewTrial(in, size, log);
    if (auto known = t.timings.find(key); known != t.timings.end()) {
        log.reused += int(settings.size());
        return known->second;
    }
    std::vector<double> best(settings.size(), std::numeric_limits<double>::infinity());
    for (int round = 0; round < kTimedRounds; ++round) {
        for (size_t j = 0; j < settings.size(); ++j) {
            // Forward, then backward: no setting always follows the same one.
            const size_t i = round % 2 == 0 ? j : settings.size() - 1 - j;
            if (useSetting(t, in, size, settings[i])) renderAt(*t.renderer, in.time, t.frame++);  // untimed: the switch allocates
            const int frame = t.frame++;
            renderAt(*t.renderer, in.time, frame);
            best[i] = std::min(best[i], t.renderer->cost(frame).shadowMs);
        }
    }
    log.timed += int(settings.size());
    t.timings[key] = best;
    log.ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return best;
}

void releaseTrialRenderers() {
    std::lock_guard<std::mutex> lock(mutex);
    for (auto& [key, t] : trials) t.renderer.reset();
}

}  // namespace shadowlab
