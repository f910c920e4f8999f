// The window: the loop, the renderers, the technique view (present), the overlay of the light and
// the split, screenshots; runWindow (`shadowlab window`) and runDefault (`shadowlab` with no
// arguments, with a headless fallback when no display is there). See window.h for the structure.
#include "scene/input_file.h"
#include "gl/loader.h"  // before GLFW, which must not include GL/gl.h
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/resource_limits.h"
#include "error.h"
#include "gl/context.h"
#include "lesson/lesson.h"
#include "lesson/player.h"
#include "scene/light_view.h"
#include "views.h"
#include "vtk_offscreen.h"
#include "window/camera_control.h"
#include "window/window.h"

namespace shadowlab {

namespace fs = std::filesystem;

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool isGltf(const std::string& path) { return endsWith(path, ".gltf") || endsWith(path, ".glb"); }

ImU32 rgba(int r, int g, int b, int a = 255) { return IM_COL32(r, g, b, a); }

// An output's folder must exist (nothing is created half-way); checked before the window opens.
void checkOutputPath(const std::string& flag, const std::string& path) {
    if (path.empty()) throw InputError("window: " + flag + ": expected a file path");
    checkPathName("window: " + flag, path);
    fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw InputError("window: " + flag + ": folder '" + parent.string() + "' does not exist");
    if (fs::is_directory(path, ec)) throw InputError("window: " + flag + ": '" + path + "' is a folder, expected a file path");
}

}  // namespace

// ---- the Window ---------------------------------------------------------------------------------------

Window::Window(GLFWwindow* window, WindowState state, bool software)
    : window_(window), state_(std::move(state)), software_(software) {
    for (const TechniqueDesc* d : allTechniques()) techniques_.push_back(d->id);
    scenes_ = listScenes();
    present_ = ShaderProgram("common/fullscreen.vert", "window/present.frag");
    errorDummy_ = Texture::create2D(1, 1, Format::R32F);
    if (const TechniqueDesc* reference = findTechnique("reference"))
        if (const ParamDesc* p = reference->findParam("samples")) state_.referenceSamples = int(p->defaultValue);
    if (const TechniqueDesc* raytraced = findTechnique("raytraced"))
        if (const ParamDesc* p = raytraced->findParam("rays")) state_.referenceRays = int(p->defaultValue);
    updateLayout();
    if (!rebuildScene()) throw InputError("window: " + status_);
}

Window::~Window() = default;

glm::vec2 Window::windowSize() const {
    int w = 1, h = 1;
    glfwGetWindowSize(window_, &w, &h);
    return glm::vec2(std::max(1, w), std::max(1, h));
}

float Window::aspect() const {
    glm::ivec2 s = renderSize();
    return float(s.x) / float(s.y);
}

glm::ivec2 Window::framebufferSize() const {
    int w = 1, h = 1;
    glfwGetFramebufferSize(window_, &w, &h);
    return glm::ivec2(std::max(1, w), std::max(1, h));
}

glm::ivec2 Window::renderSize() const {
    const glm::vec2 scale = glm::vec2(framebufferSize()) / windowSize();  // HiDPI: pixels per window unit
    const LayoutRect& r = layout_.technique;
    return glm::max(glm::ivec2(1), glm::ivec2(glm::round(glm::vec2(r.w, r.h) * scale)));
}

glm::vec2 Window::toView(glm::vec2 windowPoint) const {
    return windowPoint - glm::vec2(layout_.technique.x, layout_.technique.y);
}

void Window::updateLayout() {
    // Presentation: body text at least 1/40 of the window's height, whatever its size.
    if (state_.presentation) state_.uiScale = presentationUiScale(windowSize().y);
    LayoutInput in;
    in.window = windowSize();
    in.uiScale = state_.uiScale;
    in.panel = state_.showPanel;
    in.hud = state_.showHud;
    in.lesson = lesson_ != nullptr;
    in.present = state_.presentation;
    // Each view renders at its cell's size (views_panel.cpp), at the view's own aspect (viewAspect:
    // the error view's two frame images side by side are ~2x the frame's), the chart at its own.
    // The aspects are taken again only when what they depend on changes (the views, the technique,
    // the pick, the light), not when the frame's size does: a cell's aspect feeding back into the
    // frame's size would re-lay the window out frame after frame. The frame aspect they are for is
    // the technique region's without the views.
    if (state_.showViews) {
        const WindowLayout bare = computeWindowLayout(in);
        const float frameAspect = bare.technique.h > 0.0f ? bare.technique.w / bare.technique.h : 4.0f / 3.0f;
        char frameText[32];
        std::snprintf(frameText, sizeof frameText, "|%.3f", frameAspect);
        std::string key = state_.technique + "|" + std::to_string(state_.lightIndex) + (state_.pickedPixel ? "|pick" : "|") + frameText;
        for (const auto& v : views_) key += "|" + v->name;
        if (key != viewAspectKey_ && renderer_) {
            viewAspects_.clear();
            for (const auto& v : views_) {
                ViewRequest request;
                request.view = v->name;
                request.pixel = state_.pickedPixel;
                if (request.pixel) *request.pixel = glm::clamp(*request.pixel, glm::ivec2(0), glm::ivec2(renderer_->width(), renderer_->height()) - 1);
                request.light = std::clamp(state_.lightIndex, 0, std::max(0, int(renderer_->lights().size()) - 1));
                float aspect = 4.0f / 3.0f;
                try {
                    aspect = viewAspect(*renderer_, request, frameAspect);
                } catch (const InputError&) {
                }
                viewAspects_.push_back(aspect);
            }
            viewAspectKey_ = key;
        }
        in.cellAspects = viewAspects_;
        in.cellAspects.resize(views_.size(), 4.0f / 3.0f);
    }
    if (state_.showAccuracy) in.cellAspects.push_back(560.0f / 380.0f);
    layout_ = computeWindowLayout(in);
}

