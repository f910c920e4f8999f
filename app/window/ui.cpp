// The window's panels (Dear ImGui 1.86): techniques and their parameters generated from the
// descriptors (techniques/core/graph/technique.h), scenes and "open a file", light, camera, split and
// error views, the progressive reference, display settings; the HUD; F1's key list; the views hook.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "views.h"
#include "window/window.h"

namespace shadowlab {

namespace {

std::string formatValue(const ParamDesc& p, double v) {
    char text[64];
    if (p.type == ParamDesc::Type::Float) std::snprintf(text, sizeof text, "%.6g", v);
    else std::snprintf(text, sizeof text, "%lld", static_cast<long long>(std::llround(v)));
    return text;
}

std::string paramLabel(const ParamDesc& p) { return p.symbol.empty() ? p.key : p.symbol + "  (" + p.key + ")"; }

void tooltip(const std::string& text) {
    if (!text.empty() && ImGui::IsItemHovered()) {
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 32.0f);
        ImGui::TextUnformatted(text.c_str());
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
    }
}

// Snaps an Int value to the table: min + k * step, odd, power of two.
double snapInt(const ParamDesc& p, double v) {
    v = std::clamp(std::round(v), p.minValue, p.maxValue);
    if (p.step > 1) v = p.minValue + std::round((v - p.minValue) / p.step) * p.step;
    if (p.constraint == ParamDesc::Constraint::Odd && std::fmod(std::abs(v), 2.0) == 0.0) v = v + 1 <= p.maxValue ? v + 1 : v - 1;
    return std::clamp(v, p.minValue, p.maxValue);
}

}  // namespace

// One parameter's widget; returns the new value text when the user changed it.
static std::optional<std::string> paramWidget(const ParamDesc& p, double value) {
    std::string label = paramLabel(p) + "##" + p.key;
    std::string unit = p.unit.empty() ? "" : " " + p.unit;
    std::optional<std::string> changed;
    switch (p.type) {
    case ParamDesc::Type::Bool: {
        bool b = value != 0.0;
        if (ImGui::Checkbox(label.c_str(), &b)) changed = b ? "1" : "0";
        break;
    }
    case ParamDesc::Type::Enum: {
        int index = int(value);
        std::string current = index >= 0 && size_t(index) < p.choices.size() ? p.choices[size_t(index)] : "?";
        if (ImGui::BeginCombo(label.c_str(), current.c_str())) {
            for (size_t i = 0; i < p.choices.size(); ++i)
                if (ImGui::Selectable(p.choices[i].c_str(), int(i) == index)) changed = p.choices[i];
            ImGui::EndCombo();
        }
        break;
    }
    case ParamDesc::Type::Int: {
        if (p.constraint == ParamDesc::Constraint::PowerOfTwo) {
            std::string current = formatValue(p, value) + unit;
            if (ImGui::BeginCombo(label.c_str(), current.c_str())) {
                for (double v = 1; v <= p.maxValue; v *= 2)
                    if (v >= p.minValue && ImGui::Selectable(formatValue(p, v).c_str(), v == value))
                        changed = formatValue(p, v);
                ImGui::EndCombo();
            }
            break;
        }
        int v = int(value);
        int lo = int(std::max(p.minValue, -1e9)), hi = int(std::min(p.maxValue, 1e9));
        std::string format = "%d" + unit;
        ImGuiSliderFlags flags = (hi - lo > 4096 && lo > 0) ? ImGuiSliderFlags_Logarithmic : 0;
        if (ImGui::SliderInt(label.c_str(), &v, lo, hi, format.c_str(), flags)) {
            double snapped = snapInt(p, v);
            if (snapped != value) changed = formatValue(p, snapped);
        }
        break;
    }
    case ParamDesc::Type::Float: {
        float v = float(value);
        std::string format = (p.step >= 1 ? "%.0f" : p.step >= 0.1 ? "%.1f" : p.step >= 0.01 ? "%.2f" : "%.4f") + unit;
        if (ImGui::SliderFloat(label.c_str(), &v, float(p.minValue), float(p.maxValue), format.c_str())) {
            double d = v;
            if (p.step > 0) d = p.minValue + std::round((d - p.minValue) / p.step) * p.step;
            d = std::clamp(d, p.minValue, p.maxValue);
            if (d != value) changed = formatValue(p, d);
        }
        break;
    }
    }
    std::string doc = p.doc + "\ndefault (the paper's): " +
                      (p.type == ParamDesc::Type::Enum ? p.choices.at(size_t(p.defaultValue)) : formatValue(p, p.defaultValue)) +
                      unit + "; range " + formatValue(p, p.minValue) + " .. " + formatValue(p, p.maxValue);
    if (!p.appliesWhen.empty()) doc += "\napplies when " + p.appliesWhen;
    tooltip(doc);
    return changed;
}

