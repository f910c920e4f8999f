// For view authors: what a view is (ViewDesc), what it sees (ViewContext: the renderer's typed
// internals collected in memory, the lights, the frame read-backs), and the pipeline pieces every
// view shares (a source algorithm for custom geometry, image data, colour maps and bars, captions,
// writers). A new view is one file defining `const ViewDesc& myView()` and one line in the
// registry (SHADOWLAB_VIEWS in views.cpp); viz/README.md walks through one.
#pragma once
#include <vtkLookupTable.h>
#include <vtkPolyDataAlgorithm.h>
#include <vtkSmartPointer.h>

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "graph/internals.h"
#include "graph/renderer.h"
#include "style.h"
#include "views.h"
#include "vtk_offscreen.h"

class vtkActor;
class vtkImageData;
class vtkPolyData;
class vtkRenderer;
class vtkActor2D;
class vtkTextActor;
class vtkScalarBarActor;
class vtkPoints;
class vtkCellArray;

namespace shadowlab {

// ---- the renderer's internals, collected in memory (Renderer::writeInternals into a sink) ----------
struct CollectedInternal {
    std::string name;   // as the technique declares it
    std::string kind;   // "image", "pyramid", "mesh", "lines", "json", "record"
    std::string doc;    // the internal's doc line (pyramids: of level 0)
    std::vector<Image> levels;  // image: one; pyramid: every level, 0 first (row 0 at the top)
    MeshData mesh;
    nlohmann::json json;
};

class InternalCollector : public InternalSink {
public:
    void image(const std::string& name, const Image& image, const std::string& doc, const std::string& kind = "image",
               int level = -1) override;
    void mesh(const std::string& name, const MeshData& mesh, const std::string& kind, const std::string& doc) override;
    void json(const std::string& name, const nlohmann::json& value, const std::string& doc,
              const std::string& kind = "json") override;
    // Key: the light's prefix and the name, as --internals names the files ("shadow_map",
    // "light1/shadow_map"); "pixel" holds the per-pixel records of every light.
    std::map<std::string, CollectedInternal> entries;
};

// ---- what a view sees -------------------------------------------------------------------------------
class ViewContext {
public:
    ViewContext(Renderer& renderer, const Scene& scene, const ViewRequest& request, VtkOffscreen& out);
    Renderer& renderer;
    const Scene& scene;
    const ViewRequest& request;
    VtkOffscreen& out;

