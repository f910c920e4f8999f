// Views of what a technique computes (DESIGN.md section 7): each a VTK pipeline (source algorithm
// -> filters -> mapper -> actor, STYLE.md 11) reading only the core's typed data: the renderer's
// internals (Renderer::internalRequests / writeInternals, the technique's InternalDesc list and
// its per-pixel records), the G-buffer and visibility read-backs, the scene and the lights. No
// view calls technique-specific code. The window, the lesson player and `shadowlab viz` all call
// renderView(); adding a view is one file and one registry line (viz/README.md).
#pragma once
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "text_box.h"

namespace shadowlab {

class Renderer;
struct LightState;
struct Scene;
class VtkOffscreen;
class OutputSet;

struct ViewRequest {
    std::string view;                  // a name of listViews(): "scene3d", "shadow-map", "internal", "error"
    std::optional<glm::ivec2> pixel;   // the picked pixel of the technique view (x, y from the top)
    std::string internal;              // `internal`: the internal's name ("" = the technique's first image
                                       // or pyramid); `shadow-map`: which depth map ("" = shadow_map)
    int light = 0;                     // whose internals (index into the scene's lights)
    int width = 640, height = 480;     // of the picture
    // 3D views: the camera orbits the default view by these (degrees) and zooms (> 1 = closer).
    float azimuth = 0.0f, elevation = 0.0f, zoom = 1.0f;
    int rays = 64;                     // scene3d: light samples traced from the picked point (1..4096)
    // error: the reference visibility (1 channel, the renderer's size). Null: renderView computes it
    // with the `reference` technique in the renderer's state, with `referenceSamples` light samples
    // (0: the technique's default, 1024).
    const Image* reference = nullptr;
    int referenceSamples = 0;
    // The largest share of the picture's height the caption may take. A caption that needs more
    // keeps its first lines and ends with a line saying the rest is in the tooltip (the window's
    // cells: a picture ~200 px high would otherwise hold nothing but its caption; the whole caption is
    // ViewResult::caption, the cell's tooltip). 0.9, the default, never cuts (headless, figures).
    float captionMaxShare = 0.9f;
    std::string exportPath;            // the view's data for ParaView (.vtp or .vti, see ViewInfo); "" = none
    OutputSet* outputs = nullptr;      // stages the export files (all-or-nothing); null: written directly
};

struct ViewResult {
    Image image;          // RGBA, row 0 at the top, opaque
    std::string caption;  // the text drawn under the picture (also for a panel's tooltip, tests)
    nlohmann::json data;  // the numbers behind the picture (picked point, metrics, ...)
    std::vector<TextBox> texts;  // every text drawn, with its box (style.h): the layout the tests check
};

struct ViewInfo {
    std::string name;
    std::string doc;
    std::string appliesTo;        // the rule, in words ("techniques with a 'shadow_map' internal")
    std::string exportExtension;  // ".vtp" (poly data) or ".vti" (image data)
};
std::vector<ViewInfo> listViews();

// "" when `request.view` applies to the renderer's current technique and request; else the reason.
// An unknown view, a pixel outside the image, an unknown light or a bad ray count or zoom are
// InputErrors.
std::string viewRefusal(const Renderer& renderer, const ViewRequest& request);
// The same for one light resolved without a renderer or a GL context (Renderer::resolveLights):
// what `lesson --check` asks of every `show` (the light, pixel and ray checks need the renderer).
std::string viewRefusal(const LightState& light, const ViewRequest& request);
// The picture's width / height at which the view's panels fill it (the error view's two frame
// images side by side: ~2x the frame's aspect; the shadow map with a close-up: ~1.4; a 3D view:
// 4:3), for a request the view does not refuse; 4:3 when it does.
// `frameAspect`: the technique frame's width / height the aspect is for (0: the renderer's; the
// window passes its technique region's, so a cell's aspect does not feed back into the frame's).
float viewAspect(const Renderer& renderer, const ViewRequest& request, float frameAspect = 0.0f);

// Renders the view into a new offscreen VTK frame. Needs the renderer's GL context current (and an
// EGL or window context: not OSMesa). Renders the frame data the view needs first (the renderer's
// graph reuses what is current). Throws InputError (exit code 2) with the reason when the view does
// not apply, the pixel lies outside the image, the light or internal does not exist, or the
// reference does not match. Writes the export (request.exportPath; a pyramid's level k > 0 beside it
// as <stem>-<k>.vti) through request.outputs when given.
ViewResult renderView(Renderer& renderer, const Scene& scene, const ViewRequest& request);
// The same into `out` (resized to the request), kept for a panel: out.texture() holds the picture.
// The view's pipelines stay in `out` until the next renderView into it (they hold copies of what
// they draw), so out.renderToTexture() redraws the same picture; call renderView again when the
// renderer's state, the pixel or the request changed.
ViewResult renderView(Renderer& renderer, const Scene& scene, const ViewRequest& request, VtkOffscreen& out);

}  // namespace shadowlab
