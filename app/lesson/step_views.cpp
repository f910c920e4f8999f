// The views of a lesson step. This is the one place that turns a view name into pictures: the
// visibility buffers as grey images here, every other view through viz/views.h (renderView).
#include <algorithm>
#include <cmath>
#include <map>

#include "bench/compare.h"
#include "error.h"
#include "vtk_offscreen.h"
#include "gl/texture.h"
#include "image/metrics.h"
#include "lesson/headless.h"
#include "views.h"

#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkNew.h>
#include <vtkRenderer.h>

namespace shadowlab {

namespace {

Image grey(const Image& v) {
    Image out(v.width, v.height, 3);
    for (size_t i = 0; i < v.pixelCount(); ++i) {
        float x = std::isfinite(v.data[i]) ? std::clamp(v.data[i], 0.0f, 1.0f) : 0.0f;
        for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = x;
    }
    return out;
}

// Nearest-neighbour resampling: a small shadow map keeps its texels visible (aliasing).
Image resampleNearest(const Image& in, int width, int height) {
    Image out(width, height, in.channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            int sx = std::min(in.width - 1, x * in.width / width), sy = std::min(in.height - 1, y * in.height / height);
            for (int c = 0; c < in.channels; ++c) out.at(x, y, c) = in.at(sx, sy, c);
        }
    return out;
}

// "shadow-map-texels": light-view depth as grey: nearer is darker; no caster (the far marker) is white. The map is
// fitted to the whole scene, so the casters may cover a small part of it: the view shows the square
// around the texels that hold a caster (with a margin of a quarter of its side), each texel as a
// block of pixels, so aliasing shows texel by texel.
Image shadowMapView(Renderer& r, int width, int height) {
    const Resource* map = r.pool().find("L0/shadow_map");
    if (!map) throw InputError("lesson: the shadow-map view needs a shadow-map technique on light 0");
    Image depth = readTextureLevel(map->texture, 0);
    float lo = INFINITY, hi = -INFINITY;
    int x0 = depth.width, y0 = depth.height, x1 = -1, y1 = -1;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            float z = depth.at(x, y);
            if (z >= 1e30f) continue;
            lo = std::min(lo, z), hi = std::max(hi, z);
            x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
        }
    if (x1 < 0) x0 = y0 = 0, x1 = depth.width - 1, y1 = depth.height - 1;  // no caster: the whole map
    int side = std::max(x1 - x0 + 1, y1 - y0 + 1);
    side = std::min(std::max(depth.width, depth.height), side + side / 2);
    int cx = (x0 + x1 + 1) / 2, cy = (y0 + y1 + 1) / 2;
    int sx = std::clamp(cx - side / 2, 0, std::max(0, depth.width - side));
    int sy = std::clamp(cy - side / 2, 0, std::max(0, depth.height - side));
    Image g(std::min(side, depth.width), std::min(side, depth.height), 1);
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            float z = depth.at(sx + x, sy + y);
            g.at(x, y) = z >= 1e30f ? 1.0f : hi > lo ? 0.1f + 0.7f * (z - lo) / (hi - lo) : 0.5f;
        }
    return grey(resampleNearest(g, width, height));
}

// A red ring around the picked pixel, open at the centre so the pixel itself stays visible.
void markPixel(Image& img, glm::ivec2 p) {
    for (int dy = -6; dy <= 6; ++dy)
        for (int dx = -6; dx <= 6; ++dx) {
            float d = std::sqrt(float(dx * dx + dy * dy));
            if (d < 3.5f || d > 5.5f) continue;
            int x = p.x + dx, y = p.y + dy;
            if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
            img.at(x, y, 0) = 1.0f;
            img.at(x, y, 1) = 0.1f;
            img.at(x, y, 2) = 0.1f;
        }
}

Image accuracyTimeView(RendererLessonHost& host) {
    AccuracyTimePanel panel{host.sceneName() + ": RMSE against the step's reference, " + std::to_string(host.width()) +
                                "x" + std::to_string(host.height()),
                            lessonAccuracyPoints(host)};
    const int width = std::max(host.width(), 960), height = width * 5 / 8;
    AccuracyTimeStyle style;
    style.panelHeight = height;
    VtkOffscreen out(width, height);
    vtkNew<vtkContextView> view;
    out.attach(view);
    view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    view->GetScene()->AddItem(buildAccuracyTimeChart(panel, style));
    Image rgba = out.render();
    Image rgb(rgba.width, rgba.height, 3);
    for (size_t i = 0; i < rgba.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) rgb.data[i * 3 + c] = rgba.data[i * rgba.channels + c];
    return rgb;
}

}  // namespace