void Window::placeRegion(const LayoutRect& r) const {
    ImGui::SetNextWindowPos(ImVec2(r.x, r.y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(r.w, r.h), ImGuiCond_Always);
}

bool Window::interacting() const {
    // Moving the split changes no rendered state: the technique and the reference stay as they are.
    if (drag_ != Drag::None && drag_ != Drag::Split) return true;
    if (ImGui::GetCurrentContext() && ImGui::IsAnyItemActive()) return true;
    return std::chrono::duration<double>(clock::now() - lastInput_).count() < 0.15;
}

void Window::setStatus(const std::string& text, bool error) {
    status_ = text;
    statusError_ = error;
    statusTime_ = clock::now();
    if (error) std::fprintf(stderr, "shadowlab window: %s\n", text.c_str());
}

std::string Window::memoryRefusal(const std::string& technique, const std::map<std::string, std::string>& params) const {
    if (!scene_ || technique == "raytraced" || technique == "reference") return "";  // their renderers run hard
    RenderOptions options;
    const glm::ivec2 size = renderSize();
    options.width = size.x;
    options.height = size.y;
    options.technique = technique;
    for (const auto& [key, value] : params) options.sets.push_back({key, value});
    const double bytes = estimateRenderBytes(*scene_, options);
    if (bytes <= double(state_.maxMemoryMB) * 1e6) return "";
    return technique + " with these parameters would need about " + std::to_string(int(bytes / 1e6)) +
           " MB at " + std::to_string(size.x) + "x" + std::to_string(size.y) + ", over the limit of " +
           std::to_string(state_.maxMemoryMB) + " MB (--max-memory-mb N raises it): not applied";
}

bool Window::rebuildScene() {
    std::unique_ptr<Scene> scene;
    try {
        scene = std::make_unique<Scene>(loadScene(state_.scene));
    } catch (const InputError& e) {
        setStatus(e.what(), true);
        return false;
    }
    preview_ = MirrorRenderer();
    previewSizes_.clear();
    compare_ = MirrorRenderer();
    comparePreview_ = MirrorRenderer();
    reference_.cancel();
    raytrace_.cancel();  // joins its worker before the old scene goes
    renderer_.reset();
    scene_ = std::move(scene);
    state_.camera = scene_->camera;
    state_.lights = scene_->lights;
    state_.lightIndex = std::clamp(state_.lightIndex, 0, std::max(0, int(state_.lights.size()) - 1));
    RenderOptions options;
    glm::ivec2 size = renderSize();
    options.width = size.x;
    options.height = size.y;
    options.technique = showsReference() ? "hard" : state_.technique;
    options.cpuClock = true;
    options.spareBytes = kSpareBytes;  // the layout changes its size: a return to a size allocates nothing
    renderer_ = std::make_unique<Renderer>(*scene_, options);
    for (const auto& [key, value] : state_.params) {
        try {
            renderer_->setParam(key, value, -1, "window");
        } catch (const InputError& e) {
            setStatus(e.what(), true);
        }
    }
    std::string title = "shadowlab - " + scene_->name + " - " + state_.technique + "   (F1: keys)";
    glfwSetWindowTitle(window_, title.c_str());
    compileShaders();  // on the drag frames' renderer, made now
    // The progressive reference's renderer now too, not at the first idle moment: it uploads the
    // scene (~0.25 s on plant).
    syncReference(size);
    if (!raytrace_.active()) {  // the ray tracer's renderer too (its worker starts when it is shown or compared)
        raytrace_.sync(*scene_, state_.camera, state_.lights, size.x, size.y, state_.time, state_.referenceRays);
        raytrace_.pause();
    }
    touch();
    return true;
}

void Window::compileShaders() {
    // One pass over every technique the window runs, on this scene (its light count is a define of
    // the shading program), on the drag frames' renderer, which keeps every technique's resources:
    // - the programs land in the context's cache, so a technique switch later compiles nothing (on
    //   llvmpipe a technique's programs take 0.1-0.3 s, a frozen frame);
    // - llvmpipe compiles a variant of each shader per texture state at its first draw, and the
    //   state holds whether a texture's sides are powers of two: a small frame at the view's
    //   pattern (1024 wide: a power of two), refined too (the scissored draws);
    // - a frame at 1/kWarmDivisor of the view allocates the technique's light-space maps there, so
    //   a drag's first frame of a technique does not (~0.1 s on llvmpipe).
    auto t0 = clock::now();
    const glm::ivec2 full = renderSize();
    auto pot = [](int n) { return n > 0 && (n & (n - 1)) == 0; };
    const glm::ivec2 pattern(pot(full.x) ? 16 : 17, pot(full.y) ? 16 : 17);
    const glm::ivec2 warm = glm::max(glm::ivec2(1), full / kWarmDivisor);
    const std::string current = showsReference() ? "hard" : state_.technique;
    Renderer& preview = syncMirror(preview_, current, state_.params, warm);
    int count = 0;
    for (const std::string& id : techniques_) {
        if (id == "raytraced" || id == "reference") continue;
        try {
            preview.setTechnique(id);
            preview.resize(pattern.x, pattern.y);
            preview.renderFrame(0, {"image", "visibility"});
            preview.refineFrame(1, {"image", "visibility"}, 1e9);
            preview.resize(warm.x, warm.y);
            preview.renderFrame(2, {"image", "visibility"});
            ++count;
        } catch (const InputError& e) {
            setStatus(id + ": " + e.what(), true);
        }
    }
    previewSizes_.insert({warm.x, warm.y});
    preview_.technique.clear();  // the next syncMirror sets the technique and parameters again
    glFinish();
    std::printf("shadowlab window: compiled the shaders of %d techniques for %s in %.1f s\n", count,
                scene_->name.c_str(), msSince(t0) / 1000.0);
    std::fflush(stdout);
}

// ---- actions ------------------------------------------------------------------------------------------

void Window::selectScene(const std::string& nameOrPath) {
    std::string previous = state_.scene;
    state_.scene = nameOrPath;
    state_.pickedPixel.reset();
    if (!rebuildScene()) {
        state_.scene = previous;  // the old scene stays loaded
        return;
    }
    if (std::find(scenes_.begin(), scenes_.end(), nameOrPath) == scenes_.end()) scenes_.push_back(nameOrPath);
    setStatus("scene " + scene_->name);
}

void Window::selectTechnique(const std::string& id) {
    const TechniqueDesc* desc = findTechnique(id);
    if (!desc) {
        setStatus("unknown technique '" + id + "'", true);
        return;
    }
    if (const std::string why = memoryRefusal(id, {}); !why.empty()) {
        setStatus(why, true);
        return;
    }
    state_.technique = id;
    statsValid_ = false;
    state_.params.clear();  // setTechnique starts at the technique's defaults
    renderer_->setTechnique(showsReference() ? "hard" : id);
    std::string title = "shadowlab - " + scene_->name + " - " + id + "   (F1: keys)";
    glfwSetWindowTitle(window_, title.c_str());
    setStatus("technique " + id);
    touch();
}

void Window::setParam(const std::string& key, const std::string& value) {
    if (state_.technique == "raytraced") {
        if (key != "rays") {
            setStatus("the progressive ray tracer has no '" + key + "' (it takes rays)", true);
            return;
        }
        try {
            const TechniqueDesc& raytraced = *findTechnique("raytraced");
            ParamValues check(raytraced);
            check.set(raytraced, key, value, "window");
            setReferenceRays(check.getInt("rays"));
            state_.params[key] = value;
        } catch (const InputError& e) {
            setStatus(e.what(), true);
        }
        return;
    }
    if (state_.technique == "reference") {
        if (key == "samples") {
            try {
                ParamValues check(*findTechnique("reference"));
                check.set(*findTechnique("reference"), key, value, "window");
                state_.referenceSamples = check.getInt("samples");
                state_.params[key] = value;
                touch();
            } catch (const InputError& e) {
                setStatus(e.what(), true);
            }
        } else if (ProgressiveReference::isDepthParam(key)) {
            setReferenceParam(key, value);
        } else {
            setStatus("the progressive reference has no '" + key + "'", true);
        }
        return;
    }
    try {
        std::map<std::string, std::string> next = state_.params;
        next[key] = value;
        if (const std::string why = memoryRefusal(state_.technique, next); !why.empty()) {
            setStatus(why, true);
            return;
        }
        renderer_->setParam(key, value, -1, "window");
        state_.params[key] = value;
        touch();
    } catch (const InputError& e) {
        setStatus(e.what(), true);
    }
}

void Window::resetParam(const std::string& key) {
    const TechniqueDesc* desc = findTechnique(state_.technique);
    const ParamDesc* p = desc ? desc->findParam(key) : nullptr;
    if (!p) return;
    std::string value = p->type == ParamDesc::Type::Enum ? p->choices.at(size_t(p->defaultValue))
                                                         : nlohmann::json(p->defaultValue).dump();
    if (p->type == ParamDesc::Type::Int || p->type == ParamDesc::Type::Bool)
        value = std::to_string(int64_t(std::llround(p->defaultValue)));
    setParam(key, value);
    state_.params.erase(key);
}

void Window::resetAllParams() {
    std::vector<std::string> keys;
    for (const auto& kv : state_.params) keys.push_back(kv.first);
    for (const std::string& k : keys) resetParam(k);
}

void Window::setLight(int index, const Light& light) {
    if (index < 0 || size_t(index) >= state_.lights.size()) return;
    Light l = light;
    if (glm::length(l.direction) < 1e-6f) l.direction = {0, -1, 0};
    l.direction = glm::normalize(l.direction);
    l.size = std::max(0.0f, l.size);
    state_.lights[size_t(index)] = l;
    renderer_->setMeasureChoices(!interacting());
    renderer_->setLight(size_t(index), l);
    touch();
}

void Window::resetLight() {
    for (size_t i = 0; i < scene_->lights.size() && i < state_.lights.size(); ++i) setLight(int(i), scene_->lights[i]);
}

void Window::setCamera(const Camera& camera) {
    state_.camera = camera;
    renderer_->setMeasureChoices(!interacting());  // `auto` measures its picks at rest only (renderViews)
    renderer_->setCamera(camera);
    touch();
}

void Window::resetCamera() { setCamera(scene_->camera); }

void Window::pickPixel(glm::ivec2 pixel) {
    glm::ivec2 size = renderSize();
    pixel = glm::clamp(pixel, glm::ivec2(0), size - 1);
    state_.pickedPixel = pixel;  // views re-render for it (no rendered state changes: no touch())
    pickSize_ = size;
    lessonPick_.reset();  // the lesson host sets it again after this when the pick is its world point
    setStatus("picked pixel " + std::to_string(pixel.x) + "," + std::to_string(pixel.y));
}

void Window::setCompare(WindowState::Compare compare, const std::string& technique) {
    if (compare == WindowState::Compare::Technique) {
        std::string id = technique.empty() ? state_.compareTechnique : technique;
        if (!findTechnique(id) || id == "raytraced" || id == "reference") {
            setStatus("split: '" + id + "' is not a live technique (the reference has its own split mode)", true);
            return;
        }
        state_.compareTechnique = id;
    }
    state_.compare = compare;  // what is shown, not what is rendered: no touch()
}

void Window::setErrorView(bool on) { state_.errorView = on; }

void Window::setSplit(float split) { state_.split = std::clamp(split, 0.0f, 1.0f); }

void Window::setReferenceSamples(int samples) {
    state_.referenceSamples = std::clamp(samples, 1, 65536);
    touch();
}

void Window::setReferenceTechnique(const std::string& id) {
    if (id != "reference" && id != "raytraced") {
        setStatus("the window's references are reference and raytraced, not '" + id + "'", true);
        return;
    }
    if (id == state_.referenceTechnique) return;
    if (shownSource() != &ref()) {  // unless the view shows it
        if (&ref() == &raytrace_) raytrace_.pause();  // keeps its renderer
        else reference_.cancel();
    }
    state_.referenceTechnique = id;
    touch();
}

void Window::setReferenceRays(int rays) {
    state_.referenceRays = std::clamp(rays, 1, 65536);
    touch();
}

bool Window::referenceNeeded() const {
    return state_.backgroundReference || state_.compare == WindowState::Compare::Reference || state_.errorView ||
           (lesson_ && (lesson_->checkPending() || lesson_->expectsPending()));
}

void Window::syncReference(glm::ivec2 size) {
    const bool needed = referenceNeeded();
    auto inUse = [&](const ProgressiveSource& s) { return shownSource() == &s || (needed && &ref() == &s); };
    if (inUse(raytrace_)) raytrace_.sync(*scene_, state_.camera, state_.lights, size.x, size.y, state_.time, state_.referenceRays);
    else raytrace_.pause();
    if (inUse(reference_))
        reference_.sync(*scene_, state_.camera, state_.lights, size.x, size.y, state_.time, state_.referenceSamples,
                        state_.referenceParams);
    else if (reference_.active()) reference_.cancel();
}

void Window::setReferenceParam(const std::string& key, const std::string& value) {
    try {
        if (!ProgressiveReference::isDepthParam(key))
            throw InputError("window: the progressive reference takes samples, sm_size, bias_const, bias_slope and "
                             "plane_test, not '" + key + "'");
        const TechniqueDesc& reference = *findTechnique("reference");
        ParamValues check(reference);
        check.set(reference, key, value, "window");  // a bad value is refused, naming the key
        state_.referenceParams[key] = value;
        touch();
    } catch (const InputError& e) {
        setStatus(e.what(), true);
    }
}

void Window::setUiScale(float scale) {
    if (!std::isfinite(scale)) return;  // the script and the panel pass checked values; never NaN into ImGui
    state_.uiScale = std::clamp(scale, 0.5f, 4.0f);
    if (!state_.presentation) normalUiScale_ = state_.uiScale;
}

void Window::setPresentation(bool on) {
    if (on == state_.presentation) return;
    state_.presentation = on;
    if (!on) state_.uiScale = normalUiScale_;
    setStatus(on ? "presentation mode (F5 leaves it)" : "presentation mode off");
}

void Window::cycleTechnique(int step) {
    std::vector<std::string> live;
    for (const std::string& t : techniques_)
        if (t != "raytraced") live.push_back(t);  // T stays on the GPU's techniques; raytraced: panel, key 8
    auto it = std::find(live.begin(), live.end(), state_.technique);
    size_t i = it == live.end() ? 0 : size_t(it - live.begin());
    selectTechnique(live[(i + live.size() + size_t(step + int(live.size()))) % live.size()]);
}

void Window::cycleScene(int step) {
    auto it = std::find(scenes_.begin(), scenes_.end(), state_.scene);
    size_t i = it == scenes_.end() ? 0 : size_t(it - scenes_.begin());
    selectScene(scenes_[(i + scenes_.size() + size_t(step + int(scenes_.size()))) % scenes_.size()]);
}

void Window::screenshot(const std::string& path) { pendingShots_.push_back(path); }

// ---- rendering ----------------------------------------------------------------------------------------

double Window::renderBudgetMs() const {
    // What the last frame spent outside rendering (script, UI, present less its composition, ImGui,
    // swap) comes off the frame budget, and a composition's cost when this frame is likely to
    // compose; the technique and the reference always get at least 8 ms.
    const double other = phaseMs_[0] + std::max(0.0, phaseMs_[2] - composeMs_) + phaseMs_[3] + phaseMs_[4];
    return std::max(8.0, kFrameBudgetMs - other - (composeLikely() ? composeCostMs_ : 0.0));
}

bool Window::composeLikely() const {
    if (state_.playing || composedVersion_ != version_) return true;  // a change not composed yet
    const ProgressiveSource* source = shownSource();
    if (source && !source->complete()) return true;  // its next batch or sample is composed
    const bool referenceInView = state_.errorView || state_.compare == WindowState::Compare::Reference;
    return referenceInView && !ref().complete();
}

int Window::cachedPreviewDivisor(glm::ivec2 full, int from, int to) const {
    for (int k = std::max(1, from); k <= to; ++k) {
        const glm::ivec2 size = glm::max(glm::ivec2(1), full / k);
        if (previewSizes_.count({size.x, size.y})) return k;
    }
    return 0;
}

Renderer& Window::syncMirror(MirrorRenderer& m, const std::string& technique,
                             const std::map<std::string, std::string>& params, glm::ivec2 size) {
    if (!m.renderer) {
        RenderOptions options;
        options.width = size.x;
        options.height = size.y;
        options.technique = technique;
        options.cpuClock = true;
        options.keepResources = &m == &preview_;  // the drag frames' renderer: see rebuildScene
        options.spareBytes = kSpareBytes;  // the drag's divisor changes its size
        // A drag's reduced frames: `auto` predicts there (a trial a frame would stall the drag).
        options.measureChoices = &m != &preview_ && &m != &comparePreview_;
        m.renderer = std::make_unique<Renderer>(*scene_, options);
        m.technique = technique;
        m.params.clear();
        m.version = ~0ull;
    }
    Renderer& r = *m.renderer;
    if (m.version != version_ || m.technique != technique || m.params != params) {
        if (m.technique != technique || m.params != params) {
            r.setTechnique(technique);  // back to its defaults, then the parameters set
            for (const auto& [key, value] : params) {
                try {
                    r.setParam(key, value, -1, "window");
                } catch (const InputError&) {
                    // the window's renderer validated the value already
                }
            }
            m.technique = technique;
            m.params = params;
        }
        r.setCamera(state_.camera);
        for (size_t i = 0; i < state_.lights.size(); ++i) r.setLight(i, state_.lights[i]);
        m.version = version_;
    }
    if (r.width() != size.x || r.height() != size.y) r.resize(size.x, size.y);
    return r;
}

std::string Window::shownText() const {
    if (!pendingShots_.empty()) return "";  // a screenshot's frame renders whole
    char text[96];
    const int factor = reduced_ && preview_.renderer ? std::max(1, renderSize().x / std::max(1, preview_.renderer->width())) : 1;
    if (reduced_ && interacting()) std::snprintf(text, sizeof text, "reduced 1/%d while dragging", factor);
    else if (reduced_) std::snprintf(text, sizeof text, "preview at 1/%d, refining next", factor);
    else if (refineProgress_ < 1.0) std::snprintf(text, sizeof text, "refining, %d%%", int(100.0 * refineProgress_));
    else if (!imageComplete_) std::snprintf(text, sizeof text, "refining %s", state_.compareTechnique.c_str());
    else return "";
    return text;
}

void Window::renderViews() {
    // `auto`'s choices: predicted while the user drags or types (Window::setCamera), measured again
    // once at rest (a trial renders each candidate on this view: a second's stall, not one per frame).
    renderer_->setMeasureChoices(!interacting());
    glm::ivec2 full = renderSize();
    const double budget = renderBudgetMs();
    // The layout changed the technique view's size (a panel, the views, presentation): the picked
    // pixel stays on the same point of the image.
    if (state_.pickedPixel && pickSize_ != full && pickSize_.x > 0 && pickSize_.y > 0) {
        const glm::vec2 f = (glm::vec2(*state_.pickedPixel) + 0.5f) / glm::vec2(pickSize_);
        state_.pickedPixel = glm::clamp(glm::ivec2(f * glm::vec2(full)), glm::ivec2(0), full - 1);
        // A lesson's pick: projected again at the new size (another aspect moves a world point).
        if (lessonPick_)
            if (auto p = pickPixelAt(*lessonPick_, state_.camera, full.x, full.y)) state_.pickedPixel = *p;
        pickSize_ = full;
        // The status line names the pixel as it is now, not where it was before the re-layout.
        if (status_.rfind("picked pixel ", 0) == 0)
            status_ = "picked pixel " + std::to_string(state_.pickedPixel->x) + "," + std::to_string(state_.pickedPixel->y);
    }
    if (state_.playing) {
        ++frameIndex_;
        touch();
    }
    state_.time = frameIndex_ / 30.0;

    // What this frame runs (README "The frame budget"): a screenshot renders whole; a drag, or the
    // first frame of a change whose last full frame cost more than the budget, renders the whole
    // frame at a reduced resolution that fits; otherwise the full resolution is refined in slices
    // of the budget (Renderer::refineFrame), over as many frames as it needs, and shown once complete.
    const bool shot = !pendingShots_.empty();
    // By the technique the full-size renderer runs (`hard` under the progressive references).
    const std::string costKey = showsReference() ? "hard" : state_.technique;
    auto known = frameCostMs_.find(costKey);
    const double knownCost = known == frameCostMs_.end() ? -1.0 : known->second;
    const bool dragging = interacting();
    // The divisor per side of the frames while dragging, by technique: from the full frame's cost
    // when first needed, then adapted to what the drag's frames cost (1: the full resolution fits).
    auto factorIt = dragFactor_.find(costKey);
    if (factorIt == dragFactor_.end() && dragging) {
        // Without a full frame's cost, what the refinement under way forecasts (its work so far
        // over its progress: ssm-gbp06's first refinement on plant takes ~80 frames, a drag may
        // start before); without either, the divisor the drag renderer was warmed at
        // (compileShaders): its textures are that size. Sized for 60% of the budget.
        const double estimate = knownCost > 0.0 ? knownCost
                                : refineSize_ == full && refineProgress_ > 0.05 && refineProgress_ < 1.0
                                    ? refineWorkMs_ / refineProgress_ : -1.0;
        // The light-space passes cost the same at any size (ssm-gbp06's HSM ~10 ms): the rest of
        // the frame is what the divisor divides.
        double lightSpace = 0.0;
        for (const PassRecord& r : renderer_->graph().records())
            if (r.technique == costKey && !renderer_->bandedPasses().count(r.name) && !r.times.empty())
                lightSpace += r.times.back().second;
        const double room = std::max(0.3 * budget, 0.6 * budget - lightSpace);
        const int initial = estimate > 0.0 ? int(std::ceil(std::sqrt(std::max(0.0, estimate - lightSpace) / room)))
                            : software_ ? kWarmDivisor : 1;
        int start = std::clamp(initial, 1, std::max(1, state_.reduceFactor));
        // A size the drag renderer has textures for when one is as small (down to the size it is
        // warmed at): a resize at the drag's first frame costs more than its render (40 ms to
        // 512x304); the divisor then steps down as the frames allow.
        if (start > 1) {
            const int cached = cachedPreviewDivisor(full, start, std::min(std::max(2 * start, int(kWarmDivisor)), std::max(1, state_.reduceFactor)));
            if (cached > 0) start = cached;
        }
        factorIt = dragFactor_.emplace(costKey, start).first;
    }
    int notDragging = 1;  // no divisor yet: this frame does not drag
    int& dragFactor = factorIt == dragFactor_.end() ? notDragging : factorIt->second;
    dragFactor = std::clamp(dragFactor, 1, std::max(1, state_.reduceFactor));
    bool reduce = false;
    int factor = 1;
    if (!shot && state_.reduceWhileDragging) {
        if (dragging && dragFactor > 1) {
            reduce = true;
            factor = dragFactor;
        } else if (!dragging && knownCost > budget && previewVersion_ != version_ && refineVersion_ != version_) {
            reduce = true;  // a preview of the change first (sized by the last full frame's cost), then the refinement
            factor = std::clamp(int(std::ceil(std::sqrt(knownCost / budget))), 2, std::max(2, state_.reduceFactor));
            // At a size the drag renderer has textures for, or none: a first resize to a size costs
            // more than the preview (pcf's preview at 1/2 on plant: 16 ms to render, 60 ms in all);
            // then the view keeps its last picture while the change is refined.
            const int cached = cachedPreviewDivisor(full, factor, std::max(2, state_.reduceFactor));
            if (cached > 0) factor = cached;
            else reduce = false;
        }
    }
    const glm::ivec2 size = reduce ? glm::max(glm::ivec2(1), full / factor) : full;
    if (renderer_->width() != full.x || renderer_->height() != full.y) {
        renderer_->resize(full.x, full.y);
        raytrace_.resizeRenderer(full.x, full.y);
        // The drag renderer at the new view's 1/kWarmDivisor too (its frame textures, a few ms):
        // a drag's first frame can start there instead of paying for a resize.
        if (preview_.renderer) {
            const glm::ivec2 warm = glm::max(glm::ivec2(1), full / kWarmDivisor);
            preview_.renderer->resize(warm.x, warm.y);
            previewSizes_.insert({warm.x, warm.y});
        }
    }
    if (reduce && !dragging) previewVersion_ = version_;
    const std::string rendered = showsReference() ? "hard" : state_.technique;
    const glm::ivec2 previewBefore = preview_.renderer ? glm::ivec2(preview_.renderer->width(), preview_.renderer->height()) : glm::ivec2(0);
    auto syncStart = clock::now();
    Renderer& target = reduce ? syncMirror(preview_, rendered, state_.params, size) : *renderer_;
    // A frame right after a resize pays for new textures: it says nothing about the divisor, but
    // what the textures cost a pixel (a step down the divisors may pay it once).
    const bool previewResized = reduce && previewBefore != size;
    if (previewResized && !previewSizes_.count({size.x, size.y}) && size.x * size.y > 10000)
        previewAllocMsPerPixel_ = 0.5 * previewAllocMsPerPixel_ + 0.5 * msSince(syncStart) / double(size.x * size.y);
    if (reduce) previewSizes_.insert({size.x, size.y});

    // The ray tracer's worker stops as soon as the state it traces is gone (a drag's first frame),
    // before this frame renders: its rays would be thrown away, and on two cores they slow the
    // drag's frames.
    if (referenceVersion_ != version_) raytrace_.pauseIfStale(*scene_, state_.camera, state_.lights, full.x, full.y,
                                                             state_.time, state_.referenceRays);
    auto t0 = clock::now();
    const std::set<std::string> outputs = {"image", "visibility"};
    const bool whole = shot || reduce || dragging;  // a drag's frames render whole (full size with --no-reduce)
    if (whole) {
        target.renderFrame(frameIndex_, outputs);
        if (!reduce) refineProgress_ = 1.0;
    } else {
        refineProgress_ = renderer_->refineFrame(frameIndex_, outputs, budget);
    }
    glFinish();
    renderMs_ = msSince(t0);
    reduced_ = reduce;
    if (dragging && !shot && renderMs_ > 0.5 && !previewResized) {
        // Adapt the drag's divisor: up as soon as a frame exceeds the budget, down when the next
        // smaller divisor would still leave a third of the budget (hysteresis: no size flicker).
        const double f = double(factor);
        // Up in proportion to the overrun (not its root: a drag frame's light-space passes cost the
        // same at any size, so the area is only part of it).
        if (renderMs_ > budget) dragFactor = std::min(std::max(1, state_.reduceFactor), int(std::ceil(f * renderMs_ / budget)));
        // Down when the larger frame would still leave a third of the budget, and this once with
        // the textures of a size the drag renderer has not been at yet (a first resize costs
        // 35-40 ms at 512x304 on llvmpipe, ~0.25 us a pixel; sizes it has been at are kept).
        else if (factor > 1) {
            const double larger = renderMs_ * (f * f) / ((f - 1) * (f - 1));
            const glm::ivec2 next = glm::max(glm::ivec2(1), full / (factor - 1));
            const double allocate = cachedPreviewDivisor(full, factor - 1, factor - 1) > 0 ? 0.0 : previewAllocMsPerPixel_ * next.x * next.y;
            if (larger < 0.67 * budget && larger + allocate < budget) dragFactor = factor - 1;
        }
    }
    if (!reduce) {
        if (refineVersion_ != version_ || refineSize_ != size) {  // a new frame to make: its work starts at 0
            refineVersion_ = version_;
            refineSize_ = size;
            refineWorkMs_ = 0.0;
        }
        refineWorkMs_ += renderMs_;
        if (refineProgress_ >= 1.0 && refineWorkMs_ > 1.0) {
            frameCostMs_[costKey] = refineWorkMs_;  // what this change cost at full size
            refineWorkMs_ = 0.0;
        }
    }
    double spent = renderMs_;

    bool compareComplete = true;
    if (state_.compare == WindowState::Compare::Technique) {
        auto c0 = clock::now();
        Renderer& other = syncMirror(reduce ? comparePreview_ : compare_, state_.compareTechnique, {}, size);
        if (shot || reduce) other.renderFrame(frameIndex_, {"image"});
        else compareComplete = other.refineFrame(frameIndex_, {"image"}, std::max(1.0, budget - spent)) >= 1.0;
        spent += msSince(c0);
    }
    // A reduced frame (a drag's, or a change's preview) is never the complete frame, whatever the
    // last refinement reached: the reference, the metrics and a script's wait-reference wait for
    // the change's own full frame.
    imageComplete_ = !reduce && refineProgress_ >= 1.0 && compareComplete;

    if (!referenceNeeded() && !showsReference()) {
        if (reference_.active()) reference_.cancel();
        raytrace_.pause();
    } else if (!interacting() && imageComplete_ && pendingShots_.empty() &&
               (std::chrono::duration<double>(clock::now() - lastInput_).count() > 0.5 || scriptWaitReference_ > 0)) {
        // Half a second without input first (a pause between two drags should not wait for a
        // sample), and only once the technique's frame is complete: the reference gets what is left
        // of the budget, each of its samples refined in slices too.
        const auto c1 = clock::now();
        syncReference(full);
        referenceVersion_ = version_;
        // The one the view shows first, then the reference (the ray tracer's step only uploads a
        // finished batch: its rays run on the worker thread).
        // A frame that showed a new batch of rays (an upload and a full-size shading) leaves the
        // reference for the next one.
        ProgressiveSource* first = shownSource();
        const int shownWork = first ? first->step(std::max(1.0, budget - spent - msSince(c1))) : 0;
        // The reference only with 2 ms left at least (a slice overshoots its share by a few ms).
        const double left = budget - spent - msSince(c1);
        if (referenceNeeded() && &ref() != first && !(first == &raytrace_ && shownWork > 0) && left > 2.0)
            ref().step(left);
    }
    updateMetrics();
    stepAccuracyCompare();
}

void Window::updateMetrics() {
    // A technique view showing a progressive reference is measured once it is complete (raytraced
    // against reference: intro's "two references agree"); against itself, not at all.
    const ProgressiveSource* shown = shownSource();
    if (!ref().complete() || referenceVersion_ != version_ || reduced_ || !imageComplete_ || shown == &ref() ||
        (shown && !shown->complete()))
        return;
    if (metricsGeneration_ == ref().generation() && metricsVersion_ == version_) return;
    Image test = shown ? shown->visibility() : renderer_->visibility();
    Image reference = ref().visibility();
    if (test.width != reference.width || test.height != reference.height) return;
    metricsAll_ = computeMetrics(test, reference);
    std::vector<uint8_t> mask = penumbraMask(reference);
    metricsPenumbra_ = computeMetrics(test, reference, &mask);
    metricsGeneration_ = ref().generation();
    metricsVersion_ = version_;
    recordAccuracyPoint();
}

// The technique view is composed (present.frag: split, error, sRGB encoding) into a cached RGBA8
// image at the render's resolution, only when what it shows changed, then scaled to the window with
// a blit: on llvmpipe a full-window shader pass per frame cost more than a reduced render.
void Window::present() {
    glm::ivec2 fb = renderSize();
    const glm::ivec2 window = framebufferSize();
    const Renderer& shown = shownRenderer();
    glm::ivec2 size(shown.width(), shown.height());
    bool referenceShown = ref().active() && ref().done() > 0 && referenceVersion_ == version_;
    // The technique view showing a progressive reference: its sums, once it has a first sample.
    const ProgressiveSource* source = shownSource();
    const bool sourceShown = source && source->active() && source->done() > 0 && referenceVersion_ == version_;
    GLuint a = shown.imageTexture().id(), b = a;
    float scaleA = 1.0f, scaleB = 1.0f;
    int mode = 0;
    if (sourceShown) {
        a = source->imageSum().id();
        scaleA = source->normalization();
        size = glm::ivec2(source->imageSum().width(), source->imageSum().height());
    }
    if (state_.errorView) {
        if (referenceShown) {
            a = sourceShown ? source->visibilitySum().id() : shown.pool().find("frame/visibility")->texture.id();
            scaleA = sourceShown ? source->normalization() : 1.0f;
            b = ref().visibilitySum().id();
            scaleB = ref().normalization();
            mode = 2;
        }
    } else if (state_.compare == WindowState::Compare::Reference && referenceShown) {
        b = ref().imageSum().id();
        scaleB = ref().normalization();
        mode = 1;
    } else if (state_.compare == WindowState::Compare::Technique && shownCompare()) {
        b = shownCompare()->imageTexture().id();
        mode = 1;
    }
    if (mode != 0) size = fb;  // two images (possibly of two sizes) meet at the split: compose at window size
    // The reference's progress changes the picture only where the reference is shown (a progressive
    // source shown as the technique counts through its own done() below: raytraced shown beside a
    // hidden shadow-map reference is not re-composed at each of the reference's samples).
    const bool referenceInView = mode == 2 || (mode == 1 && state_.compare == WindowState::Compare::Reference);
    std::vector<double> key = {double(version_), double(frameIndex_), double(a), double(b), double(mode),
                               double(size.x), double(size.y), state_.split, state_.errorScale,
                               referenceInView ? double(ref().done()) : 0.0,
                               referenceInView ? double(ref().generation()) : 0.0,
                               source ? double(source->done()) : 0.0, source ? double(source->generation()) : 0.0,
                               renderMs_ > 0.5 ? double(++presentCount_) : 0.0};
    // While the full-size frame is refined over several frames its textures are half old, half
    // new: the view keeps the last complete picture (a reduced preview, scaled up) until it is done.
    const bool keep = !imageComplete_ && viewCache_;
    if (keep) size = cacheSize_;
    // The cache has the view's full size; a reduced picture is composed into its lower-left corner
    // (reallocating it at every size a drag takes cost ~40 ms a time on llvmpipe).
    const glm::ivec2 capacity = glm::max(fb, size);
    if (!keep && (!viewCache_ || viewCache_.width() < capacity.x || viewCache_.height() < capacity.y ||
                  viewCache_.width() > 2 * capacity.x || viewCache_.height() > 2 * capacity.y)) {
        viewCache_ = Texture::create2D(capacity.x, capacity.y, Format::RGBA8);
        viewCacheFbo_ = Framebuffer({&viewCache_}, nullptr);
        presentKey_.clear();
        // A scaled, filtered blit into the window (a drag's reduced frames) once now, 2x2 to a
        // pixel the clear below paints over: llvmpipe builds that blit's shader at its first use,
        // 35-60 ms in the first frame of the first drag otherwise.
        glBlitNamedFramebuffer(viewCacheFbo_.id(), 0, 0, 0, 2, 2, 0, 0, 1, 1, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    }
    cacheSize_ = size;
    composeMs_ = 0.0;
    if (!keep && key != presentKey_) {
        const auto c0 = clock::now();
        viewCacheFbo_.bind(size.x, size.y);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_BLEND);
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_STENCIL_TEST);
        glDisable(GL_CULL_FACE);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        present_.use();
        glBindTextureUnit(0, a);
        glBindTextureUnit(1, b);
        present_.set("imageA", 0);
        present_.set("imageB", 1);
        present_.set("mode", mode);
        present_.set("split", state_.split);
        present_.set("viewSize", glm::vec2(size));
        present_.set("errorScale", state_.errorScale);
        present_.set("scaleA", scaleA);
        present_.set("scaleB", scaleB);
        drawFullscreenTriangle();
        glBindTextureUnit(0, 0);
        glBindTextureUnit(1, 0);
        presentKey_ = key;
        composedVersion_ = version_;
        glFinish();  // timed here, not in the blit after it
        composeMs_ = msSince(c0);
        composeCostMs_ = std::max(composeMs_, 0.9 * composeCostMs_);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, window.x, window.y);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0.09f, 0.10f, 0.12f, 1.0f);  // the regions around the technique view
    glClear(GL_COLOR_BUFFER_BIT);
    // Into the technique view's region (GL's rows count from the bottom).
    const glm::vec2 scale = glm::vec2(window) / windowSize();
    const int x0 = int(std::lround(layout_.technique.x * scale.x));
    const int y1 = window.y - int(std::lround(layout_.technique.y * scale.y));
    glBlitNamedFramebuffer(viewCacheFbo_.id(), 0, 0, 0, size.x, size.y, x0, y1 - fb.y, x0 + fb.x, y1, GL_COLOR_BUFFER_BIT,
                           size == fb ? GL_NEAREST : GL_LINEAR);
}