void Window::drawUi() {
    const float s = state_.uiScale;
    ImGuiIO& io = ImGui::GetIO();
    glm::vec2 size = windowSize();

    // ---- the panel
    const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse;
    if (state_.showPanel && state_.presentation && !layout_.panel.empty()) {
        // Presentation: one line, the technique and the lesson's step, nothing to tune.
        placeRegion(layout_.panel);
        ImGui::Begin("##bar", nullptr, fixed | ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoScrollbar);
        ImGui::Text("%s  on  %s", state_.technique.c_str(), scene_->name.c_str());
        ImGui::SameLine();
        ImGui::TextDisabled("   (F5 leaves presentation mode)");
        ImGui::End();
    } else if (state_.showPanel && !layout_.panel.empty()) {
        placeRegion(layout_.panel);
        ImGui::SetNextWindowBgAlpha(0.88f);
        ImGui::Begin("shadowlab (Tab hides, F1 keys)", &state_.showPanel, fixed);
        ImGui::PushItemWidth(std::min(170 * s, 0.5f * layout_.panel.w));
        if (ImGui::BeginCombo("open a view", "...")) {  // the views open in the strip under the image
            for (const ViewInfo& info : listViews()) {
                if (ImGui::Selectable(info.name.c_str())) {
                    openView(info.name);
                    state_.showViews = true;
                }
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s\napplies to: %s", info.doc.c_str(), info.appliesTo.c_str());
            }
            ImGui::EndCombo();
        }

        if (ImGui::CollapsingHeader("Technique", ImGuiTreeNodeFlags_DefaultOpen)) {
            for (const std::string& id : techniques_) {
                const TechniqueDesc* d = findTechnique(id);
                if (ImGui::Selectable(id.c_str(), id == state_.technique)) selectTechnique(id);
                tooltip(d->name + "\n" + d->citation + "\n" + d->summary +
                        (id == "raytraced" ? "\nin the window: rays traced on a worker thread, shown as they accumulate"
                                           : ""));
            }
        }

        const TechniqueDesc* desc = findTechnique(state_.technique);
        if (desc && ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
            std::vector<const LightState*> lights = renderer_->lights();
            const LightState* ls = lights.empty() ? nullptr : lights[size_t(std::clamp(state_.lightIndex, 0, int(lights.size()) - 1))];
            ParamValues values = ls && ls->requested == desc ? ls->requestedParams : ParamValues(*desc);
            if (state_.technique == "reference") values.set(*desc, "samples", std::to_string(state_.referenceSamples), "window");
            if (state_.technique == "raytraced") values.set(*desc, "rays", std::to_string(state_.referenceRays), "window");
            std::map<std::string, std::string> inapplicable;
            for (const auto& [k, reason] : values.inapplicable(*desc)) inapplicable[k] = reason;
            if (ls && ls->desc != ls->requested)
                ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "this light is a point: %s runs", ls->desc->id.c_str());
            for (const ParamDesc& p : desc->params) {
                std::string reason;
                if (auto it = inapplicable.find(p.key); it != inapplicable.end()) reason = it->second;
                if (state_.technique == "reference" && p.key != "samples")
                    reason = "the window's progressive reference uses the defaults";
                if (!reason.empty()) ImGui::BeginDisabled();
                double value = values.get(p.key);
                if (auto changed = paramWidget(p, value)) setParam(p.key, *changed);
                if (value != p.defaultValue && reason.empty()) {
                    ImGui::SameLine();
                    if (ImGui::SmallButton(("reset##" + p.key).c_str())) resetParam(p.key);
                    tooltip("back to the paper's default");
                }
                if (!reason.empty()) {
                    ImGui::EndDisabled();
                    ImGui::TextDisabled("   not applied: %s", reason.c_str());
                }
            }
            if (ImGui::Button("Reset all to the paper's defaults (D)")) resetAllParams();
        }

        if (ImGui::CollapsingHeader("Scene")) {
            for (const std::string& name : scenes_)
                if (ImGui::Selectable(name.c_str(), name == state_.scene)) selectScene(name);
            ImGui::InputTextWithHint("##open", "path to a .json scene or a .gltf/.glb file", &openPath_);
            ImGui::SameLine();
            if (ImGui::Button("Open") && !openPath_.empty()) selectScene(openPath_);
            if (scene_) ImGui::TextWrapped("%s", scene_->description.c_str());
        }

        if (!state_.lights.empty() && ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) {
            if (state_.lights.size() > 1) ImGui::SliderInt("light (N)", &state_.lightIndex, 0, int(state_.lights.size()) - 1);
            Light l = state_.lights[size_t(state_.lightIndex)];
            bool changed = false;
            int shape = int(l.shape);
            const char* shapes[] = {"point", "square", "disk", "sphere"};
            if (ImGui::Combo("shape (G)", &shape, shapes, 4)) {
                l.shape = LightShape(shape);
                changed = true;
            }
            const char* sizeLabel = l.shape == LightShape::Square ? "width w_l ([ ])" : "radius r ([ ])";
            if (l.shape != LightShape::Point && ImGui::SliderFloat(sizeLabel, &l.size, 0.0f, 4.0f, "%.3f world units")) changed = true;
            if (ImGui::DragFloat3("position", &l.position.x, 0.02f)) changed = true;
            tooltip("or drag the light's centre or outline in the view (Shift + drag anywhere)");
            if (ImGui::SliderFloat("intensity", &l.intensity, 0.0f, 4.0f)) changed = true;
            if (changed) setLight(state_.lightIndex, l);
            ImGui::Checkbox("outline (L)", &state_.showLight);
            ImGui::SameLine();
            ImGui::Checkbox("frustum (F)", &state_.showFrustum);
            ImGui::SameLine();
            if (ImGui::Button("reset")) resetLight();
        }

        if (ImGui::CollapsingHeader("Camera")) {
            Camera c = state_.camera;
            if (ImGui::SliderFloat("field of view", &c.fovYDegrees, 10.0f, 100.0f, "%.0f deg")) setCamera(c);
            ImGui::Text("left drag: orbit, right drag: pan, wheel: zoom");
            if (ImGui::Button("Reset camera (R)")) resetCamera();
        }

        if (ImGui::CollapsingHeader("Compare", ImGuiTreeNodeFlags_DefaultOpen)) {
            int mode = int(state_.compare);
            bool pick = false;
            pick |= ImGui::RadioButton("single", &mode, 0);
            ImGui::SameLine();
            pick |= ImGui::RadioButton("split: reference", &mode, 1);
            pick |= ImGui::RadioButton("split: technique", &mode, 2);
            if (pick) setCompare(WindowState::Compare(mode));
            if (state_.compare == WindowState::Compare::Technique &&
                ImGui::BeginCombo("right side", state_.compareTechnique.c_str())) {
                for (const std::string& id : techniques_)
                    if (id != "raytraced" && id != "reference" && ImGui::Selectable(id.c_str(), id == state_.compareTechnique))
                        setCompare(WindowState::Compare::Technique, id);
                ImGui::EndCombo();
            }
            if (state_.compare != WindowState::Compare::None) {
                float split = state_.split;
                if (ImGui::SliderFloat("split", &split, 0.0f, 1.0f, "%.2f")) setSplit(split);
                tooltip("or drag the line in the view");
            }
            bool error = state_.errorView;
            if (ImGui::Checkbox("error view |V - V_ref| (E)", &error)) setErrorView(error);
            if (state_.errorView) ImGui::SliderFloat("full colour at", &state_.errorScale, 0.01f, 1.0f, "%.2f");
        }

        if (ImGui::CollapsingHeader("Reference", ImGuiTreeNodeFlags_DefaultOpen)) {
            ImGui::Checkbox("compute in the background (B)", &state_.backgroundReference);
            tooltip("accumulated while the input is idle; restarts when the scene, camera, light or size change");
            int kind = state_.referenceTechnique == "raytraced" ? 1 : 0;
            bool changed = ImGui::RadioButton("reference", &kind, 0);
            tooltip("N stratified light samples of `reference` (hard shadow maps), a few per frame on the GPU");
            ImGui::SameLine();
            changed |= ImGui::RadioButton("raytraced", &kind, 1);
            tooltip("M stratified rays per pixel of `raytraced` (Embree), traced on a worker thread");
            if (changed) setReferenceTechnique(kind == 1 ? "raytraced" : "reference");
            if (kind == 0) {
                int n = state_.referenceSamples;
                if (ImGui::SliderInt("samples N", &n, 16, 4096, "%d", ImGuiSliderFlags_Logarithmic)) setReferenceSamples(n);
            } else {
                int m = state_.referenceRays;
                if (ImGui::SliderInt("rays M", &m, 1, 4096, "%d", ImGuiSliderFlags_Logarithmic)) setReferenceRays(m);
            }
            const ProgressiveSource& reference = ref();
            float fraction = reference.total() > 0 ? float(reference.done()) / float(reference.total()) : 0.0f;
            char overlay[64];
            std::snprintf(overlay, sizeof overlay, "%d / %d %s", reference.done(), reference.total(), reference.unit());
            ImGui::ProgressBar(fraction, ImVec2(-1, 0), overlay);
        }

        if (ImGui::CollapsingHeader("Display")) {
            float scale = state_.uiScale;
            if (ImGui::SliderFloat("UI scale (+ -)", &scale, 0.5f, 3.0f, "%.2f")) pendingScale_ = scale;
            if (ImGui::IsItemDeactivatedAfterEdit() && pendingScale_ > 0) {
                setUiScale(pendingScale_);
                pendingScale_ = 0;
            }
            ImGui::Checkbox("reduced resolution while dragging (X)", &state_.reduceWhileDragging);
            ImGui::SliderInt("at most", &state_.reduceFactor, 2, 16, "1/%d per side");
            tooltip("while dragging, a technique whose frame exceeds the frame budget renders at a reduced "
                    "resolution that fits it (README: the frame budget)");
            ImGui::Checkbox("HUD (H)", &state_.showHud);
            ImGui::SameLine();
            ImGui::Checkbox("play (Space)", &state_.playing);
            ImGui::Checkbox("views panel (V)", &state_.showViews);
        }
        ImGui::PopItemWidth();
        ImGui::End();
    }

    // ---- the HUD
    if (state_.showHud) {
        // Stats of complete full-size frames only (a frame being refined holds half old, half new
        // textures; a reduced frame's passes ran at another size), of the technique shown.
        const bool statsDue = !statsValid_ || std::chrono::duration<double>(clock::now() - statsTime_).count() > 0.5;
        if (imageComplete_ && !reduced_ && refineVersion_ != ~0ull && statsDue) {
            stats_ = renderer_->stats({}, 0, 0);
            statsTime_ = clock::now();
            statsValid_ = true;
        }
        placeRegion(layout_.hud);
        ImGui::SetNextWindowBgAlpha(0.88f);
        ImGui::Begin("##hud", nullptr,
                     ImGuiWindowFlags_NoDecoration | fixed | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
        bool currentMetrics = metricsAll_ && metricsGeneration_ == ref().generation() && metricsVersion_ == version_ &&
                              ref().complete();
        if (state_.presentation) {  // the technique, shadow_ms and RMSE, nothing else
            if (statsValid_) ImGui::Text("%s   shadow_ms %.1f", state_.technique.c_str(), stats_.value("shadow_ms", 0.0));
            else ImGui::Text("%s   shadow_ms once a frame is complete", state_.technique.c_str());
            ImGui::SameLine();
            if (!shownText().empty()) {
                ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "   %s", shownText().c_str());
                ImGui::SameLine();
            }
            if (currentMetrics) ImGui::Text("   RMSE %.4f", metricsAll_->rmse);
            else ImGui::TextDisabled("   RMSE once the reference is complete");
            ImGui::End();
        } else {
            ImGui::Text("%s  on  %s", state_.technique.c_str(), scene_->name.c_str());
            ImGui::Text("%dx%d   clock %s", shownRenderer().width(), shownRenderer().height(), renderer_->clockName());
            if (!shownText().empty()) {
                ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s", shownText().c_str());
                tooltip("the frame budget: a frame that does not fit 33 ms is shown at a reduced resolution while "
                        "dragging, then refined at full resolution in slices over the next frames (README)");
            }
            if (state_.technique == "reference") {
                ImGui::Text("progressive: %.1f ms per light sample", ref().lastSampleMs());
            } else if (state_.technique == "raytraced") {
                ImGui::Text("progressive: %.0f ms per batch (worker)", ref().lastSampleMs());
            } else {
                if (statsValid_)
                    ImGui::Text("shadow_ms %.2f   fixed_ms %.2f", stats_.value("shadow_ms", 0.0), stats_.value("fixed_ms", 0.0));
                else
                    ImGui::TextDisabled("shadow_ms / fixed_ms once a frame is complete");
                tooltip("Renderer::stats(): median of each needed pass's runs; shadow = the technique's passes, fixed = "
                        "G-buffer and shading");
            }
            // `auto`: each light's pick, its rule and prediction, and why (the tooltip); with the
            // complete reference, the measured error beside the predicted one (issue 25).
            for (const auto& light : statsValid_ ? stats_.value("lights", nlohmann::json::array()) : nlohmann::json::array()) {
                if (!light.contains("auto")) continue;
                const nlohmann::json& a = light["auto"];
                std::string text = "L" + std::to_string(light.value("index", 0)) + " auto: " + a.value("technique", std::string()) +
                                   " " + a.value("setting", std::string()) + "  (" + a.value("rule", std::string()) + ")";
                ImGui::TextColored(ImVec4(0.55f, 0.85f, 1.0f, 1.0f), "%s", text.c_str());
                tooltip(a.value("why", std::string()).c_str());
                if (a.contains("predicted")) {
                    char line[200];
                    if (a.contains("measured_error") && a.contains("measured_ms"))  // measured on the view (trial.h)
                        std::snprintf(line, sizeof line, "   trial: RMSE %.4f in %.1f ms (budget %.4f; predicted %.4f)",
                                      a.value("measured_error", 0.0), a.value("measured_ms", 0.0),
                                      a["budget"].value("error", 0.0), a["predicted"].value("error", 0.0));
                    else if (a.contains("measured_error"))  // over the budget: its error measured, not its time
                        std::snprintf(line, sizeof line, "   trial: RMSE %.4f (budget %.4f); predicted %.1f ms",
                                      a.value("measured_error", 0.0), a["budget"].value("error", 0.0),
                                      a["predicted"].value("ms", 0.0));
                    else
                        std::snprintf(line, sizeof line, "   predicted RMSE %.4f in %.1f ms (budget %.4f)",
                                      a["predicted"].value("error", 0.0), a["predicted"].value("ms", 0.0),
                                      a["budget"].value("error", 0.0));
                    ImGui::Text("%s", line);
                    if (currentMetrics && stats_.value("lights", nlohmann::json::array()).size() == 1) {
                        ImGui::SameLine();
                        ImGui::Text("  measured %.4f", metricsAll_->rmse);
                    }
                }
            }
            // Clamped kernels said: a capped kernel that truncated penumbrae (over 1% of its pixels in
            // orange), from the same stats as --stats (kernel_caps).
            for (const auto& light : statsValid_ ? stats_.value("lights", nlohmann::json::array()) : nlohmann::json::array()) {
                for (const auto& k : light.value("kernel_caps", nlohmann::json::array())) {
                    const double f = k.value("clamped_fraction", 0.0);
                    if (!(f > 0.0)) continue;
                    const std::string text = "L" + std::to_string(light.value("index", 0)) + " " +
                                             k.value("parameter", std::string()) + " clamped: " +
                                             std::to_string(int(std::lround(100.0 * f))) + "% of " +
                                             std::to_string(k.value("pixels", size_t(0))) + " px (cap " +
                                             std::to_string(int(std::lround(k.value("cap", 0.0)))) + ")";
                    if (f > 0.01)
                        ImGui::TextColored(ImVec4(1.0f, 0.65f, 0.2f, 1.0f), "%s", text.c_str());
                    else
                        ImGui::Text("%s", text.c_str());
                    tooltip("the penumbra of these pixels is wider than the kernel's cap: raise the parameter");
                }
            }
            ImGui::Text("UI %.0f fps (frame %.1f ms, render %.1f ms)", uiFps_, frameMs_, renderMs_);
            if (ref().active()) {
                float fraction = ref().total() > 0 ? float(ref().done()) / float(ref().total()) : 0.0f;
                char overlay[64];
                std::snprintf(overlay, sizeof overlay, "%s %d / %d %s", state_.referenceTechnique.c_str(), ref().done(),
                              ref().total(), ref().unit());
                ImGui::ProgressBar(fraction, ImVec2(220 * s, 0), overlay);
            }
            if (currentMetrics) {
                ImGui::Text("RMSE %.4f  PSNR %.1f dB   (all %zu px)", metricsAll_->rmse, metricsAll_->psnr, metricsAll_->pixels);
                ImGui::Text("RMSE %.4f  PSNR %.1f dB   (penumbra %zu px)", metricsPenumbra_->rmse, metricsPenumbra_->psnr,
                            metricsPenumbra_->pixels);
            } else if (!showsReference()) {
                ImGui::TextDisabled("RMSE / PSNR once the reference is complete");
            }
            if (state_.pickedPixel) ImGui::Text("picked pixel %d, %d", state_.pickedPixel->x, state_.pickedPixel->y);
            if (state_.errorView) {
                // the colour scale of shaders/window/present.frag's heat()
                ImDrawList* draw = ImGui::GetWindowDrawList();
                ImVec2 p = ImGui::GetCursorScreenPos();
                float w = 200 * s, h = 10 * s;
                const ImU32 stops[5] = {IM_COL32(0, 0, 0, 255), IM_COL32(26, 26, 179, 255), IM_COL32(204, 26, 153, 255),
                                        IM_COL32(255, 128, 0, 255), IM_COL32(255, 255, 102, 255)};
                for (int i = 0; i < 4; ++i)
                    draw->AddRectFilledMultiColor(ImVec2(p.x + w * i / 4, p.y), ImVec2(p.x + w * (i + 1) / 4, p.y + h), stops[i],
                                                  stops[i + 1], stops[i + 1], stops[i]);
                ImGui::Dummy(ImVec2(w, h));
                ImGui::Text("|V - V_ref|: 0 .. %.2f", state_.errorScale);
                if (!(ref().active() && ref().done() > 0)) ImGui::TextDisabled("waiting for the reference");
            }
            ImGui::End();
        }
    }

    // ---- status line
    if (!status_.empty() && std::chrono::duration<double>(clock::now() - statusTime_).count() < 5.0) {
        placeRegion(layout_.status);
        ImGui::SetNextWindowBgAlpha(0.6f);
        ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(6 * s, 2 * s));
        ImGui::Begin("##status", nullptr,
                     ImGuiWindowFlags_NoDecoration | fixed | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                         ImGuiWindowFlags_NoInputs);
        ImGui::PopStyleVar();
        if (statusError_) ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%s", status_.c_str());
        else ImGui::TextUnformatted(status_.c_str());
        ImGui::End();
    }

    // ---- F1
    if (state_.showHelp) {
        ImGui::SetNextWindowPos(ImVec2(size.x * 0.5f, size.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
        ImGui::SetNextWindowBgAlpha(0.92f);
        ImGui::Begin("Keys and mouse (F1 closes)", &state_.showHelp, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
        ImGui::TextUnformatted(helpText());
        ImGui::End();
    }

    if (state_.showViews) drawViewsPanel();
    (void)io;
}

}  // namespace shadowlab
