// The window (DESIGN.md sections 1 and 7): the technique view at the window's size with the light
// drawn, panels generated from the technique descriptors, a HUD, a progressive reference computed a
// few light samples per frame, split and error views, mouse camera and light control.
//
// Everything a user, a script or a lesson changes lives in one struct, WindowState; every change
// goes through one method of Window (selectTechnique, setParam, setLight ...), which the panel, the
// keys, the --script runner and (later) the lesson host all call: one code path per action.
//
// Files: window.cpp (loop, rendering, present, screenshots), window_ui.cpp (ImGui panels, HUD, F1),
// window_input.cpp (keys, mouse, --script), window_reference.cpp (progressive reference),
// camera_control.cpp (orbit/pan/zoom and picking math).
#pragma once
#include <chrono>
#include <deque>
#include <glm/glm.hpp>
#include <map>
#include <set>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/compare.h"
#include "chart_accuracy_time.h"
#include "gl/util.h"
#include "graph/renderer.h"
#include "image/image.h"
#include "image/metrics.h"
#include "lesson/lesson.h"
#include "lesson/player.h"
#include "scene/scene.h"
#include "window/layout.h"

struct GLFWwindow;

namespace shadowlab {

// What a resize of one of the window's renderers replaced, kept for a return to that size (the
// layout and the drag's divisor change their sizes back and forth): RenderOptions::spareBytes.
constexpr size_t kSpareBytes = size_t(512) << 20;

class VtkOffscreen;
class RayTracer;
struct Lesson;
class LessonPlayer;
class LessonHost;
class WindowLessonHost;

// What the user sees and has chosen: the single source of truth for the UI, keys, scripts, lessons.
struct WindowState {
    std::string scene;      // a name in assets/scenes, or a path to a .json scene or a .gltf/.glb file
    std::string technique;  // "reference" / "raytraced" show that progressive reference
    std::map<std::string, std::string> params;  // parameters set away from the defaults (key -> value)
    // --max-memory-mb: a technique or parameter whose estimated memory at the render size
    // (estimateRenderBytes, as the commands estimate) is over this is refused in the status line.
    int maxMemoryMB = 4096;
    int lightIndex = 0;     // the light the light controls edit
    Camera camera;          // the current camera (starts at the scene's)
    std::vector<Light> lights;  // the current lights (start at the scene's)
    enum class Compare { None, Reference, Technique };
    Compare compare = Compare::None;
    std::string compareTechnique = "hard";
    float split = 0.5f;      // split position, fraction of the view's width (left: technique)
    bool errorView = false;  // |technique - reference| visibility as a heat map
    float errorScale = 0.25f;  // error shown at full colour
    bool showLight = true;
    bool showFrustum = false;
    std::optional<glm::ivec2> pickedPixel;  // in the technique image, x right, y down from the top
    bool playing = false;                   // animated scenes: time advances
    double time = 0.0;                      // seconds
    bool reduceWhileDragging = true;        // heavy techniques render at a reduced resolution while dragging
    int reduceFactor = 16;                  // at most 1/16 per side (the factor adapts to the frames' cost)
    bool backgroundReference = true;        // accumulate the reference whenever the input is idle
    int referenceSamples = 1024;            // N of `reference` (its descriptor's default)
    // The reference the split, the error view, the metrics and a lesson's check read: "reference"
    // (light samples on the GPU) or "raytraced" (rays on a worker thread). Selecting either as the
    // technique selects it here too.
    std::string referenceTechnique = "reference";
    int referenceRays = 256;                // M of `raytraced` (its descriptor's default)
    // The reference's shadow-map settings away from its defaults (sm_size, bias_const, bias_slope,
    // plane_test): a lesson's `reference reference ...` or the panel with `reference` selected.
    std::map<std::string, std::string> referenceParams;
    float uiScale = 1.0f;
    bool presentation = false;  // presentation mode (--present, F5): one-line bars, large text, wide narration
    bool showPanel = true, showHud = true, showHelp = false, showViews = false;
    bool showAccuracy = false;  // the accuracy-time chart of the settings tried (A)
    std::vector<std::string> openViews;  // VTK views shown in the views panel (viz/views.h names)
    // An open view shown enlarged over the technique view's region ("" for none): its "enlarge"
    // button or the script's `enlarge-view NAME`; "restore" (or `enlarge-view off`) puts it back.
    std::string enlargedView;
};

// Every field a progressive reference depends on (reference.cpp): a difference restarts it.
bool sameLight(const Light& a, const Light& b);
bool sameCamera(const Camera& a, const Camera& b);

// A reference the window accumulates while the input is idle, restarted by any change of what it
// depends on: the progressive `reference` (light samples on the GL thread, in slices of the frame
// budget) or the progressive `raytraced` (rays on a worker thread). The split's reference side, the
// error view, the HUD metrics and a lesson's check read whichever the state selects.
class ProgressiveSource {
public:
    virtual ~ProgressiveSource() = default;
    virtual void cancel() = 0;
    // Work on the GL thread for at most `budgetMs` of wall time; returns the units it completed.
    virtual int step(double budgetMs) = 0;
    virtual bool active() const = 0;
    bool complete() const { return active() && done() >= total(); }
    virtual int done() const = 0;   // units accumulated (light samples, rays per pixel)
    virtual int total() const = 0;
    virtual const char* unit() const = 0;  // "samples", "rays"
    virtual double lastSampleMs() const = 0;  // what the last unit (or batch) cost
    uint64_t generation() const { return generation_; }  // changes on every restart, unique across sources
    virtual Image visibility() const = 0;  // the estimate so far (1 channel; a read-back)
    // The estimate's sums (the mean is sum x normalization()): linear shaded image (RGBA32F) and
    // visibility (R32F).
    virtual const Texture& imageSum() const = 0;
    virtual const Texture& visibilitySum() const = 0;
    virtual float normalization() const = 0;

protected:
    void restarted();  // a new generation
    uint64_t generation_ = 0;
};

// The reference of the current state, accumulated a few light samples per frame: N stratified light
// samples (the same points as the `reference` technique), each a hard shadow of the light at that
// point, weighted by its stratum's area. Any change of the state it depends on restarts it.
class ProgressiveReference : public ProgressiveSource {
public:
    // Restarts when the scene, camera, lights, size or time differ from the running accumulation.
    void sync(const Scene& scene, const Camera& camera, const std::vector<Light>& lights, int width, int height,
              double time, int samples, const std::map<std::string, std::string>& depthParams = {});
    // The `reference` parameters each sample's hard frame takes (the rest is the sample count).
    static bool isDepthParam(const std::string& key);
    void cancel() override;
    // Runs light samples until `budgetMs` of wall time is spent (at least one piece of one sample's
    // frame: a sample that does not fit is refined over several calls); returns how many completed.
    int step(double budgetMs) override;
    bool active() const override { return renderer_ != nullptr; }
    int done() const override { return done_; }
    int total() const override { return total_; }
    const char* unit() const override { return "samples"; }
    double lastSampleMs() const override { return lastSampleMs_; }
    Image visibility() const override;  // the weighted mean so far
    const Texture& imageSum() const override { return imageSum_; }  // alpha = the weights
    const Texture& visibilitySum() const override { return visibilitySum_; }
    float normalization() const override { return weightSum_ > 0.0 ? float(1.0 / weightSum_) : 0.0f; }

private:
    std::unique_ptr<Renderer> renderer_;
    const Scene* scene_ = nullptr;
    Camera camera_;
    std::vector<Light> lights_;
    std::map<std::string, std::string> depthParams_;
    int width_ = 0, height_ = 0, total_ = 0, done_ = 0;
    double time_ = 0.0, weightSum_ = 0.0, lastSampleMs_ = 0.0;
    bool sampleStarted_ = false;  // sample done_'s lights are set; its frame may span calls
    double sampleWeight_ = 0.0, sampleMs_ = 0.0;
    Texture imageSum_, visibilitySum_;
    Framebuffer sums_;
    ShaderProgram accumulate_;
};

// `raytraced` in the window (issue 18): the M stratified rays per pixel of the `raytraced` technique
// (RayTracer, the same rays and weights), traced in batches of rays per pixel on a worker thread
// while the GL thread keeps the UI's rate. The G-buffer is read back once per restart; after each
// batch the GL thread uploads every light's estimate and re-shades with the shade pass's own math
// (Renderer::shadeWith). Complete, its visibility equals `render --technique raytraced` (test:
// WindowRaytrace.*). The worker runs one thread at a lower priority.
class ProgressiveRaytrace : public ProgressiveSource {
public:
    ProgressiveRaytrace();
    ~ProgressiveRaytrace() override;  // stops and joins the worker
    // Restarts when the scene, camera, lights, size, time or M differ from the running trace.
    void sync(const Scene& scene, const Camera& camera, const std::vector<Light>& lights, int width, int height,
              double time, int rays);
    void cancel() override;
    // Stops the worker and forgets the estimate but keeps the renderer (made at scene load, so
    // selecting raytraced later does not upload the scene in a UI frame); the next sync restarts.
    void pause();
    // pause() when the running trace is not of this state.
    void pauseIfStale(const Scene& scene, const Camera& camera, const std::vector<Light>& lights, int width, int height,
                      double time, int rays);
    // The paused renderer to the view's size (when the window re-lays out, whose frame pays for
    // reallocating the others anyway), so selecting raytraced later reallocates nothing.
    void resizeRenderer(int width, int height);
    // The G-buffer (in slices of the budget) and the worker's start after a restart; then each
    // batch the worker finished, uploaded and shaded. Returns the batches shown.
    int step(double budgetMs) override;
    bool active() const override { return renderer_ != nullptr && live_; }
    int done() const override { return shown_; }
    int total() const override { return total_; }
    const char* unit() const override { return "rays"; }
    double lastSampleMs() const override;
    Image visibility() const override;
    const Texture& imageSum() const override;
    const Texture& visibilitySum() const override;
    float normalization() const override { return 1.0f; }
    // Blocks until the trace is complete (a lesson's check): steps, sleeping while the worker works.
    void finish();
    struct Job;  // what the worker reads and publishes (raytrace.cpp)

private:
    bool matches(const Scene& scene, const Camera& camera, const std::vector<Light>& lights, int width, int height,
                 double time, int rays) const;
    // Stops the running worker (it ends at its next row); joins the finished ones, or all (`wait`).
    void stopWorker(bool wait);
    std::unique_ptr<Renderer> renderer_;
    const Scene* scene_ = nullptr;
    Camera camera_;
    std::vector<Light> lights_;
    int width_ = 0, height_ = 0, total_ = 0, rays_ = 0, shown_ = 0;
    double time_ = 0.0;
    bool started_ = false;  // the worker runs for this generation
    bool live_ = false;     // synced and not paused
    int readRows_ = 0;        // the G-buffer's rows read back so far (GL's order, bottom first)
    double msPerRow_ = 0.0;   // what reading one row of both cost
    std::unique_ptr<float[]> rawPositions_, rawNormals_;  // RGBA32F rows being read back
    double lastBatchMs_ = 0.0;
    std::shared_ptr<Job> job_;
    std::thread worker_;
    std::vector<std::pair<std::shared_ptr<Job>, std::thread>> retired_;  // stopped workers not joined yet
    std::shared_ptr<const RayTracer> tracer_;  // the BVH of (scene_, time_), reused by the next restart
    std::vector<Texture> lightVisibility_;     // per light, the estimate uploaded (R32F)
    std::vector<const Texture*> shadeInputs_;  // lightVisibility_ as shadeWith takes it (null: lit)
    int shading_ = 0;            // rays per pixel of the batch being shaded
    int shadeRows_ = 0;          // its rows shaded so far (GL's order); 0: none being shaded
    double msPerShadeRow_ = 0.0; // what shading one row cost
};

struct ScriptCommand {
    int line = 0;
    std::string verb;
    std::vector<std::string> args;
};

class Window {
public:
    Window(GLFWwindow* window, WindowState state, bool software);
    ~Window();