void Window::drawOverlay() {
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    // Everything here is drawn over the technique view, in its region, clipped to it.
    const LayoutRect& view = layout_.technique;
    const glm::vec2 origin(view.x, view.y);
    glm::vec2 size(std::max(view.w, 1.0f), std::max(view.h, 1.0f));
    float aspectRatio = size.x / size.y;
    float s = state_.uiScale;
    draw->PushClipRect(ImVec2(view.x, view.y), ImVec2(view.right(), view.bottom()), true);
    auto project = [&](const glm::vec3& p) -> std::optional<glm::vec2> {
        auto q = projectToWindow(state_.camera, aspectRatio, p, size);
        if (q) *q += origin;
        return q;
    };
    auto line = [&](const glm::vec3& p, const glm::vec3& q, ImU32 colour, float width) {
        auto a = project(p), b = project(q);
        if (a && b) draw->AddLine(ImVec2(a->x, a->y), ImVec2(b->x, b->y), colour, width);
    };
    if (state_.showLight) {
        for (size_t i = 0; i < state_.lights.size(); ++i) {
            const Light& l = state_.lights[i];
            bool selected = int(i) == state_.lightIndex;
            ImU32 colour = selected ? rgba(255, 220, 60) : rgba(200, 200, 200, 200);
            std::vector<glm::vec3> outline = lightOutline(l);
            for (size_t k = 0; k < outline.size(); ++k) line(outline[k], outline[(k + 1) % outline.size()], colour, 2.0f * s);
            auto c = project(l.position);
            const bool inView = c && c->x >= view.x && c->y >= view.y && c->x < view.right() && c->y < view.bottom();
            if (inView) {
                draw->AddCircleFilled(ImVec2(c->x, c->y), 4.0f * s, colour);
                draw->AddCircle(ImVec2(c->x, c->y), 7.0f * s, rgba(0, 0, 0, 160), 0, 1.5f * s);
            } else {
                // Outside the view (or behind the camera): an arrow at the view's edge points to it.
                const glm::vec4 v = state_.camera.viewFromWorld() * glm::vec4(l.position, 1.0f);
                glm::vec2 dir(v.x, -v.y);
                if (glm::length(dir) < 1e-6f) dir = glm::vec2(0.0f, -1.0f);
                dir = glm::normalize(dir);
                const glm::vec2 centre = origin + 0.5f * size;
                const glm::vec2 half = 0.5f * size - glm::vec2(22.0f * s);
                const float t = std::min(std::abs(dir.x) > 1e-6f ? half.x / std::abs(dir.x) : 1e30f,
                                         std::abs(dir.y) > 1e-6f ? half.y / std::abs(dir.y) : 1e30f);
                const glm::vec2 tip = centre + dir * std::max(t, 0.0f);
                const glm::vec2 side(-dir.y, dir.x);
                const glm::vec2 a = tip - dir * (16.0f * s) + side * (8.0f * s), b = tip - dir * (16.0f * s) - side * (8.0f * s);
                draw->AddTriangleFilled(ImVec2(tip.x, tip.y), ImVec2(a.x, a.y), ImVec2(b.x, b.y), colour);
                const glm::vec2 text = tip - dir * (30.0f * s) - glm::vec2(14.0f * s, 7.0f * s);
                const std::string name = state_.lights.size() > 1 ? "light " + std::to_string(i) : "light";
                draw->AddText(ImVec2(text.x, text.y), colour, name.c_str());
            }
            if (state_.showFrustum && l.castsShadows) {
                LightView v = fitLightView(l, l.position, scene_->bounds(state_.time));
                std::vector<glm::vec3> c = frustumCorners(l.position, l, v.tanHalfFov, v.nearZ, v.farZ);
                ImU32 fc = rgba(90, 200, 255, 200);
                for (int k = 0; k < 4; ++k) {
                    line(c[k], c[(k + 1) % 4], fc, 1.5f * s);
                    line(c[4 + k], c[4 + (k + 1) % 4], fc, 1.5f * s);
                    line(l.position, c[4 + k], fc, 1.0f * s);
                }
            }
        }
    }
    if (state_.compare != WindowState::Compare::None && !state_.errorView) {
        float x = origin.x + state_.split * size.x;
        draw->AddLine(ImVec2(x, origin.y), ImVec2(x, origin.y + size.y), rgba(255, 255, 255, 220), 2.0f * s);
        draw->AddCircleFilled(ImVec2(x, origin.y + size.y * 0.5f), 8.0f * s, rgba(255, 255, 255, 220));
        // Which side is which, on the image: the left technique's name, the right one's.
        const std::string right = state_.compare == WindowState::Compare::Reference ? state_.referenceTechnique : state_.compareTechnique;
        auto label = [&](const std::string& text, float atX, bool alignRight) {
            const ImVec2 t = ImGui::CalcTextSize(text.c_str());
            const float pad = 4.0f * s;
            const float x0 = alignRight ? atX - t.x - 3.0f * pad : atX + 2.0f * pad;
            // At the view's bottom edge: the light's edge arrow points up from the top one (a light
            // above the view, as on plant) and would touch labels there.
            const float y0 = origin.y + size.y - t.y - 2.0f * pad - 6.0f * s;
            draw->AddRectFilled(ImVec2(x0, y0), ImVec2(x0 + t.x + 2 * pad, y0 + t.y + 2 * pad), rgba(0, 0, 0, 170), 3.0f * s);
            draw->AddText(ImVec2(x0 + pad, y0 + pad), rgba(255, 255, 255), text.c_str());
        };
        label(state_.technique, x, true);
        label(right, x, false);
    }
    if (state_.pickedPixel) {
        glm::ivec2 fb = renderSize();
        glm::vec2 p = origin + (glm::vec2(*state_.pickedPixel) + 0.5f) * size / glm::vec2(fb);
        ImU32 c = rgba(255, 60, 200);
        draw->AddLine(ImVec2(p.x - 10 * s, p.y), ImVec2(p.x - 3 * s, p.y), c, 2.0f * s);
        draw->AddLine(ImVec2(p.x + 3 * s, p.y), ImVec2(p.x + 10 * s, p.y), c, 2.0f * s);
        draw->AddLine(ImVec2(p.x, p.y - 10 * s), ImVec2(p.x, p.y - 3 * s), c, 2.0f * s);
        draw->AddLine(ImVec2(p.x, p.y + 3 * s), ImVec2(p.x, p.y + 10 * s), c, 2.0f * s);
    }
    draw->PopClipRect();
}

