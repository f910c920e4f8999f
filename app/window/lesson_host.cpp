// The lesson player in the window (DESIGN.md section 8): a LessonHost on the window's own actions
// (selectScene, selectTechnique, setParam, setLight, setCamera, pickPixel, setCompare, openView), so
// a lesson step changes the window exactly as the panel, the keys and --script do, and the panel of
// app/lesson/panel.cpp drawn beside the views.
//
// What differs from the headless host (app/lesson/headless.cpp), and why:
//   - "reference" is the window's progressive reference (the `reference` technique's stratified
//     samples, N from the lesson's `reference reference samples=N`); a task that reads it waits
//     for it to complete (taskBuffersReady: the check is pending while the window keeps refining
//     the reference in its frame budget) so the check sees the finished integral.
//     "raytraced" is the window's progressive ray tracer (M from the step's `reference raytraced
//     rays=M`, its default otherwise): a task's check waits for it to complete the same way.
//   - the lesson-only views `visibility` and `reference` are the technique view itself and the
//     split against the reference; `shadow-map-texels` opens the `shadow-map` view.
#include "gl/loader.h"  // before GLFW, which must not include GL/gl.h
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lesson/headless.h"
#include "lesson/player.h"
#include "views.h"
#include "window/window.h"

namespace shadowlab {

class WindowLessonHost : public LessonHost {
public:
    explicit WindowLessonHost(Window& window) : w_(window) {}