    // ---- actions: the panel, keys, --script and lessons call these (each validates its input and
    // reports a bad value in the status line, never a crash).
    void selectScene(const std::string& nameOrPath);
    void selectTechnique(const std::string& id);
    void setParam(const std::string& key, const std::string& value);
    void resetParam(const std::string& key);
    void resetAllParams();
    void setLight(int index, const Light& light);
    void resetLight();
    void setCamera(const Camera& camera);
    void resetCamera();
    void pickPixel(glm::ivec2 pixel);
    void setCompare(WindowState::Compare compare, const std::string& technique = "");
    void setErrorView(bool on);
    void setSplit(float split);
    void setUiScale(float scale);
    void setPresentation(bool on);  // presentation mode (F5, --present): the UI scale follows the window's height
    void setReferenceSamples(int samples);  // N of the progressive reference (restarts it)
    // One of the reference's shadow-map settings (ProgressiveReference::isDepthParam), checked
    // against the `reference` descriptor; restarts the progressive reference.
    void setReferenceParam(const std::string& key, const std::string& value);
    void cycleTechnique(int step);
    void cycleScene(int step);
    void screenshot(const std::string& path);  // the whole window, UI included, after this frame
    void openView(const std::string& name);     // a VTK view of viz/views.h in the views panel
    void closeView(const std::string& name);
    void enlargeView(const std::string& name);  // "" or "off": none (the view is opened if it is not)
    // ---- lessons (window_lesson.cpp): the player drives the window through the actions above.
    void openLesson(Lesson lesson);  // applies its first step
    // "next", "previous", "restore", "check", "show-me" (the panel's buttons; --script lesson ACTION)
    void lessonAction(const std::string& action);
    const LessonPlayer* lesson() const { return lesson_.get(); }
    // ---- the accuracy-time chart (window_accuracy.cpp): the settings tried against one reference.
    void saveAccuracyPoints(const std::string& path) const;  // JSON (--script save-accuracy FILE)