std::vector<AccuracyTimePoint> lessonAccuracyPoints(RendererLessonHost& host, int frames) {
    Scene scene = host.scene();
    scene.lights = host.lights();
    scene.camera = host.camera();
    const Image reference = host.reference().visibility();
    const bool cpuClock = std::string(host.technique().clockName()) == "cpu-finish";
    const TechniqueDesc& desc = requireTechnique(host.techniqueId(), "lesson");
    ParamValues shown(desc);
    for (const auto& [k, v] : host.techniqueParams()) shown.set(desc, k, v, "lesson");
    std::vector<AccuracyTimePoint> points;
    for (const ChartSetting& s : comparedSettings(host.techniqueId(), &shown))
        points.push_back(measureChartSetting(scene, host.sceneName(), host.width(), host.height(), s, reference, cpuClock, frames));
    return points;
}

Image renderLessonView(RendererLessonHost& host, const std::string& view) {
    if (view == "technique") {
        Image img = host.technique().image();
        if (!host.split().empty()) {
            // Left half: the technique; right half: what it is compared with; a white seam between.
            Image other = host.splitRenderer().image();
            int seam = img.width / 2;
            for (int y = 0; y < img.height; ++y)
                for (int x = seam; x < img.width; ++x)
                    for (int c = 0; c < 3; ++c) img.at(x, y, c) = x == seam ? 1.0f : other.at(x, y, c);
        }
        if (auto p = host.pickedPixel()) markPixel(img, *p);
        return img;
    }
    if (view == "visibility") return grey(host.technique().visibility());
    if (view == "reference") return grey(host.reference().visibility());
    if (view == "shadow-map-texels") return shadowMapView(host.technique(), host.width(), host.height());
    if (view == "accuracy-time") return accuracyTimeView(host);
    // The VTK views (viz/): the picked pixel, and the lesson's reference for the error view.
    ViewRequest request;
    request.view = view;
    request.pixel = host.pickedPixel();
    // VTK views carry captions, colour bars and close-ups: at least 480x360 to stay readable.
    request.width = std::max(host.width(), 480);
    request.height = request.width * 3 / 4;
    Image reference;
    if (view == "error") {
        reference = host.reference().visibility();
        request.reference = &reference;
    }
    Renderer& renderer = host.technique();
    return renderView(renderer, host.scene(), request).image;
}

void checkLessonViews(const Lesson& lesson) {
    std::map<std::string, Scene> scenes;
    const std::vector<ViewInfo> vtkViews = listViews();
    for (const LessonStep& step : lesson.steps)
        for (const LessonState* state : {&step.state, step.answerState ? &*step.answerState : nullptr}) {
            if (!state) continue;
            for (const std::string& view : state->views) {
                // The pictures made here (technique, visibility, reference, texels) apply to every technique.
                if (std::none_of(vtkViews.begin(), vtkViews.end(), [&](const ViewInfo& v) { return v.name == view; }))
                    continue;
                auto it = scenes.find(state->scene);
                if (it == scenes.end()) it = scenes.emplace(state->scene, loadScene(state->scene)).first;
                Scene scene = it->second;
                scene.lights = state->lights;
                RenderOptions options;
                options.technique = state->technique;
                options.sets = state->paramTexts();
                const std::string where = step.where.str() + ": show " + view + " (technique " + state->technique + "): ";
                const std::vector<LightState> lights = Renderer::resolveLights(scene, options);
                if (lights.empty()) throw InputError(where + "view " + view + ": the scene has no light");
                ViewRequest request;
                request.view = view;
                if (state->pick) request.pixel = glm::ivec2(0);  // the refusals ask whether a pixel is picked, not which
                if (std::string why = viewRefusal(lights.front(), request); !why.empty())
                    throw InputError(where + "view " + view + ": " + why);
            }
        }
}

}  // namespace shadowlab