    void setScene(const std::string& name) override {
        if (w_.state_.scene != name || !w_.scene_) w_.selectScene(name);
    }
    void setTechnique(const std::string& id) override {
        w_.selectTechnique(id);  // parameters start at their defaults (raytraced: the progressive ray tracer)
    }
    void setParam(const std::string& key, const std::string& value) override {
        // The window shows `reference` as its progressive reference: N and its shadow-map settings
        // apply there.
        if (w_.state_.technique == "reference") {
            if (key == "samples") w_.setReferenceSamples(std::stoi(value));
            else if (ProgressiveReference::isDepthParam(key)) w_.setReferenceParam(key, value);
            return;
        }
        w_.setParam(key, value);
    }
    void setLight(size_t index, const Light& light) override { w_.setLight(int(index), light); }
    void setCamera(const Camera& camera) override { w_.setCamera(camera); }
    void setReference(const std::string& technique,
                      const std::vector<std::pair<std::string, std::string>>& params) override {
        referenceTechnique_ = technique;
        referenceParams_ = params;
        if (technique == "raytraced") {
            // Exactly the step's M, else the technique's default.
            w_.setReferenceTechnique("raytraced");
            const ParamDesc* rays = requireTechnique("raytraced", "lesson").findParam("rays");
            int m = rays ? int(rays->defaultValue) : 256;
            for (const auto& [key, value] : params)
                if (key == "rays") m = std::stoi(value);
            w_.setReferenceRays(m);
            return;
        }
        if (technique != "reference") return;
        w_.setReferenceTechnique("reference");
        // Exactly the step's settings: what it does not name goes back to the reference's defaults.
        w_.state_.referenceParams.clear();
        w_.touch();
        for (const auto& [key, value] : params)
            if (key == "samples") w_.setReferenceSamples(std::stoi(value));
            else if (ProgressiveReference::isDepthParam(key)) w_.setReferenceParam(key, value);
    }
    void showView(const std::string& view, bool shown) override {
        if (view == "visibility") return;  // the technique view is always shown
        if (view == "reference") {
            referenceShown_ = shown;  // applied with the split (setSplit comes after the views)
            return;
        }
        if (view == "accuracy-time") {
            // The chart panel, filled with every technique once the reference is complete.
            if (shown != w_.compareAll_) w_.compareEveryTechnique(shown);
            if (!shown) w_.state_.showAccuracy = false;
            return;
        }
        if (view == "shadow-map-texels") texelsShown_ = shown;  // comes before "shadow-map"
        std::string name = view == "shadow-map-texels" ? "shadow-map" : view;
        std::vector<ViewInfo> all = listViews();
        if (std::none_of(all.begin(), all.end(), [&](const ViewInfo& v) { return v.name == name; })) return;
        if (shown || (name == "shadow-map" && texelsShown_)) w_.openView(name);
        else w_.closeView(name);
    }
    void pickPixel(const std::optional<LessonPick>& pick) override {
        // A world point is projected through the step's camera at the technique view's size (the
        // camera is applied before the pick, applyLessonState); off-screen here: no pick, said.
        std::optional<glm::ivec2> pixel;
        if (pick) pixel = pickPixelAt(*pick, w_.state_.camera, w_.renderSize().x, w_.renderSize().y);
        if (!pixel) {
            w_.state_.pickedPixel.reset();
            if (pick) w_.setStatus(pick->where.str() + ": the lesson's pick is off-screen at this size", true);
            return;
        }
        w_.pickPixel(*pixel);
        w_.lessonPick_ = *pick;  // re-projected if the technique view's size changes (Window::renderViews)
    }
    void setSplit(const std::string& against) override {
        if (against.empty()) w_.setCompare(referenceShown_ ? WindowState::Compare::Reference : WindowState::Compare::None);
        else if (against == "reference") w_.setCompare(WindowState::Compare::Reference);
        else w_.setCompare(WindowState::Compare::Technique, against);
    }
    bool taskBuffersReady(bool withReference, std::string& waiting) override {
        // What readTaskBuffers would otherwise complete at once (a pause of seconds): the shown
        // progressive source, and the progressive reference the task reads, for the current state.
        const glm::ivec2 size = w_.renderSize();
        // The technique's own frame first: refined in the frame budget, complete, it is read as it
        // is (readTaskBuffers renders nothing then; a synchronous frame of ssm-gbp06 under a wide
        // light is a pause of seconds).
        if (!frameComplete()) {
            waiting = "the technique's frame";
            return false;
        }
        auto pending = [&](ProgressiveSource& s, const char* what) {
            if (&s == &w_.raytrace_)
                w_.raytrace_.sync(*w_.scene_, w_.state_.camera, w_.state_.lights, size.x, size.y, w_.state_.time,
                                  w_.state_.referenceRays);
            else
                w_.reference_.sync(*w_.scene_, w_.state_.camera, w_.state_.lights, size.x, size.y, w_.state_.time,
                                   w_.state_.referenceSamples, w_.state_.referenceParams);
            if (s.complete()) return false;
            char text[128];
            std::snprintf(text, sizeof text, "%s: %d of %d %s", what, s.done(), s.total(), s.unit());
            waiting = text;
            return true;
        };
        if (w_.state_.technique == "raytraced" && pending(w_.raytrace_, "raytraced")) return false;
        if (w_.state_.technique == "reference" && pending(w_.reference_, "the reference")) return false;
        if (withReference && referenceTechnique_ == "reference" && pending(w_.reference_, "the reference")) return false;
        if (withReference && referenceTechnique_ == "raytraced" && pending(w_.raytrace_, "the raytraced reference")) return false;
        return true;
    }
    TaskBuffers readTaskBuffers(const TaskReads& reads) override {
        const bool withReference = reads.reference;
        glm::ivec2 size = w_.renderSize();
        Renderer& r = *w_.renderer_;
        if (r.width() != size.x || r.height() != size.y) r.resize(size.x, size.y);
        std::set<std::string> requested = {"image", "visibility"};
        if (!reads.internals.empty())
            for (const std::string& name : r.internalRequests(false)) requested.insert(name);
        // The refined frame complete: its outputs are renderFrame's (Renderer::refineFrame).
        if (!frameComplete() || !reads.internals.empty()) r.renderFrame(w_.frameIndex_, requested);
        TaskBuffers b;
        b.visibility = r.visibility();
        b.ids = r.ids();
        if (!reads.internals.empty()) b.internals = collectInternals(r, reads.internals);
        if (reads.positions) b.positions = r.positions();
        b.pick = w_.state_.pickedPixel;
        // The technique view showing a progressive reference: its complete visibility.
        if (w_.state_.technique == "raytraced") {
            w_.raytrace_.sync(*w_.scene_, w_.state_.camera, w_.state_.lights, size.x, size.y, w_.state_.time,
                              w_.state_.referenceRays);
            w_.raytrace_.finish();
            b.visibility = w_.raytrace_.visibility();
        } else if (w_.state_.technique == "reference") {
            w_.reference_.sync(*w_.scene_, w_.state_.camera, w_.state_.lights, size.x, size.y, w_.state_.time,
                               w_.state_.referenceSamples, w_.state_.referenceParams);
            while (!w_.reference_.complete()) w_.reference_.step(1e9);
            b.visibility = w_.reference_.visibility();
        }
        w_.referenceVersion_ = w_.version_;
        if (!withReference) return b;
        if (referenceTechnique_ == "reference") {
            ProgressiveReference& ref = w_.reference_;
            ref.sync(*w_.scene_, w_.state_.camera, w_.state_.lights, size.x, size.y, w_.state_.time,
                     w_.state_.referenceSamples, w_.state_.referenceParams);
            w_.referenceVersion_ = w_.version_;
            while (!ref.complete()) ref.step(1e9);
            b.reference = ref.visibility();
        } else if (referenceTechnique_ == "raytraced") {
            ProgressiveRaytrace& ref = w_.raytrace_;
            ref.sync(*w_.scene_, w_.state_.camera, w_.state_.lights, size.x, size.y, w_.state_.time,
                     w_.state_.referenceRays);
            w_.referenceVersion_ = w_.version_;
            ref.finish();
            b.reference = ref.visibility();
        } else {
            RenderOptions options;
            options.width = size.x;
            options.height = size.y;
            options.technique = referenceTechnique_;
            options.sets = referenceParams_;
            Renderer reference(*w_.scene_, options);
            for (size_t i = 0; i < w_.state_.lights.size(); ++i) reference.setLight(i, w_.state_.lights[i]);
            reference.setCamera(w_.state_.camera);
            reference.renderFrame(0, {"visibility"});
            b.reference = reference.visibility();
        }
        return b;
    }