    const LightState& light() const;  // request.light
    // An internal of request.light by name (nullptr when the technique did not write it).
    const CollectedInternal* internal(const std::string& name) const;
    // request.light's per-pixel record (the fields of every Record internal; "pixel" merged in);
    // null json without a picked pixel.
    nlohmann::json pixelRecord() const;
    // The whole "pixel" entry: {pixel, position, visibility, lights: [...]}.
    nlohmann::json pixelData() const;
    // Where to write an export file that ends up at `path` (staged through request.outputs).
    std::string exportTarget(const std::string& path) const;

private:
    friend ViewResult renderView(Renderer&, const Scene&, const ViewRequest&, VtkOffscreen&);
    InternalCollector collected_;
};

// ---- what a view is ---------------------------------------------------------------------------------
struct ViewDesc {
    ViewInfo info;
    // "" when the view applies to the light's technique for this request; else the reason (the
    // refusal names the technique). Called before anything renders.
    std::function<std::string(const LightState&, const ViewRequest&)> refusal;
    // Builds the pipelines into ctx.out (renderers, actors), fills the caption and data, and writes
    // the export when asked. renderView renders the picture afterwards.
    std::function<void(ViewContext& ctx, ViewResult& result)> build;
    // The picture's width / height at which its panels fill it (the window gives each view a cell of
    // this aspect) when the technique's frame has aspect `frame`; null: 4:3. Called for a request
    // the view does not refuse.
    std::function<float(const Renderer&, const ViewRequest&, float frame)> aspect;
};

// The share of a view's height its caption strip takes at the window's cell sizes (addCaptionStrip:
// two or three lines under a picture ~300 px high), for the aspect rules.
constexpr float kCaptionShare = 0.15f;
// The aspect of `panels` frame-size images side by side, each with its colour bar beside it
// (addImagePanelWithBar), over the caption strip.
float framePanelsAspect(float frameAspect, int panels);

// ---- pipeline pieces --------------------------------------------------------------------------------
// A source algorithm whose output is made by a function (custom geometry: light shapes, frusta,
// rays, scene meshes). The function fills an empty vtkPolyData.
class FunctionSource : public vtkPolyDataAlgorithm {
public:
    static FunctionSource* New();
    vtkTypeMacro(FunctionSource, vtkPolyDataAlgorithm);
    void SetGenerator(std::function<void(vtkPolyData*)> generator);

protected:
    FunctionSource();
    int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
    std::function<void(vtkPolyData*)> generator_;
};

// An Image (row 0 at the top) as vtkImageData with VTK's origin at the bottom-left, so that point
// (i, j) is texel (x = i, y = j from the bottom) as GL and the pixel records count it. One point
// array per channel, named by `channelNames` (else "c0", "c1", ...); non-finite values become NaN.
vtkSmartPointer<vtkImageData> toImageData(const Image& image, const std::vector<std::string>& channelNames = {});

// Colour maps: a sequential map (dark blue -> yellow, perceptually ordered like viridis) and a
// diverging one (blue -> white -> red, symmetric about 0). NaN shows as `nanRgb`.
vtkSmartPointer<vtkLookupTable> sequentialLut(double lo, double hi, glm::vec3 nanRgb = kBackgroundGrey);
vtkSmartPointer<vtkLookupTable> divergingLut(double maxAbs);
// Colour bars: addColourBar / colourBarWidthPx (style.h), whose texts are measured.
// Caption text at the bottom-left of a viewport (the text standard's size, style.h textPx).
vtkSmartPointer<vtkTextActor> captionActor(const std::string& text, int frameHeight);
// A strip along the bottom of the frame holding the caption (one line per '\n', long lines wrapped
// to the frame's width, never shrunk; cut to its first lines only where out.captionMaxShare() asks,
// see captionStripLayout); returns its height as a fraction of the frame, for the panels
// to start above it.
double addCaptionStrip(VtkOffscreen& out, const std::string& caption, bool monospace = false);
// How addCaptionStrip lays a caption out: the text drawn (wrapped; where the strip would take more
// than out.captionMaxShare() of the height, its first lines and kCaptionContinues), the strip's
// share of the height and the text's margin in pixels. For a view that sizes its panels from the
// strip before drawing it.
struct CaptionStrip {
    std::string text;
    double share = 0.0;
    int margin = 0;
    bool cut = false;  // lines were left out (the whole caption is ViewResult::caption)
};
CaptionStrip captionStripLayout(const VtkOffscreen& out, const std::string& caption, bool monospace = false);
// The last line of a caption cut to fit a window cell.
inline constexpr const char* kCaptionContinues = "... (the rest: hover the view)";
// Parallel camera of an image panel showing all of a width x height image in a viewport of
// `viewportAspect` (width / height), with a small margin.
void fitImage(vtkRenderer* renderer, int width, int height, double viewportAspect);
// A title at the top-left of a renderer's viewport.
vtkSmartPointer<vtkTextActor> titleActor(const std::string& text, int frameHeight);
// Renders an image as a flat colour-mapped picture filling `renderer`'s viewport (parallel
// camera); returns the image actor's bounds for overlays.
void addImagePanel(vtkRenderer* renderer, vtkImageData* image, const std::string& array, vtkLookupTable* lut);
// An image panel with its colour bar and title in the frame rectangle [x0, x1] x [y0, y1]
// (fractions of the frame): the image on the left 80%, the bar on the right.
void addImagePanelWithBar(VtkOffscreen& out, vtkImageData* image, const std::string& array, vtkLookupTable* lut,
                          const std::string& title, const std::string& barTitle, double x0, double y0, double x1,
                          double y1);
// A pyramid as a stack of levels in 3D (level 0 at the bottom, level k scaled by 2^k so each covers
// the same footprint), one colour scale over all levels with its bar, above the frame's y0.
// Returns the colour range (channel 0).
std::pair<float, float> addPyramidStack(VtkOffscreen& out, const std::vector<Image>& levels, const std::string& channel,
                                        const std::string& title, double y0, float zoom = 1.0f);
// Lines (pairs of points) as a 2D-overlay actor in world coordinates of an image panel, z above it.
vtkSmartPointer<vtkActor> lineActor(const std::vector<std::pair<glm::vec3, glm::vec3>>& lines, glm::vec3 rgb,
                                    float width);

// World-space triangles of the scene's objects at time t (casters only when castersOnly), each
// with its object's index.
struct WorldTriangle {
    glm::vec3 a, b, c;
    int object;
};
std::vector<WorldTriangle> worldTriangles(const Scene& scene, double t, bool castersOnly);

// ---- the 3D volume views (wedges, penumbra-volumes) --------------------------------------------------
// A distinct colour per silhouette edge: hues a golden angle apart, saturated and bright.
glm::vec3 edgeColour(int edge);
// The light's outline in world space (a square's four sides, a disk's or sphere's circle of 64
// segments in the light's plane); none for a point light.
std::vector<std::pair<glm::vec3, glm::vec3>> lightOutlineSegments(const Light& light);
// Lines and triangles with the volume views' cell arrays: part, edge, face, holds_pixel and an RGBA
// colour (alpha, so translucent parts blend). VTK orders lines before polys in the cell data.
struct ViewCells {
    struct Attributes {
        int part, edge, face, holds;
        std::array<unsigned char, 4> rgba;
    };
    ViewCells();
    static std::array<unsigned char, 4> bytes(glm::vec3 c, float alpha);
    void line(glm::vec3 a, glm::vec3 b, Attributes at);
    void triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, Attributes at);
    vtkSmartPointer<vtkPolyData> data();

