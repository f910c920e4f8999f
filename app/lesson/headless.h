// The headless side of lessons: a LessonHost on Renderers (the technique, the reference, and a
// second technique for a split), the views rendered from their buffers (app/lesson/step_views.cpp), and
// `shadowlab lesson L --headless --out DIR`: every step as PNGs plus an HTML handout.
#pragma once
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "graph/renderer.h"
#include "image/image.h"
#include "error.h"
#include "lesson/host.h"
#include "chart_accuracy_time.h"

namespace shadowlab {

// Needs a current GL context for as long as it lives.
class RendererLessonHost : public LessonHost {
public:
    RendererLessonHost(int width, int height);
    ~RendererLessonHost() override;

    void setScene(const std::string& name) override;
    void setTechnique(const std::string& id) override;
    void setParam(const std::string& key, const std::string& value) override;
    void setLight(size_t index, const Light& light) override;
    void setCamera(const Camera& camera) override;
    void setReference(const std::string& technique,
                      const std::vector<std::pair<std::string, std::string>>& params) override;
    void showView(const std::string& view, bool shown) override;
    void pickPixel(const std::optional<LessonPick>& pick) override;
    void setSplit(const std::string& against) override;
    TaskBuffers readTaskBuffers(const TaskReads& reads) override;
    TaskBuffers readVariantBuffers(const LessonState& variant, const TaskReads& reads) override;

    // ---- what the runner and the views read
    Renderer& technique();            // rendered (frame 0, time 0) on return
    Renderer& reference();            // rendered on return
    Renderer& splitRenderer();        // the reference, or the split's own technique; rendered
    const Scene& scene() const { return *scene_; }
    const std::set<std::string>& views() const { return views_; }
    const std::string& split() const { return split_; }
    // In pixels of the image. A world point off-screen at this size is a lesson error (InputError
    // naming the pick's file and line and the size).
    std::optional<glm::ivec2> pickedPixel() const;
    const std::optional<LessonPick>& pick() const { return pick_; }
    const Camera& camera() const { return camera_; }
    const std::vector<Light>& lights() const { return lights_; }
    const std::string& sceneName() const { return sceneName_; }
    // The technique every light asks for and the parameters the step set (text as the lesson gave it).
    const std::string& techniqueId() const { return main_.technique; }
    const std::vector<std::pair<std::string, std::string>>& techniqueParams() const { return main_.params; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    struct Slot {
        std::unique_ptr<Renderer> renderer;
        std::string technique;
        std::vector<std::pair<std::string, std::string>> params;
        bool dirty = true;
    };
    // Creates (with every light and the camera) and renders; with `internals`, every internal the
    // technique can expose is rendered too (Renderer::internalRequests).
    Slot& ensure(Slot& slot, bool internals = false);
    void render(Renderer& renderer, const std::set<std::string>& requested);
    int width_, height_;
    std::unique_ptr<Scene> scene_;
    std::string sceneName_;
    std::vector<Light> lights_;
    Camera camera_;
    Slot main_, reference_, split_slot_;
    std::set<std::string> views_;
    std::optional<LessonPick> pick_;
    std::string split_;
    std::unique_ptr<RendererLessonHost> variant_;  // renders an expectation's variants
    std::optional<LessonState> variantState_;      // the variant it shows
};

// The "accuracy-time" view's points: the step's scene, lights and camera at the host's size, each
// setting `auto` chooses among (the default calibration's, every technique at its defaults) and
// `auto` itself at the step's parameters and at the error budgets 0.005, 0.02 and 0.1, each placed by
// its shadow_ms (every pass run every frame, median of `frames` after one warm-up) and its RMSE
// against the step's reference. The step's own setting is highlighted. Needs a current GL context.
std::vector<AccuracyTimePoint> lessonAccuracyPoints(RendererLessonHost& host, int frames = 2);

// The internals named (the keys of Renderer::writeInternals: "kernel_size", "light1/kernel_size")
// of the renderer's last frame, which must have requested them; a pyramid's level 0. An internal
// not written is absent.
std::map<std::string, Image> collectInternals(Renderer& renderer, const std::set<std::string>& names);

// The images of one view of the host's current state (app/lesson/step_views.cpp): "technique" (the
// shaded image, with the split and the picked pixel), or one of lessonViews().
Image renderLessonView(RendererLessonHost& host, const std::string& view);
// Every `show` of every step (and of its answer) asked of the step's technique without rendering,
// as `lesson --check` does without --sizes: a view its technique cannot give (`show hsm` under
// `hard`) is an InputError naming the step's file and line. Loads the lessons' scenes; no GL.
void checkLessonViews(const Lesson& lesson);

// Every failing expectation of a lesson at one size, one per line:
// "lessons/intro.md:42 at 320x320: expect mean(visibility in penumbra) > 0.3: 0.21".
class LessonCheckError : public InputError {
public:
    using InputError::InputError;
};

// Renders every step of `lesson` into `directory` (PNGs, index.html, lesson.json with each step's
// state, its expectations and task outcomes), or, with `directory` empty, renders and checks
// without writing anything. Checks each task both ways (the step's state must not pass it, the
// show-me state must), else an InputError naming the task's line, and every expectation of every
// step, else a LessonCheckError listing the failing ones. All-or-nothing outputs.
nlohmann::json renderLessonHeadless(const Lesson& lesson, const std::string& directory, int width, int height);

}  // namespace shadowlab