double Window::frame() {
    auto t0 = clock::now();
    runScriptStep();

    static float appliedScale = 0.0f;
    if (appliedScale != state_.uiScale) {
        ImGuiIO& io = ImGui::GetIO();
        io.Fonts->Clear();
        ImFontConfig config;
        config.SizePixels = std::round(13.0f * state_.uiScale);
        io.Fonts->AddFontDefault(&config);
        ImGui_ImplOpenGL3_DestroyFontsTexture();
        ImGui_ImplOpenGL3_CreateFontsTexture();
        ImGuiStyle style;
        ImGui::StyleColorsDark(&style);
        style.WindowRounding = 4.0f;
        style.ScaleAllSizes(state_.uiScale);
        ImGui::GetStyle() = style;
        appliedScale = state_.uiScale;
    }
    auto phase = clock::now();
    auto lap = [&](double& ms) {
        glFinish();
        ms = msSince(phase);
        phase = clock::now();
    };
    syncViewList();
    updateLayout();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    drawUi();
    {
        auto now = clock::now();
        double seconds = lessonClock_ == clock::time_point{} ? 0.0 : std::chrono::duration<double>(now - lessonClock_).count();
        lessonClock_ = now;
        drawLesson(seconds);
    }
    drawAccuracyChart();
    lap(phaseMs_[0]);
    renderViews();
    finishPendingCheck();
    updateViews();
    lap(phaseMs_[1]);
    present();
    drawOverlay();
    lap(phaseMs_[2]);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    lap(phaseMs_[3]);
    for (const std::string& path : pendingShots_) takeScreenshot(path);
    pendingShots_.clear();
    glfwSwapBuffers(window_);
    lap(phaseMs_[4]);
    frameMs_ = msSince(t0);
    uiFps_ = uiFps_ == 0.0 ? 1000.0 / frameMs_ : 0.9 * uiFps_ + 0.1 * (1000.0 / frameMs_);
    return frameMs_;
}

