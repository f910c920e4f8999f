// What the lesson player drives: the window (app/window/window.cpp, wired by the lead) or the headless
// runner (app/lesson/headless.cpp, on a Renderer). The player applies a step's complete state
// through these calls, in the order of applyLessonState(), so a host needs no lesson logic.
#pragma once
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lesson/lesson.h"
#include "scene/scene.h"

namespace shadowlab {

class LessonHost {
public:
    virtual ~LessonHost() = default;

    // A scene by name (assets/scenes/<name>.json). The host may keep its renderer when the name is
    // the current one. Lights and camera are set afterwards by their own calls.
    virtual void setScene(const std::string& name) = 0;
    // Every light's technique; its parameters start at their defaults (Renderer::setTechnique).
    virtual void setTechnique(const std::string& id) = 0;
    // One parameter of the technique, as text its table accepts (Renderer::setParam).
    virtual void setParam(const std::string& key, const std::string& value) = 0;
    virtual void setLight(size_t index, const Light& light) = 0;
    virtual void setCamera(const Camera& camera) = 0;
    // What "reference" means for tasks, the error view and the split: a reference technique with
    // its parameters, rendered with the same scene, lights and camera.
    virtual void setReference(const std::string& technique,
                              const std::vector<std::pair<std::string, std::string>>& params) = 0;
    // A view beside the technique view (lessonViews()).
    virtual void showView(const std::string& view, bool shown) = 0;
    // The picked pixel (a world point or a fraction of the image: LessonPick); nullopt: none.
    virtual void pickPixel(const std::optional<LessonPick>& pick) = 0;
    // Left half the technique, right half `against` ("reference" or a technique id); "" = no split.
    virtual void setSplit(const std::string& against) = 0;
    // Renders the shown state and returns what a condition reads of it (TaskReads: the reference,
    // internals by the names Renderer::writeInternals gives them; the visibility and the ids always).
    virtual TaskBuffers readTaskBuffers(const TaskReads& reads) = 0;
    // The same of `variant` (the step with an expectation's changes, TaskVariant), rendered aside:
    // what the host shows does not change.
    virtual TaskBuffers readVariantBuffers(const LessonState& variant, const TaskReads& reads) = 0;
    // Whether readTaskBuffers can answer now without waiting: false while what the task reads is
    // still accumulating (the window's progressive references), `waiting` then says what ("the
    // reference: 40 of 128 samples"); the player marks the check pending and the host calls
    // LessonPlayer::finishCheck once it is ready. The headless host is always ready.
    virtual bool taskBuffersReady(bool /*withReference*/, std::string& /*waiting*/) { return true; }
    // A number that changes whenever what the host shows changes (the window's state version), so
    // the player knows whether the step it applied is still what is shown; 0 if the host never
    // changes by itself.
    virtual unsigned long long shownVersion() const { return 0; }
};

// Applies the complete state to a host: scene, technique, every parameter, every light, the
// camera, the reference, every view (shown or hidden), the picked pixel and the split. Nothing the
// user changed before survives.
inline void applyLessonState(LessonHost& host, const LessonState& state) {
    host.setScene(state.scene);
    host.setTechnique(state.technique);
    for (const auto& [key, value] : state.paramTexts()) host.setParam(key, value);
    for (size_t i = 0; i < state.lights.size(); ++i) host.setLight(i, state.lights[i]);
    host.setCamera(state.camera);
    host.setReference(state.referenceTechnique, state.referenceParamTexts());
    for (const std::string& view : lessonViews()) host.showView(view, state.views.count(view) > 0);
    host.pickPixel(state.pick);
    host.setSplit(state.split);
}

}  // namespace shadowlab