    // ---- input (window_input.cpp): GLFW callbacks and synthetic events from --script.
    void key(int key, int mods);
    void mouseButton(int button, bool press, int mods, glm::vec2 at);
    void mouseMove(glm::vec2 at);
    void scroll(double dy);
    // --script FILE: parsed up front by parseScript (errors name the file and line), one step per frame.
    void setScript(std::deque<ScriptCommand> script, const std::string& path);
    bool scriptFinished() const { return scriptDone_; }
    bool scriptFailed() const { return scriptFailed_; }

    // One frame: script step, render, present, UI, screenshot. Returns the frame's wall time in ms.
    double frame();

    const WindowState& state() const { return state_; }
    const std::vector<std::string>& techniques() const { return techniques_; }
    const std::vector<std::string>& scenes() const { return scenes_; }
    bool interacting() const;
    // The technique view's size in framebuffer pixels: its region of the layout (window/layout.h).
    glm::ivec2 renderSize() const;
    glm::ivec2 framebufferSize() const;  // the whole window
    const WindowLayout& layout() const { return layout_; }
    std::string lastFrameReport() const;

    static const char* helpText();  // F1: every key and mouse action

private:
    friend struct WindowUi;
    friend class WindowLessonHost;
    bool lessonKey(int key) const;     // a key the open lesson's panel reads (the window ignores it)
    void reportCheck();                // the current step's check in the status line and on stdout
    void finishPendingCheck();         // a check waiting for a progressive reference, once it is complete
    void drawLesson(double seconds);   // the lesson panel, and the step's animation advanced
    void recordAccuracyPoint();        // the current setting's shadow_ms and RMSE (metrics just computed)
    void drawAccuracyChart();
    // The chart's comparison with every setting `auto` chooses among and `auto` at three budgets
    // (bench/compare.h; a lesson's `show accuracy-time`, the chart's button): on, it opens the chart
    // and places one queued setting per frame once the reference is complete (a change of scene,
    // light, camera or size starts again).
    void compareEveryTechnique(bool on);
    void stepAccuracyCompare();
    bool rebuildScene();  // false (status says why) when the scene does not load: the old one stays
    void compileShaders();  // every technique's programs for the scene, before its first frame
    void renderViews();
    void present();
    void drawOverlay();
    void drawUi();
    void drawViewsPanel();
    void runScriptStep();
    void takeScreenshot(const std::string& path);
    void touch() { ++version_; }  // the rendered state changed (scene, technique, parameter, light, camera)
    void noteInput() { lastInput_ = clock::now(); }  // a drag, wheel or arrow key: render reduced for a moment
    void updateMetrics();
    void setStatus(const std::string& text, bool error = false);
    // "" when `technique` with `params` fits the memory limit at the render size; else the reason.
    std::string memoryRefusal(const std::string& technique, const std::map<std::string, std::string>& params) const;
    glm::vec2 windowSize() const;   // the whole window, in window units
    float aspect() const;           // the technique view's
    void updateLayout();            // layout_ from the window's size, the scale and what is open
    void placeRegion(const LayoutRect& r) const;  // the next ImGui window fixed at r
    glm::vec2 toView(glm::vec2 windowPoint) const;  // window units -> the technique view's