void Window::takeScreenshot(const std::string& path) {
    glm::ivec2 fb = framebufferSize();
    std::vector<unsigned char> rgb(size_t(fb.x) * fb.y * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, fb.x, fb.y, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    Image shot(fb.x, fb.y, 3);
    for (int y = 0; y < fb.y; ++y)
        for (int x = 0; x < fb.x; ++x)
            for (int c = 0; c < 3; ++c) shot.at(x, y, c) = rgb[(size_t(fb.y - 1 - y) * fb.x + x) * 3 + c] / 255.0f;
    try {
        OutputSet outputs;
        if (endsWith(path, ".pfm")) writePFM(outputs.stage(path), shot);  // for tests: no PNG reader in the core
        else writePNG(outputs.stage(path), shot);
        outputs.commit();
        if (scriptDone_) setStatus("screenshot " + path);  // a script's shots stay out of the next one
        std::printf("shadowlab window: screenshot %s (%dx%d)\n", path.c_str(), fb.x, fb.y);
        std::fflush(stdout);
    } catch (const std::exception& e) {
        setStatus(std::string("screenshot failed: ") + e.what(), true);
    }
}

std::string Window::lastFrameReport() const {
    glm::ivec2 size = renderer_ ? glm::ivec2(shownRenderer().width(), shownRenderer().height()) : glm::ivec2(0);
    nlohmann::json j{{"frame_ms", frameMs_}, {"render_ms", renderMs_}, {"reduced", reduced_},
                     {"refine_progress", refineProgress_}, {"complete", imageComplete_ && !reduced_},
                     {"budget_ms", renderBudgetMs()},
                     {"interacting", interacting()}, {"render_size", {size.x, size.y}},
                     {"reference_samples", ref().done()}, {"reference_total", ref().total()},
                     {"shown_samples", shownSource() && shownSource()->active() ? shownSource()->done() : 0},
                     {"shown_total", shownSource() && shownSource()->active() ? shownSource()->total() : 0},
                     {"reference_technique", state_.referenceTechnique},
                     {"window", {windowSize().x, windowSize().y}}, {"layout", layout_.toJson()},
                     {"enlarged_view", state_.enlargedView},
                     {"technique", state_.technique},
                     {"phases_ms", {{"ui", phaseMs_[0]}, {"render_and_reference", phaseMs_[1]}, {"present", phaseMs_[2]},
                                    {"imgui_draw", phaseMs_[3]}, {"swap", phaseMs_[4]}}}};
    // Each open view's rendered frame (its cell's size, or the technique view's when enlarged).
    nlohmann::json frames = nlohmann::json::object();
    for (const auto& v : views_)
        if (v->frame) frames[v->name] = {v->frame->width(), v->frame->height()};
    j["view_frames"] = frames;
    if (lesson_) {  // the lesson panel and its "Next >" button, x y width height in window pixels
        const LessonPanelRects& l = lessonRects_;
        j["lesson_panel"] = {{"panel", {l.panel[0], l.panel[1], l.panel[2], l.panel[3]}},
                             {"next_button", {l.next[0], l.next[1], l.next[2], l.next[3]}}};
    }
    if (!state_.lights.empty()) {
        const glm::vec3& p = state_.lights[size_t(state_.lightIndex)].position;
        j["light"] = {p.x, p.y, p.z};
    }
    return j.dump();
}

// ---- entry points -------------------------------------------------------------------------------------

namespace {

void* glfwLoader(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

std::string lastGlfwError;
void onGlfwError(int, const char* message) { lastGlfwError = message ? message : "unknown GLFW error"; }

Window* windowOf(GLFWwindow* w) { return static_cast<Window*>(glfwGetWindowUserPointer(w)); }

void onKey(GLFWwindow* w, int key, int, int action, int mods) {
    if (action == GLFW_RELEASE || ImGui::GetIO().WantCaptureKeyboard) return;
    if (Window* win = windowOf(w)) win->key(key, mods);
}

void onMouseButton(GLFWwindow* w, int button, int action, int mods) {
    Window* win = windowOf(w);
    if (!win) return;
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    if (action == GLFW_PRESS && ImGui::GetIO().WantCaptureMouse) return;
    win->mouseButton(button, action == GLFW_PRESS, mods, glm::vec2(float(x), float(y)));
}

void onCursor(GLFWwindow* w, double x, double y) {
    if (Window* win = windowOf(w)) win->mouseMove(glm::vec2(float(x), float(y)));
}

void onScroll(GLFWwindow* w, double, double dy) {
    if (ImGui::GetIO().WantCaptureMouse) return;
    if (Window* win = windowOf(w)) win->scroll(dy);
}

size_t indexOf(const std::vector<std::string>& list, const std::string& value, const std::string& flag) {
    for (size_t i = 0; i < list.size(); ++i)
        if (list[i] == value) return i;
    std::string all;
    for (const std::string& v : list) all += (all.empty() ? "" : ", ") + v;
    throw InputError("window: " + flag + ": unknown value '" + value + "' (expected one of: " + all + ")");
}

int runWindowImpl(const std::vector<std::string>& args, bool fallback) {
    Options opts("window", args, 0,
                 {"--scene", "--technique", "--size", "--screenshot", "--frames", "--script", "--report", "--ui-scale",
                  "--lesson", "--max-memory-mb"},
                 {"--no-reduce", "--present"});
    if (!opts.positional().empty()) throw InputError("window: unexpected argument '" + opts.positional()[0] + "'");
    WindowState state;
    state.scene = opts.get("--scene", "square-occluder");
    if (!isGltf(state.scene) && !isRandomSceneName(state.scene)) resolveScenePath(state.scene);  // InputError naming a missing scene
    std::vector<std::string> techniques;
    for (const TechniqueDesc* d : allTechniques()) techniques.push_back(d->id);
    state.technique = techniques[indexOf(techniques, opts.get("--technique", "pcf"), "--technique")];
    if (state.technique == "raytraced" || state.technique == "reference") state.referenceTechnique = state.technique;
    int width = 1024, height = 768;
    if (opts.has("--size")) parseSize(opts.get("--size"), width, height);
    std::string screenshot = opts.get("--screenshot");
    if (!screenshot.empty()) checkOutputPath("--screenshot", screenshot);
    int maxFrames = opts.getInt("--frames", screenshot.empty() ? 0 : 3, 0, 1000000);
    state.uiScale = opts.getFloat("--ui-scale", 1.0f, 0.5f, 4.0f);
    state.reduceWhileDragging = !opts.has("--no-reduce");
    state.presentation = opts.has("--present");
    std::string reportPath = opts.get("--report");
    if (!reportPath.empty()) checkOutputPath("--report", reportPath);
    std::deque<ScriptCommand> script;
    if (opts.has("--script")) script = parseScript(opts.get("--script"));
    // A lesson is read and checked before the window opens: a bad one is refused (file:line, exit 2).
    std::optional<Lesson> lesson;
    if (opts.has("--lesson")) {
        lesson = loadLesson(opts.get("--lesson"));
        state.scene = lesson->steps.front().state.scene;
    }

    // The memory estimate the commands apply, for the first technique at the window's size, before
    // the window opens (later switches are checked as they are asked for: Window::memoryRefusal).
    state.maxMemoryMB = opts.getInt("--max-memory-mb", kDefaultMaxMemoryMB, 16, 1 << 20);
    if (state.technique != "raytraced" && state.technique != "reference") {
        RenderOptions first;
        first.width = width;
        first.height = height;
        first.technique = lesson ? lesson->steps.front().state.technique : state.technique;
        if (lesson) first.sets = lesson->steps.front().state.paramTexts();
        Scene scene = loadScene(state.scene);
        if (lesson) scene.lights = lesson->steps.front().state.lights;
        try {
            checkRenderMemory(scene, first, opts);
        } catch (const InputError& e) {
            throw InputError("window: " + first.technique + " at " + std::to_string(width) + "x" + std::to_string(height) +
                             ": " + e.what());
        }
    }

    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        std::string reason = "no display: " + lastGlfwError;
        if (fallback) return runHeadlessFallback(reason);
        std::fprintf(stderr,
                     "shadowlab: cannot open a window (%s). Run it under a display (or `xvfb-run -a shadowlab "
                     "window ...`), or use the headless commands: shadowlab render --scene S --out img.png\n",
                     reason.c_str());
        return 2;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
    GLFWwindow* window = glfwCreateWindow(width, height, "shadowlab", nullptr, nullptr);
    if (!window) {
        std::string reason = "no OpenGL 4.5 core window: " + lastGlfwError;
        glfwTerminate();
        if (fallback) return runHeadlessFallback(reason);
        throw InternalError("GLFW: cannot create an OpenGL 4.5 core window (" + lastGlfwError + ")");
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(0);  // frame times are the work's, not the display's; the UI is not throttled
    initializeGLForCurrentContext(glfwLoader);
    const GLubyte* rendererName = glGetString(GL_RENDERER);
    bool software = rendererName && (std::string(reinterpret_cast<const char*>(rendererName)).find("llvmpipe") !=
                                     std::string::npos);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini written into the working folder
    glfwSetKeyCallback(window, onKey);
    glfwSetMouseButtonCallback(window, onMouseButton);
    glfwSetCursorPosCallback(window, onCursor);
    glfwSetScrollCallback(window, onScroll);
    ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains to the callbacks above
    ImGui_ImplOpenGL3_Init("#version 450 core");

    int result = 0;
    {
        std::unique_ptr<Window> win;
        try {
            win = std::make_unique<Window>(window, state, software);
            if (lesson) win->openLesson(std::move(*lesson));
            if (opts.has("--script")) win->setScript(std::move(script), opts.get("--script"));
        } catch (...) {
            ImGui_ImplOpenGL3_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
            releaseExternalContextObjects();
            glfwDestroyWindow(window);
            glfwTerminate();
            throw;
        }
        glfwSetWindowUserPointer(window, win.get());
        nlohmann::json report = nlohmann::json::array();
        for (int shown = 0; !glfwWindowShouldClose(window); ++shown) {
            glfwPollEvents();
            bool last = maxFrames > 0 && shown + 1 >= maxFrames;
            if (last && !screenshot.empty()) win->screenshot(screenshot);
            win->frame();
            if (!reportPath.empty()) report.push_back(nlohmann::json::parse(win->lastFrameReport()));
            if (last || (opts.has("--script") && win->scriptFinished())) glfwSetWindowShouldClose(window, GLFW_TRUE);
        }
        if (!reportPath.empty()) {
            OutputSet outputs;
            std::ofstream(outputs.stage(reportPath)) << nlohmann::json{{"frames", report}}.dump(1) << "\n";
            outputs.commit();
        }
        glfwSetWindowUserPointer(window, nullptr);
        if (win->scriptFailed()) result = 2;
        win.reset();
        if (glDebugState().errors > 0) {
            std::fprintf(stderr, "shadowlab window: %d GL error(s), last: %s\n", glDebugState().errors,
                         glDebugState().lastError.c_str());
            result = 1;
        }
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    releaseExternalContextObjects();
    glfwDestroyWindow(window);
    glfwTerminate();
    return result;
}

}  // namespace

int runWindow(const std::vector<std::string>& args) { return runWindowImpl(args, false); }

// The first lesson (intro) in the window: what a new user should see first.
int runDefault() { return runWindowImpl({"--lesson", "intro"}, true); }

int runHeadlessFallback(const std::string& reason) {
    std::error_code ec;
    fs::path dir = fs::current_path(ec) / "shadowlab-output";
    fs::create_directories(dir, ec);
    if (ec || access(dir.c_str(), W_OK) != 0) {
        dir = fs::temp_directory_path() / ("shadowlab-output-" + std::to_string(getpid()));
        fs::create_directories(dir, ec);
    }
    std::string png = (dir / "square-occluder-pcf.png").string();
    std::string stats = (dir / "square-occluder-pcf.json").string();
    std::printf("shadowlab: no window (%s).\nInstead, rendered the default scene headless (square-occluder, pcf):\n",
                reason.c_str());
    std::fflush(stdout);
    int code = runCommandLine({"render", "--scene", "square-occluder", "--technique", "pcf", "--size", "768x768",
                               "--out", png, "--stats", stats});
    if (code == 0) {
        std::printf("  image: %s\n  stats: %s\nOpen the window on a display (or `xvfb-run -a shadowlab`), or see "
                    "`shadowlab help` for the command line.\n",
                    png.c_str(), stats.c_str());
        return 0;
    }
    std::printf("The headless render failed too (see above); `shadowlab help` lists the commands.\n");
    return 2;
}

}  // namespace shadowlab