    // An expectation's variant: rendered at the technique view's size on a headless host of its own
    // (the window's state, its progressive references and its picture are untouched); its
    // reference, when it reads one, is rendered whole at once.
    TaskBuffers readVariantBuffers(const LessonState& variant, const TaskReads& reads) override {
        const glm::ivec2 size = w_.renderSize();
        if (!variant_ || variant_->width() != size.x || variant_->height() != size.y) {
            variant_ = std::make_unique<RendererLessonHost>(size.x, size.y);
            variantState_.reset();
        }
        if (!variantState_ || *variantState_ != variant) applyLessonState(*variant_, variant);
        variantState_ = variant;
        return variant_->readTaskBuffers(reads);
    }
    unsigned long long shownVersion() const override { return w_.version_; }

private:
    // The technique's frame of what is shown now is complete (refined to the end, not a preview).
    bool frameComplete() const {
        const glm::ivec2 size = w_.renderSize();
        const Renderer& r = *w_.renderer_;
        return w_.imageComplete_ && !w_.reduced_ && w_.refineVersion_ == w_.version_ && w_.refineSize_ == size &&
               r.width() == size.x && r.height() == size.y;
    }
    Window& w_;
    std::unique_ptr<RendererLessonHost> variant_;
    std::optional<LessonState> variantState_;
    bool referenceShown_ = false, texelsShown_ = false;
    std::string referenceTechnique_ = "reference";
    std::vector<std::pair<std::string, std::string>> referenceParams_;
};

void Window::openLesson(Lesson lesson) {
    lesson_.reset();
    lessonHost_ = std::make_unique<WindowLessonHost>(*this);
    lesson_ = std::make_unique<LessonPlayer>(std::move(lesson), *lessonHost_);  // applies step 1
    setStatus("lesson " + lesson_->lesson().title);
}

bool Window::lessonKey(int key) const {
    if (!lesson_) return false;
    switch (key) {
    case GLFW_KEY_RIGHT:
    case GLFW_KEY_LEFT:
    case GLFW_KEY_PAGE_UP:
    case GLFW_KEY_PAGE_DOWN:
    case GLFW_KEY_SPACE:
    case GLFW_KEY_R:
    case GLFW_KEY_C:
    case GLFW_KEY_M: return true;  // the lesson panel reads these (app/lesson/panel.cpp)
    default: return false;
    }
}

void Window::lessonAction(const std::string& action) {
    if (!lesson_) {
        setStatus("no lesson is open (shadowlab lesson L, or window --lesson L)", true);
        return;
    }
    if (action == "next") lesson_->next();
    else if (action == "previous") lesson_->previous();
    else if (action == "restore") lesson_->restore();
    else if (action == "check" && lesson_->step().task) {
        lesson_->checkTask();
        reportCheck();
    } else if (action == "show-me" && lesson_->step().task) lesson_->showMe();
}

void Window::reportCheck() {
    const LessonPlayer::Feedback& f = lesson_->feedback();
    if (f.pending) {  // the window keeps refining what it waits for; finishPendingCheck runs it
        setStatus(f.message);
        return;
    }
    const bool passed = f.status == LessonPlayer::TaskStatus::Passed || f.status == LessonPlayer::TaskStatus::ShownAnswer;
    setStatus(std::string(passed ? "solved: " : "not yet: ") + f.message, !passed);
    std::printf("lesson: step %zu: %s: %s\n", lesson_->stepIndex() + 1, passed ? "passed" : "not yet", f.message.c_str());
    std::fflush(stdout);
}

// Each frame: a check that waited (the Check button, C or the script's `lesson check` while the
// reference accumulated) runs once what it reads is complete, and prints as a check at once would.
void Window::finishPendingCheck() {
    if (lesson_ && lesson_->expectsPending()) {
        // The step's claims, once what they read is complete: printed, and shown in the panel (a
        // failing one is reported, never fatal).
        if (lesson_->checkExpects()) {
            const LessonStep& step = lesson_->step();
            if (lesson_->expectStatus() == LessonPlayer::ExpectStatus::Changed)
                std::printf("lesson: step %zu: expectations not checked: the step was changed before they were\n",
                            lesson_->stepIndex() + 1);
            for (size_t k = 0; k < lesson_->expectResults().size(); ++k) {
                const LessonPlayer::ExpectResult& r = lesson_->expectResults()[k];
                std::printf("lesson: step %zu: %s: expect %s: %s\n", lesson_->stepIndex() + 1, step.expects[k].where.str().c_str(),
                            step.expects[k].condition.text().c_str(), r.passed ? "holds" : ("FAILS: " + r.failure).c_str());
                if (!r.passed) setStatus(step.expects[k].where.str() + ": expect " + step.expects[k].condition.text() + ": " + r.failure, true);
            }
            std::fflush(stdout);
        }
    }
    if (!lesson_ || !lesson_->checkPending()) return;
    if (!lesson_->finishCheck()) {
        if (status_.rfind("checking: ", 0) == 0) status_ = lesson_->feedback().message;  // the progress so far
        return;
    }
    reportCheck();
}

void Window::drawLesson(double seconds) {
    if (!lesson_) return;
    lesson_->update(seconds);
    // The lesson's column on the right (window/layout.h): never over the image or the views.
    placeRegion(layout_.lesson);
    lessonRects_ = drawLessonPanel(*lesson_, state_.presentation ? 1.0f : 1.3f);
}

}  // namespace shadowlab
