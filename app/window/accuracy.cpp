// The window's accuracy-time chart (issue 8, DESIGN.md section 1: "the app places any setting on an
// accuracy-versus-time chart"): every setting the user visits while the reference of the current
// scene, light and camera is complete becomes a point (RMSE against that reference, shadow_ms of
// the setting measured with every pass run; recorded while the chart is open), drawn with the bench's own chart
// (viz/chart_accuracy_time.h), the current setting ringed. A change of scene, light, camera or size
// restarts the reference and clears the points: they are only comparable against one reference.
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkNew.h>
#include <vtkRenderer.h>

#include "chart_accuracy_time.h"
#include "image/image.h"
#include "vtk_offscreen.h"
#include "window/window.h"

namespace shadowlab {

void Window::recordAccuracyPoint() {
    // Timing a setting runs its passes three more times (seconds for a heavy technique on llvmpipe):
    // only while the chart is open.
    if (!state_.showAccuracy) return;
    if (accuracyGeneration_ != ref().generation()) {
        accuracyPoints_.clear();
        accuracyGeneration_ = ref().generation();
    }
    // shadow_ms of this setting alone: every needed pass timed (frame numbers no normal frame uses).
    renderer_->measureCost(costFrame_, 3);
    double shadowMs = renderer_->cost(costFrame_).shadowMs;
    costFrame_ += 3;
    const LightState& light = *renderer_->lights().at(0);
    AccuracyTimePoint point{state_.technique, settingLabel(*light.requested, light.requestedParams), shadowMs, metricsAll_->rmse, true};
    for (AccuracyTimePoint& p : accuracyPoints_) p.highlight = false;
    auto same = std::find_if(accuracyPoints_.begin(), accuracyPoints_.end(), [&](const AccuracyTimePoint& p) {
        return p.series == point.series && p.label == point.label;
    });
    if (same != accuracyPoints_.end()) *same = point;
    else accuracyPoints_.push_back(point);
    accuracyDirty_ = true;
}

void Window::compareEveryTechnique(bool on) {
    compareAll_ = on;
    compareQueue_.clear();
    compareTotal_ = 0;
    compareGeneration_ = ~0ull;
    if (on) state_.showAccuracy = true;
}

void Window::stepAccuracyCompare() {
    if (!compareAll_ || !state_.showAccuracy || !scene_ || !renderer_) return;
    if (!ref().complete() || referenceVersion_ != version_) return;
    if (compareGeneration_ != ref().generation()) {
        // A new reference: every setting again (recordAccuracyPoint cleared the old points), but
        // the one shown, which the window places itself.
        const LightState& light = *renderer_->lights().at(0);
        compareQueue_.clear();
        for (const ChartSetting& s : comparedSettings(state_.technique, &light.requestedParams))
            if (!s.current) compareQueue_.push_back(s);
        compareTotal_ = compareQueue_.size();
        compareGeneration_ = ref().generation();
        if (accuracyGeneration_ != ref().generation()) {
            accuracyPoints_.clear();
            accuracyGeneration_ = ref().generation();
        }
    }
    if (compareQueue_.empty()) return;
    // One setting per frame: a heavy technique at the full size takes a second or so on llvmpipe.
    const ChartSetting s = compareQueue_.front();
    compareQueue_.erase(compareQueue_.begin());
    Scene scene = *scene_;
    scene.lights = renderer_->frameLights();
    scene.camera = state_.camera;
    const glm::ivec2 size = renderSize();
    AccuracyTimePoint point =
        measureChartSetting(scene, scene_->name, size.x, size.y, s, ref().visibility(), true, 2);
    auto same = std::find_if(accuracyPoints_.begin(), accuracyPoints_.end(), [&](const AccuracyTimePoint& p) {
        return p.series == point.series && p.label == point.label;
    });
    if (same != accuracyPoints_.end()) *same = point;
    else accuracyPoints_.push_back(point);
    accuracyDirty_ = true;
}

void Window::drawAccuracyChart() {
    if (!state_.showAccuracy) return;
    const float s = state_.uiScale;
    int w = int(560 * s), h = int(380 * s);
    if (accuracyDirty_ || !accuracyFrame_ || accuracyFrame_->width() != w || accuracyFrame_->height() != h) {
        if (!accuracyFrame_) accuracyFrame_ = std::make_unique<VtkOffscreen>(w, h);
        if (accuracyFrame_->width() != w || accuracyFrame_->height() != h) accuracyFrame_->resize(w, h);
        vtkNew<vtkContextView> view;
        accuracyFrame_->attach(view);
        view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);  // opaque: the panel's dark fill must not show through
        view->GetRenderer()->SetBackgroundAlpha(1.0);
        AccuracyTimePanel panel{(scene_ ? scene_->name : std::string()) + ": RMSE against the reference", accuracyPoints_};
        AccuracyTimeStyle style;
        style.fontSize = std::max(14, int(14 * s));
        if (!accuracyPoints_.empty()) view->GetScene()->AddItem(buildAccuracyTimeChart(panel, style));
        accuracyFrame_->renderToTexture();
        accuracyDirty_ = false;
    }
    // The last cell of the views strip (window/layout.h), the chart scaled into it.
    if (layout_.cells.empty() || layout_.cells.back().empty()) return;
    placeRegion(layout_.cells.back());
    ImGui::Begin("Accuracy vs time (A)", &state_.showAccuracy,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    if (compareAll_ && !compareQueue_.empty())
        ImGui::Text("placing every technique: %zu of %zu (next: %s)", compareTotal_ - compareQueue_.size(), compareTotal_,
                    compareQueue_.front().technique.c_str());
    else if (accuracyPoints_.empty())
        ImGui::TextWrapped("Points appear once the reference is complete: each setting you try is placed by its "
                           "shadow_ms and its RMSE against the reference (B computes it in the background).");
    else
        ImGui::Text("%zu setting(s) against one reference; the ring is the current one", accuracyPoints_.size());
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    float ih = std::max(1.0f, avail.y - ImGui::GetFrameHeightWithSpacing()), iw = ih * float(w) / float(h);
    if (iw > avail.x) iw = avail.x, ih = iw * float(h) / float(w);
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(accuracyFrame_->texture())), ImVec2(iw, ih),
                 ImVec2(0, 1), ImVec2(1, 0));
    if (ImGui::Button("clear")) {
        accuracyPoints_.clear();
        accuracyDirty_ = true;
        compareEveryTechnique(false);
    }
    ImGui::SameLine();
    if (ImGui::Button("every technique")) compareEveryTechnique(true);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Places every setting auto chooses among (each technique at its defaults) and auto at the "
                          "budgets 0.005, 0.02 and 0.1, one per frame, against this reference");
    ImGui::End();
}

void Window::saveAccuracyPoints(const std::string& path) const {
    nlohmann::json points = nlohmann::json::array();
    for (const AccuracyTimePoint& p : accuracyPoints_)
        points.push_back({{"technique", p.series}, {"setting", p.label}, {"shadow_ms", p.timeMs}, {"rmse", p.error},
                          {"current", p.highlight}});
    OutputSet outputs;
    std::ofstream(outputs.stage(path)) << nlohmann::json{{"scene", scene_ ? scene_->name : ""}, {"points", points}}.dump(1)
                                       << "\n";
    outputs.commit();
}

}  // namespace shadowlab