    using clock = std::chrono::steady_clock;
    GLFWwindow* window_;
    WindowState state_;
    bool software_;
    std::vector<std::string> techniques_, scenes_;
    std::unique_ptr<Scene> scene_;
    std::unique_ptr<Renderer> renderer_;  // the technique at the view's full size
    // A renderer kept in step with the window's state when it is used (the split's technique, the
    // reduced frames): a frame of its own size, so the full-size renderer is never resized by a
    // drag (on llvmpipe reallocating the frame's textures cost ~0.1 s).
    struct MirrorRenderer {
        std::unique_ptr<Renderer> renderer;
        std::string technique;
        std::map<std::string, std::string> params;
        uint64_t version = ~0ull;
    };
    // Creates or brings `m` to `technique` with `params`, the camera, the lights and `size`.
    Renderer& syncMirror(MirrorRenderer& m, const std::string& technique,
                         const std::map<std::string, std::string>& params, glm::ivec2 size);
    MirrorRenderer preview_, compare_, comparePreview_;
    std::set<std::pair<int, int>> previewSizes_;  // the sizes preview_ has rendered at (its spares)
    // The smallest divisor in [from, to] at which preview_ has rendered at a `full` view, or 0.
    int cachedPreviewDivisor(glm::ivec2 full, int from, int to) const;
    double previewAllocMsPerPixel_ = 0.25e-3;  // what a first resize of preview_ costs a pixel (measured)
    static constexpr int kWarmDivisor = 8;  // the drag renderer's size at scene load: the view's / 8
    const Renderer& shownRenderer() const { return reduced_ ? *preview_.renderer : *renderer_; }
    const Renderer* shownCompare() const {
        return reduced_ ? comparePreview_.renderer.get() : compare_.renderer.get();
    }
    ProgressiveReference reference_;
    ProgressiveRaytrace raytrace_;  // after scene_: destroyed (its worker joined) before the scene
    // The reference state_.referenceTechnique selects: the split's right side, the error view, the
    // metrics, a lesson's check.
    ProgressiveSource& ref() { return state_.referenceTechnique == "raytraced" ? static_cast<ProgressiveSource&>(raytrace_) : reference_; }
    const ProgressiveSource& ref() const { return const_cast<Window*>(this)->ref(); }
    // The technique view shows a progressive reference itself (technique "reference" or "raytraced"):
    // that one, whichever the split compares it with (intro's "two references agree": raytraced
    // against reference).
    bool showsReference() const { return state_.technique == "reference" || state_.technique == "raytraced"; }
    ProgressiveSource* shownSource() {
        if (state_.technique == "raytraced") return &raytrace_;
        return state_.technique == "reference" ? &reference_ : nullptr;
    }
    const ProgressiveSource* shownSource() const { return const_cast<Window*>(this)->shownSource(); }
    bool referenceNeeded() const;  // the split, the error view, the metrics in the background need ref()
    // Brings the progressive sources in use (the shown one, the reference when needed) to the state
    // at `size`; the others stop.
    void syncReference(glm::ivec2 size);
    void setReferenceTechnique(const std::string& id);  // "reference" or "raytraced"
    void setReferenceRays(int rays);                    // M of the progressive ray tracer (restarts it)
    ShaderProgram present_;
    WindowLayout layout_;
    float normalUiScale_ = 1.0f;
    glm::ivec2 pickSize_{0};  // the technique view's size when the pixel was picked
    // The lesson's pick when it is a world point (`pick at X Y Z`): re-projected through the camera
    // when the technique view's size changes (a step opening views shrinks it), so the picked pixel
    // stays on that point, not on the same fraction of an image of another aspect. Any other pick
    // clears it.
    std::optional<LessonPick> lessonPick_;
    bool pressOnLight_ = false;  // a script's drag-light press (input.cpp)  // the UI scale to go back to when presentation mode ends
    Texture errorDummy_;
    Texture viewCache_;          // the composed technique view (sRGB RGBA8), at the render's size
    Framebuffer viewCacheFbo_;
    glm::ivec2 cacheSize_{0};    // the part of viewCache_ the last composition filled
    std::vector<double> presentKey_;  // what the cache shows
    uint64_t presentCount_ = 0;
    // Composing the view (present.frag at the render's size) cost 6-13 ms at 1024x608 on llvmpipe: the frame
    // budget keeps it aside on a frame likely to compose (composeLikely).
    double composeMs_ = 0.0;      // what this frame's composition cost (0: none)
    double composeCostMs_ = 0.0;  // what a composition costs (the last, decaying slowly)
    uint64_t composedVersion_ = ~0ull;  // version_ the cache was last composed at
    int frameIndex_ = 0;
    uint64_t version_ = 0;  // bumps on every change of the state
    clock::time_point lastInput_{};
    bool dragging_ = false;
    enum class Drag { None, Orbit, Pan, Light, Split };
    Drag drag_ = Drag::None;
    glm::vec2 dragLast_{0}, dragStart_{0};
    glm::vec3 dragLightStart_{0}, dragHitStart_{0};
    glm::vec2 mouse_{0};
    bool reduced_ = false;      // this frame rendered at reduced resolution
    // The frame budget (README "The frame budget"): the UI frame aims at kFrameBudgetMs.
    static constexpr double kFrameBudgetMs = 33.0;
    double renderBudgetMs() const;  // what the technique and the reference may spend this frame
    bool composeLikely() const;     // this frame's picture may change: a composition to pay for
    // What the technique view shows when it is not the complete frame: "refining, 40%", "reduced
    // 1/7 while dragging", "preview at 1/7, refining next"; "" when it is.
    std::string shownText() const;
    std::map<std::string, double> frameCostMs_;  // by technique: what the last full-size change cost
    std::map<std::string, int> dragFactor_;      // by technique: the drag frames' divisor per side (adapts)
    uint64_t previewVersion_ = ~0ull;            // the state a reduced preview was shown for
    double refineProgress_ = 1.0;                // of the full-size frame being refined (1: complete)
    bool imageComplete_ = true;                  // the renderers' images are complete frames (present them)
    uint64_t refineVersion_ = ~0ull;             // the state the work below is for
    glm::ivec2 refineSize_{0};
    double refineWorkMs_ = 0.0;                  // time spent on it so far
    double renderMs_ = 0, frameMs_ = 0, uiFps_ = 0;
    double phaseMs_[5] = {0, 0, 0, 0, 0};  // ui, render (+ reference), present, ImGui draw, swap
    nlohmann::json stats_;
    bool statsValid_ = false;  // stats_ is of a complete frame of the technique selected
    clock::time_point statsTime_{};
    // metrics against the reference, for (reference generation, state version)
    std::optional<Metrics> metricsAll_, metricsPenumbra_;
    uint64_t metricsGeneration_ = ~0ull, metricsVersion_ = ~0ull;
    std::string status_;
    clock::time_point statusTime_{};
    bool statusError_ = false;
    std::vector<std::string> pendingShots_;
    std::string openPath_;
    std::deque<ScriptCommand> script_;
    std::string scriptPath_;
    bool scriptDone_ = true;
    bool scriptFailed_ = false;
    bool shotArmed_ = false;
    int scriptWait_ = 0;
    struct ScriptDrag {
        int button = 0, mods = 0, frames = 0, step = 0;
        glm::vec2 from{0}, to{0};
    };
    std::optional<ScriptDrag> scriptDrag_;
    int scriptWaitReference_ = 0;  // frames left to wait for the reference to complete
    int shotCounter_ = 0;
    float pendingScale_ = 0.0f;
    // The views panel (window_views.cpp): one VTK frame per open view, re-rendered when the state,
    // the picked pixel or the view's own orbit changed, one view per idle frame.
    struct OpenView {
        std::string name;
        std::unique_ptr<VtkOffscreen> frame;
        std::string caption, refusal;
        bool valid = false;
        std::vector<double> renderedKey;
        float azimuth = 0.0f, elevation = 0.0f, zoom = 1.0f;
    };
    std::vector<std::unique_ptr<OpenView>> views_;
    std::vector<float> viewAspects_;  // each open view's cell aspect (viewAspect), for viewAspectKey_
    std::string viewAspectKey_;
    void syncViewList();
    void updateViews();
    std::vector<AccuracyTimePoint> accuracyPoints_;
    uint64_t accuracyGeneration_ = ~0ull;
    bool compareAll_ = false;
    std::vector<ChartSetting> compareQueue_;  // still to place against the reference of compareGeneration_
    size_t compareTotal_ = 0;
    uint64_t compareGeneration_ = ~0ull;
    bool accuracyDirty_ = true;
    int costFrame_ = 1 << 28;  // frame numbers of cost measurements (above any frame the window runs)
    std::unique_ptr<VtkOffscreen> accuracyFrame_;
    std::unique_ptr<LessonHost> lessonHost_;
    std::unique_ptr<LessonPlayer> lesson_;
    LessonPanelRects lessonRects_;  // where the lesson panel drew its step buttons (--report)
    clock::time_point lessonClock_{};
    Image referenceImage_;  // the complete reference's visibility, for the error view
    uint64_t referenceImageGeneration_ = ~0ull;
    uint64_t referenceVersion_ = ~0ull;  // version_ the reference was last synced to
};


// Reads and checks a --script file (window_input.cpp lists the steps). InputError naming file:line.
std::deque<ScriptCommand> parseScript(const std::string& path);

// Renders the default scene headless into a folder when no window can open (no display); prints
// what it did and where. Returns the exit code (0 when the render worked).
int runHeadlessFallback(const std::string& reason);


}  // namespace shadowlab
