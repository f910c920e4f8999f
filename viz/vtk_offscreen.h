// The bridge between VTK and the GL context the program made (DESIGN.md sections 7 and 11): VTK
// renders with vtkGenericOpenGLRenderWindow into the current context (headless EGL from
// techniques/core/gl/context.h, or the window's GLFW one), never into a window of its own, so views
// and charts need no X server. Each render() draws into a frame of our own (a GL texture the window
// can show in a panel) and returns it as an RGBA Image.
//
//   3D views:  VtkOffscreen out(640, 480);
//              vtkRenderer* r = out.addRenderer();  r->AddActor(...);
//              Image rgba = out.render();            // 4 channels in [0,1], row 0 at the top
//   2D charts: vtkNew<vtkContextView> view;  out.attach(view);  view->GetScene()->AddItem(chart);
//              Image rgba = out.render();
//              // vector export: vtkSVGExporter/vtkPDFExporter with SetRenderWindow(out.window()),
//              // SetFileName, Write() (see exportVector below)
//
// GL state: render() saves and restores the state the program's passes rely on (framebuffer
// bindings, viewport, scissor, program, vertex array, texture bindings of units 0..15 and the active
// unit, buffer bindings, pixel store, enables, depth/colour masks, blend, clear values). The
// project's passes set their fixed-function state with PipelineState::apply() anyway; anything
// else a caller keeps bound across a render() must be re-bound by the caller (image units, SSBO and
// UBO indexed bindings, samplers are not touched by VTK's surface and chart rendering and are not
// saved).
//
// Multisampling is off (5x slower on llvmpipe). GLEW inside VTK reports error 4 (no GLX display)
// under EGL yet loads every function: that one message is filtered; every other VTK error or
// warning is printed and counted in vtkMessages() (tests assert none).
#pragma once
#include <string>

#include "image/image.h"

class vtkContextView;
class vtkGenericOpenGLRenderWindow;
class vtkRenderer;

namespace shadowlab {

// VTK's error and warning messages since the start of the process (the harmless GLEW one aside).
struct VtkMessages {
    int errors = 0;
    int warnings = 0;
    std::string last;
};
VtkMessages& vtkMessages();
// Routes VTK's messages through vtkMessages() (idempotent; VtkOffscreen calls it).
void installVtkMessageFilter();

class VtkOffscreen {
public:
    // Needs a current GL 4.5 context (the program's own); renders at width x height pixels.
    VtkOffscreen(int width, int height);
    ~VtkOffscreen();
    VtkOffscreen(const VtkOffscreen&) = delete;
    VtkOffscreen& operator=(const VtkOffscreen&) = delete;

    // The window VTK renders with (for exporters, or for adding renderers yourself). Do not call
    // its Render() directly: use render(), which binds our frame and keeps the GL state.
    vtkGenericOpenGLRenderWindow* window() const;
    // A new renderer covering the whole frame (set its viewport to share the frame).
    vtkRenderer* addRenderer();
    // Makes a 2D context view (vtkChartXY ...) render into this window.
    void attach(vtkContextView* view);

    // A new frame of that size. The old frame's texture() stays valid until releaseRetired() (or the
    // next resize): a UI that recorded it in a draw list this frame may still draw it.
    void resize(int width, int height);
    void releaseRetired();
    int width() const { return width_; }
    int height() const { return height_; }

    // Renders every renderer of the window into our frame and reads it back: RGBA, values in [0,1]
    // (8-bit colours divided by 255), row 0 at the top, alpha 1 (opaque, ready for writePNG). The current context must be the one the
    // object was made in.
    Image render();
    // Renders without reading back; the frame stays in texture() (GL_RGBA8, row 0 at the BOTTOM as
    // GL stores it), for the window's ImGui panel.
    void renderToTexture();
    unsigned int texture() const { return colorTexture_; }

    // Writes the window's 2D context scene (charts) as SVG (".svg") or PDF (".pdf") with
    // vtkSVGExporter / vtkPDFExporter. InputError for another extension. Writes `path` directly:
    // callers stage it through an OutputSet.
    void exportVector(const std::string& path);

    // The largest share of the frame's height a view's caption strip may take (addCaptionStrip,
    // viz/view_common.h). 0.9 (the default): the caption is wrapped and its strip grows, as in
    // headless views and figures; the window's small cells ask less (ViewRequest::captionMaxShare).
    void setCaptionMaxShare(float share) { captionMaxShare_ = share; }
    float captionMaxShare() const { return captionMaxShare_; }

private:
    void allocateFrame();
    void releaseFrame();
    int width_ = 0, height_ = 0;
    float captionMaxShare_ = 0.9f;
    struct Impl;
    Impl* impl_ = nullptr;
    unsigned int fbo_ = 0, colorTexture_ = 0, depthBuffer_ = 0;
    unsigned int retiredTexture_ = 0;  // the colour texture before the last resize
};

}  // namespace shadowlab
