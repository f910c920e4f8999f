// The window's views panel: the VTK views of viz/views.h (scene3d, shadow-map, internal, error),
// each rendered by renderView() into its own VtkOffscreen frame whose texture the panel shows.
// A view re-renders when the rendered state (version_), the picked pixel or its own orbit changed;
// at most one per frame and never while the user drags (a view costs a VTK render on llvmpipe).
// Dragging over a 3D view orbits it, the wheel zooms it.
#include <imgui.h>

#include <algorithm>

#include "error.h"
#include "views.h"
#include "vtk_offscreen.h"
#include "window/window.h"

namespace shadowlab {

void Window::openView(const std::string& name) {
    std::vector<ViewInfo> all = listViews();
    if (std::none_of(all.begin(), all.end(), [&](const ViewInfo& v) { return v.name == name; })) {
        std::string names;
        for (const ViewInfo& v : all) names += (names.empty() ? "" : ", ") + v.name;
        setStatus("unknown view '" + name + "' (expected one of: " + names + ")", true);
        return;
    }
    state_.showViews = true;
    if (std::find(state_.openViews.begin(), state_.openViews.end(), name) == state_.openViews.end())
        state_.openViews.push_back(name);
}

void Window::closeView(const std::string& name) {
    state_.openViews.erase(std::remove(state_.openViews.begin(), state_.openViews.end(), name), state_.openViews.end());
    if (state_.enlargedView == name) state_.enlargedView.clear();
}

void Window::enlargeView(const std::string& name) {
    if (name.empty() || name == "off") {
        state_.enlargedView.clear();
        return;
    }
    openView(name);  // refuses an unknown name in the status line
    if (std::find(state_.openViews.begin(), state_.openViews.end(), name) != state_.openViews.end()) state_.enlargedView = name;
}

void Window::syncViewList() {
    // One OpenView per name in the state (the state is what lessons and scripts set). Runs before
    // the UI is built: a view's texture must outlive the frame whose draw list shows it.
    views_.erase(std::remove_if(views_.begin(), views_.end(),
                                [&](const auto& v) {
                                    return std::find(state_.openViews.begin(), state_.openViews.end(), v->name) ==
                                           state_.openViews.end();
                                }),
                 views_.end());
    // A frame resized by updateViews after the last UI was built kept its old texture for that
    // UI's draw list; it has been drawn.
    for (const auto& v : views_)
        if (v->frame) v->frame->releaseRetired();
    if (std::find(state_.openViews.begin(), state_.openViews.end(), state_.enlargedView) == state_.openViews.end())
        state_.enlargedView.clear();
    for (const std::string& name : state_.openViews)
        if (std::none_of(views_.begin(), views_.end(), [&](const auto& v) { return v->name == name; })) {
            auto v = std::make_unique<OpenView>();
            v->name = name;
            views_.push_back(std::move(v));
        }
}

void Window::updateViews() {
    if (!state_.showViews || views_.empty() || interacting() || reduced_ || !imageComplete_) return;

    const float s = state_.uiScale;
    glm::ivec2 pixel = state_.pickedPixel.value_or(glm::ivec2(-1));
    for (size_t index = 0; index < views_.size(); ++index) {
        auto& v = views_[index];
        // Rendered at its cell's size (window/layout.h), less the title line and the caption band,
        // so a view is as legible as its cell allows (300 x 225 x scale when it has no cell).
        int w = int(300 * s), h = int(225 * s);
        if (v->name == state_.enlargedView && !layout_.technique.empty()) {
            // Enlarged: the technique view's region less the title line (drawViewsPanel).
            w = std::max(64, int(layout_.technique.w - 4.0f * s));
            h = std::max(48, int(layout_.technique.h - (17.0f + 10.0f) * s));
        } else if (index < layout_.cells.size() && !layout_.cells[index].empty()) {
            // The title line, and the pick hint under the first view while no pixel is picked; the
            // caption is drawn inside the picture (and shown again as its tooltip), not under it.
            const float band = (17.0f * (!state_.pickedPixel && index == 0 ? 2.0f : 1.0f) + 10.0f) * s;
            w = std::max(64, int(layout_.cells[index].w - 4.0f * s));
            h = std::max(48, int(layout_.cells[index].h - band));
        }
        bool error = v->name == "error";
        bool haveReference = ref().complete() && referenceVersion_ == version_;
        std::vector<double> key = {double(version_), double(pixel.x), double(pixel.y), v->azimuth, v->elevation,
                                   v->zoom, double(w), double(h),
                                   error ? double(haveReference ? ref().generation() : ~0ull) : 0.0};
        if (key == v->renderedKey) continue;
        v->renderedKey = key;
        if (error && !haveReference) {
            v->valid = false;
            v->refusal = "waiting for the reference (" + std::to_string(ref().done()) + " / " +
                         std::to_string(ref().total()) + " " + ref().unit() + "; B turns it on)";
            continue;
        }
        ViewRequest request;
        request.view = v->name;
        request.pixel = state_.pickedPixel;
        request.light = std::clamp(state_.lightIndex, 0, std::max(0, int(scene_->lights.size()) - 1));
        request.width = w;
        request.height = h;
        request.azimuth = v->azimuth;
        request.elevation = v->elevation;
        request.zoom = v->zoom;
        // A cell is a few hundred pixels high: a long caption keeps its first lines (the whole of it
        // is the cell's tooltip), so the picture keeps at least 60% of the cell.
        // Enlarged, the view has room for its whole caption (the request's default).
        if (v->name != state_.enlargedView) request.captionMaxShare = 0.4f;
        if (error) {
            if (referenceImageGeneration_ != ref().generation()) {
                referenceImage_ = ref().visibility();
                referenceImageGeneration_ = ref().generation();
            }
            request.reference = &referenceImage_;
        }
        try {
            std::string why = viewRefusal(*renderer_, request);
            if (!why.empty()) {
                v->valid = false;
                v->refusal = why;
                continue;
            }
            if (!v->frame) v->frame = std::make_unique<VtkOffscreen>(w, h);
            if (v->frame->width() != w || v->frame->height() != h) v->frame->resize(w, h);
            ViewResult result = renderView(*renderer_, *scene_, request, *v->frame);
            v->caption = result.caption;
            v->refusal.clear();
            v->valid = true;
        } catch (const InputError& e) {
            v->valid = false;
            v->refusal = e.what();
        }
        break;  // one view per frame: the UI stays responsive
    }
}

// The views strip (window/layout.h): one fixed window per open view, in its cell under the
// technique view; the image scaled into the cell at its own aspect, its caption below. The
// enlarged view (WindowState::enlargedView) is drawn over the technique view's region, rendered at
// that size (updateViews), and its cell keeps its title line with a "restore" button: a lecturer
// shows one view as large as the frame at 1024x768, where a cell's picture is about 190 x 150.
void Window::drawViewsPanel() {
    const float s = state_.uiScale;
    std::string toClose, toEnlarge;
    bool restore = false;
    const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                   ImGuiWindowFlags_NoTitleBar;
    // What to draw: every view in its cell, and the enlarged one again over the technique view.
    struct Place {
        size_t index;
        LayoutRect region;
        bool enlarged;
    };
    std::vector<Place> places;
    for (size_t i = 0; i < views_.size(); ++i) {
        if (i < layout_.cells.size() && !layout_.cells[i].empty()) places.push_back({i, layout_.cells[i], false});
        if (views_[i]->name == state_.enlargedView && !layout_.technique.empty()) places.push_back({i, layout_.technique, true});
    }
    for (const Place& place : places) {
        const size_t i = place.index;
        auto& v = views_[i];
        const bool enlarged = place.enlarged;
        const bool isEnlarged = v->name == state_.enlargedView && !layout_.technique.empty();  // shown over it
        placeRegion(place.region);
        ImGui::SetNextWindowBgAlpha(enlarged ? 1.0f : 0.92f);
        ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(2 * s, 2 * s));
        ImGui::Begin(("##view " + v->name + (enlarged ? " enlarged" : "")).c_str(), nullptr, fixed);
        ImGui::PopStyleVar();
        // The title line: the name, then the two buttons at the line's right end, where they are in
        // every cell. A 1024x768 cell's line has about 190 px: "skipped-pixels close enlarge" did
        // not fit and the last button was cut; the name gives way (clipped) instead, since the
        // view's picture prints its own title.
        const char* second = isEnlarged ? "restore" : "enlarge";
        const float gap = 3.0f * s;
        const auto buttonWidth = [](const char* label) {
            return ImGui::CalcTextSize(label).x + 2.0f * ImGui::GetStyle().FramePadding.x;
        };
        const float buttons = buttonWidth("close") + gap + buttonWidth(second);
        const float line = ImGui::GetContentRegionAvail().x;
        const float nameRoom = std::max(0.0f, line - buttons - gap);
        const ImVec2 nameAt = ImGui::GetCursorScreenPos();
        ImGui::PushClipRect(nameAt, ImVec2(nameAt.x + nameRoom, nameAt.y + ImGui::GetTextLineHeightWithSpacing()), true);
        ImGui::TextUnformatted(v->name.c_str());
        ImGui::PopClipRect();
        ImGui::SameLine(ImGui::GetCursorStartPos().x + std::max(0.0f, line - buttons));
        ImGui::PushID(v->name.c_str());
        ImGui::PushID(enlarged ? 1 : 0);
        if (ImGui::SmallButton("close")) toClose = v->name;
        ImGui::SameLine(0.0f, gap);
        if (isEnlarged) {
            if (ImGui::SmallButton("restore")) restore = true;
        } else if (ImGui::SmallButton("enlarge")) {
            toEnlarge = v->name;
        }
        ImGui::PopID();
        ImGui::PopID();
        // Under the picture only the pick hint (first view, no pixel picked): the view draws its
        // caption itself, so a second copy here only took the picture's room (at 1024x768 with two
        // views the two copies filled the cells).
        const bool hint = !state_.pickedPixel && i == 0 && !enlarged;
        static const char* kPickHint = "Ctrl+click in the image picks the pixel the views show";
        const ImVec2 avail = ImGui::GetContentRegionAvail();
        // The hint as tall as it wraps in the cell (two lines in a 1024x768 cell; one line's band
        // cut its second line off).
        const float captionBand =
            hint ? ImGui::CalcTextSize(kPickHint, nullptr, false, avail.x).y + ImGui::GetStyle().ItemSpacing.y : 0.0f;
        if (isEnlarged && !enlarged) {
            ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + avail.x);
            ImGui::TextDisabled("shown enlarged over the technique view (restore puts it back)");
            ImGui::PopTextWrapPos();
        } else if (v->valid && v->frame) {
            const float aspect = float(v->frame->width()) / float(std::max(1, v->frame->height()));
            float h = std::max(1.0f, avail.y - captionBand), w = h * aspect;
            if (w > avail.x) w = avail.x, h = w / aspect;
            ImVec2 picture(w, h);
            // GL's row 0 is the bottom: flip v.
            ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(v->frame->texture())), picture,
                         ImVec2(0, 1), ImVec2(1, 0));
            if (v->name == "scene3d" && ImGui::IsItemHovered()) {
                ImGuiIO& io = ImGui::GetIO();
                if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
                    v->azimuth -= io.MouseDelta.x * 0.5f;
                    v->elevation = std::clamp(v->elevation + io.MouseDelta.y * 0.5f, -89.0f, 89.0f);
                }
                if (io.MouseWheel != 0.0f) v->zoom = std::clamp(v->zoom * (io.MouseWheel > 0 ? 1.1f : 1.0f / 1.1f), 0.1f, 20.0f);
            }
            // The whole caption as the cell's tooltip (an enlarged view prints all of it already).
            if (!enlarged && ImGui::IsItemHovered() && !v->caption.empty() && !ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
                ImGui::BeginTooltip();
                ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
                ImGui::TextUnformatted(v->caption.c_str());
                ImGui::PopTextWrapPos();
                ImGui::EndTooltip();
            }
        } else if (!v->refusal.empty()) {
            ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + avail.x);
            ImGui::TextDisabled("%s", v->refusal.c_str());
            ImGui::PopTextWrapPos();
        } else {
            ImGui::TextDisabled("rendering ...");
        }
        if (hint) {
            ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + avail.x);
            ImGui::TextDisabled("%s", kPickHint);
            ImGui::PopTextWrapPos();
        }
        ImGui::End();
    }
    if (!toClose.empty()) closeView(toClose);
    if (restore) enlargeView("off");
    if (!toEnlarge.empty()) enlargeView(toEnlarge);
}

}  // namespace shadowlab