    vtkSmartPointer<vtkPoints> points;
    vtkSmartPointer<vtkCellArray> lines, polys;
    std::vector<Attributes> lineAttributes, polyAttributes;
};
// An actor colouring cells by their "colour" array; `blend`: drawn after the opaque parts with GL
// blending (VTK's translucent pass blits a depth buffer the offscreen frame cannot give it).
vtkSmartPointer<vtkActor> cellsActor(vtkPolyData* data, float lineWidth, bool lit, bool blend);

// The 3D views' camera: the scene camera's view, orbited by azimuth and elevation (degrees), at a
// 30 degree view angle (the caller fits it to what it draws).
void orbitSceneCamera(vtkRenderer* renderer, const Camera& camera, double azimuth, double elevation);
// A ball marking a picked point (unlit, in `rgb`).
vtkSmartPointer<vtkActor> pointMarker(glm::vec3 point, double radius, glm::vec3 rgb);

// Writers (XML, binary appended): .vtp / .vti. Throw InternalError when VTK cannot write.
void writePolyData(vtkPolyData* data, const std::string& path);
void writeImageData(vtkImageData* data, const std::string& path);

// The finite range of channel `c` of an image (lo > hi when no value is finite).
std::pair<float, float> finiteRange(const Image& image, int c = 0);
// "%.6g"-style short number for captions.
std::string formatNumber(double v, int digits = 4);

// ---- the screen-space multi-resolution views (skipped-pixels, pull-push) ----------------------------
// "" when the light's technique writes the internals `names` now; else why not: it has none, or
// only while screen_adaptive is on (the reason says to turn it on).
std::string screenAdaptiveRefusal(const Renderer& renderer, const ViewRequest& request, const std::vector<std::string>& names);
// The pixels of each code SEL_BACKGROUND (0) .. SEL_SKIPPED (6) of a `selection` image, exactly
// those the skipped-pixels view colours (InternalError on any other value).
std::array<size_t, 7> selectionCounts(const Image& selection);

// ---- the registry (views.cpp) ---------------------------------------------------------------------
const std::vector<const ViewDesc*>& allViews();
const ViewDesc* findView(const std::string& name);

}  // namespace shadowlab
