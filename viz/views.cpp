#include "views.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRendererCollection.h>
#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapToColors.h>
#include <vtkImageMapper3D.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <cstdio>

#include "error.h"
#include "gl/loader.h"
#include <vtkSphereSource.h>
#include "view_common.h"
#include "style.h"

namespace shadowlab {

// ---- the registry: one line per view; the view's own file defines the function ---------------------
#define SHADOWLAB_VIEWS(X) X(scene3dView) X(shadowMapView) X(internalView) X(errorView) X(kernelSizeView) X(reuseView) X(backprojectionView) X(hsmView) X(wedgesView) X(penumbraVolumesView) X(pullPushView) X(skippedPixelsView) X(spsmTexelsView)

#define SHADOWLAB_DECLARE_VIEW(fn) const ViewDesc& fn();
SHADOWLAB_VIEWS(SHADOWLAB_DECLARE_VIEW)
#undef SHADOWLAB_DECLARE_VIEW

const std::vector<const ViewDesc*>& allViews() {
#define SHADOWLAB_LIST_VIEW(fn) &fn(),
    static const std::vector<const ViewDesc*> views = {SHADOWLAB_VIEWS(SHADOWLAB_LIST_VIEW)};
#undef SHADOWLAB_LIST_VIEW
    return views;
}

const ViewDesc* findView(const std::string& name) {
    for (const ViewDesc* v : allViews())
        if (v->info.name == name) return v;
    return nullptr;
}

std::vector<ViewInfo> listViews() {
    std::vector<ViewInfo> out;
    for (const ViewDesc* v : allViews()) out.push_back(v->info);
    return out;
}

static const ViewDesc& requireView(const std::string& name) {
    if (const ViewDesc* v = findView(name)) return *v;
    std::string names;
    for (const ViewDesc* v : allViews()) names += (names.empty() ? "" : ", ") + v->info.name;
    throw InputError("--view: unknown view '" + name + "' (expected one of: " + names + ")");
}

// ---- collected internals --------------------------------------------------------------------------
void InternalCollector::image(const std::string& name, const Image& img, const std::string& doc,
                              const std::string& kind, int level) {
    CollectedInternal& e = entries[prefix_ + name];
    e.name = name;
    e.kind = kind;
    if (level <= 0) e.doc = doc;
    size_t index = size_t(std::max(level, 0));
    if (e.levels.size() <= index) e.levels.resize(index + 1);
    e.levels[index] = img;
}

void InternalCollector::mesh(const std::string& name, const MeshData& mesh, const std::string& kind,
                             const std::string& doc) {
    CollectedInternal& e = entries[prefix_ + name];
    e.name = name;
    e.kind = kind;
    e.doc = doc;
    e.mesh = mesh;
}

void InternalCollector::json(const std::string& name, const nlohmann::json& value, const std::string& doc,
                             const std::string& kind) {
    CollectedInternal& e = entries[prefix_ + name];
    e.name = name;
    e.kind = kind;
    e.doc = doc;
    e.json = value;
}

// ---- the context ------------------------------------------------------------------------------------
ViewContext::ViewContext(Renderer& r, const Scene& s, const ViewRequest& q, VtkOffscreen& o)
    : renderer(r), scene(s), request(q), out(o) {}

const LightState& ViewContext::light() const { return *renderer.lights().at(size_t(request.light)); }

static std::string lightPrefix(int light) { return light == 0 ? "" : "light" + std::to_string(light) + "/"; }

const CollectedInternal* ViewContext::internal(const std::string& name) const {
    auto it = collected_.entries.find(lightPrefix(request.light) + name);
    return it == collected_.entries.end() ? nullptr : &it->second;
}

nlohmann::json ViewContext::pixelData() const {
    auto it = collected_.entries.find("pixel");
    return it == collected_.entries.end() ? nlohmann::json() : it->second.json;
}

nlohmann::json ViewContext::pixelRecord() const {
    nlohmann::json all = pixelData();
    if (all.is_null() || !all.contains("lights")) return nlohmann::json();
    for (const auto& l : all["lights"])
        if (l.is_object() && l.contains("light") && l["light"].is_number_integer() && l["light"].get<int>() == request.light)
            return l;
    return nlohmann::json();
}

std::string ViewContext::exportTarget(const std::string& path) const {
    return request.outputs ? request.outputs->stage(path) : path;
}

// ---- scene geometry -------------------------------------------------------------------------------
std::vector<WorldTriangle> worldTriangles(const Scene& scene, double t, bool castersOnly) {
    std::vector<WorldTriangle> out;
    for (size_t o = 0; o < scene.objects.size(); ++o) {
        const Object& obj = scene.objects[o];
        if (castersOnly && !obj.castsShadows) continue;
        glm::mat4 m = obj.worldFromObjectAt(t);
        std::vector<glm::vec3> world(obj.mesh.positions.size());
        for (size_t i = 0; i < world.size(); ++i) world[i] = glm::vec3(m * glm::vec4(obj.mesh.positions[i], 1.0f));
        for (size_t i = 0; i + 2 < obj.mesh.indices.size(); i += 3)
            out.push_back({world[obj.mesh.indices[i]], world[obj.mesh.indices[i + 1]], world[obj.mesh.indices[i + 2]],
                           int(o)});
    }
    return out;
}


void orbitSceneCamera(vtkRenderer* renderer, const Camera& camera, double azimuth, double elevation) {
    vtkCamera* view = renderer->GetActiveCamera();
    view->SetPosition(camera.position.x, camera.position.y, camera.position.z);
    view->SetFocalPoint(camera.target.x, camera.target.y, camera.target.z);
    view->SetViewUp(camera.up.x, camera.up.y, camera.up.z);
    view->SetViewAngle(30.0);
    view->Azimuth(azimuth);
    view->Elevation(elevation);
    view->OrthogonalizeViewUp();
}

vtkSmartPointer<vtkActor> pointMarker(glm::vec3 point, double radius, glm::vec3 rgb) {
    vtkNew<vtkSphereSource> ball;
    ball->SetCenter(point.x, point.y, point.z);
    ball->SetRadius(radius);
    ball->SetThetaResolution(16);
    ball->SetPhiResolution(16);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(ball->GetOutputPort());
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(rgb.r, rgb.g, rgb.b);
    actor->GetProperty()->LightingOff();
    return actor;
}

// ---- FunctionSource -----------------------------------------------------------------------------------
vtkStandardNewMacro(FunctionSource);

FunctionSource::FunctionSource() { SetNumberOfInputPorts(0); }

void FunctionSource::SetGenerator(std::function<void(vtkPolyData*)> generator) {
    generator_ = std::move(generator);
    Modified();
}

int FunctionSource::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputs) {
    vtkPolyData* output = vtkPolyData::GetData(outputs);
    if (generator_) generator_(output);
    return 1;
}

// ---- images -------------------------------------------------------------------------------------------
vtkSmartPointer<vtkImageData> toImageData(const Image& image, const std::vector<std::string>& channelNames) {
    auto data = vtkSmartPointer<vtkImageData>::New();
    data->SetDimensions(image.width, image.height, 1);
    data->SetOrigin(0.0, 0.0, 0.0);
    data->SetSpacing(1.0, 1.0, 1.0);
    for (int c = 0; c < image.channels; ++c) {
        vtkNew<vtkFloatArray> array;
        array->SetName(c < int(channelNames.size()) ? channelNames[size_t(c)].c_str() : ("c" + std::to_string(c)).c_str());
        array->SetNumberOfTuples(vtkIdType(image.pixelCount()));
        for (int y = 0; y < image.height; ++y) {
            int row = image.height - 1 - y;  // VTK's j counts from the bottom
            for (int x = 0; x < image.width; ++x) {
                float v = image.at(x, y, c);
                array->SetValue(vtkIdType(row) * image.width + x, std::isfinite(v) ? v : NAN);
            }
        }
        data->GetPointData()->AddArray(array);
        if (c == 0) data->GetPointData()->SetActiveScalars(array->GetName());
    }
    return data;
}

std::pair<float, float> finiteRange(const Image& image, int c) {
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < image.pixelCount(); ++i) {
        float v = image.data[i * size_t(image.channels) + size_t(c)];
        if (!std::isfinite(v)) continue;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    return {lo, hi};
}

std::string formatNumber(double v, int digits) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    return buffer;
}

vtkSmartPointer<vtkLookupTable> sequentialLut(double lo, double hi, glm::vec3 nanRgb) {
    auto lut = paletteLut(Palette::Depth, lo, hi);
    lut->SetNanColor(nanRgb.r, nanRgb.g, nanRgb.b, 1.0);
    return lut;
}

vtkSmartPointer<vtkLookupTable> divergingLut(double maxAbs) {
    if (!(maxAbs > 0.0)) maxAbs = 1e-6;
    return paletteLut(Palette::SignedError, -maxAbs, maxAbs);
}

static vtkSmartPointer<vtkTextActor> textActor(const std::string& text, int size) {
    auto actor = vtkSmartPointer<vtkTextActor>::New();
    actor->SetInput(text.c_str());
    actor->GetTextProperty()->SetFontSize(size);
    actor->GetTextProperty()->SetColor(0.95, 0.95, 0.95);
    actor->GetTextProperty()->SetFontFamilyToArial();
    actor->GetTextProperty()->ShadowOff();
    actor->GetTextProperty()->ItalicOff();
    return actor;
}

vtkSmartPointer<vtkTextActor> captionActor(const std::string& text, int frameHeight) {
    auto actor = textActor(text, textPx(frameHeight));
    actor->SetPosition(8, 6);
    return actor;
}

vtkSmartPointer<vtkTextActor> titleActor(const std::string& text, int frameHeight) {
    auto actor = textActor(text, textPx(frameHeight));
    actor->GetTextProperty()->SetVerticalJustificationToTop();
    actor->GetTextProperty()->BoldOn();
    actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    actor->SetPosition(0.02, 0.97);
    return actor;
}

CaptionStrip captionStripLayout(const VtkOffscreen& out, const std::string& caption, bool monospace) {
    // The standard's text size, the caption wrapped to the width (never shrunk under the standard).
    auto text = captionActor(caption, out.height());
    if (monospace) text->GetTextProperty()->SetFontFamilyToCourier();  // columns of figures line up
    CaptionStrip c;
    c.margin = std::max(6, textPx(out.height()) / 3);
    c.text = wrapText(text->GetTextProperty(), caption, out.width() - 2 * c.margin);
    auto share = [&](const std::string& t) {
        int w = 0, h = 0;
        textExtent(text->GetTextProperty(), t, w, h);
        return double(h + 2 * c.margin) / out.height();
    };
    c.share = share(c.text);
    // 0.9f is the default: never cut (compared as a float: 0.9f is under the double 0.9).
    const bool mayCut = out.captionMaxShare() < 0.9f;
    const double limit = std::clamp(double(out.captionMaxShare()), 0.05, 0.9);
    if (mayCut && c.share > limit) {
        // Too tall for the picture (a window cell): the first lines that fit with the note under them.
        const std::string note = wrapText(text->GetTextProperty(), kCaptionContinues, out.width() - 2 * c.margin);
        std::vector<std::string> lines;
        for (size_t at = 0;;) {
            size_t end = c.text.find('\n', at);
            lines.push_back(c.text.substr(at, end == std::string::npos ? std::string::npos : end - at));
            if (end == std::string::npos) break;
            at = end + 1;
        }
        std::string kept;
        for (size_t n = lines.size(); n-- > 1;) {
            kept.clear();
            for (size_t i = 0; i < n; ++i) kept += lines[i] + "\n";
            if (share(kept + note) <= limit) break;
        }
        // Not even one line fits with the note: the note alone (the picture keeps its room).
        if (share(kept + note) > limit) kept.clear();
        c.text = kept + note;
        c.cut = true;
        c.share = share(c.text);
    }
    c.share = std::min(0.9, c.share);
    return c;
}

double addCaptionStrip(VtkOffscreen& out, const std::string& caption, bool monospace) {
    const CaptionStrip c = captionStripLayout(out, caption, monospace);
    auto text = captionActor(c.text, out.height());
    if (monospace) text->GetTextProperty()->SetFontFamilyToCourier();
    vtkRenderer* r = out.addRenderer();
    r->SetViewport(0.0, 0.0, 1.0, c.share);
    r->SetBackground(0.07, 0.07, 0.08);
    text->SetPosition(c.margin, c.margin);
    r->AddActor2D(text);
    return c.share;
}

void fitImage(vtkRenderer* renderer, int width, int height, double viewportAspect) {
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    const double cx = (width - 1) * 0.5, cy = (height - 1) * 0.5;
    camera->SetFocalPoint(cx, cy, 0.0);
    camera->SetPosition(cx, cy, 1e4);
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(0.5 * std::max<double>(height, width / viewportAspect) * 1.08);
    renderer->ResetCameraClippingRange();
}

void addImagePanel(vtkRenderer* renderer, vtkImageData* image, const std::string& array, vtkLookupTable* lut) {
    // Panels may show different arrays of one image: each maps its own shallow copy (shared arrays,
    // its own active scalars).
    vtkNew<vtkImageData> shown;
    shown->ShallowCopy(image);
    if (!shown->GetPointData()->HasArray(array.c_str()))
        throw InternalError("addImagePanel: the image has no array '" + array + "'");
    shown->GetPointData()->SetActiveScalars(array.c_str());
    vtkNew<vtkImageMapToColors> colours;
    colours->SetInputData(shown);
    colours->SetLookupTable(lut);
    colours->SetOutputFormatToRGB();
    vtkNew<vtkImageActor> actor;
    actor->GetMapper()->SetInputConnection(colours->GetOutputPort());
    actor->InterpolateOff();  // texels stay squares
    renderer->AddActor(actor);
    int* dims = image->GetDimensions();
    fitImage(renderer, dims[0], dims[1], 1.0);
}

void addImagePanelWithBar(VtkOffscreen& out, vtkImageData* image, const std::string& array, vtkLookupTable* lut,
                          const std::string& title, const std::string& barTitle, double x0, double y0, double x1,
                          double y1) {
    // The bar takes the width its labels need (measured), at most half the panel.
    const double barWidth = std::min(0.5 * (x1 - x0), double(colourBarWidthPx(lut, barTitle, out.height())) / out.width());
    const double split = x1 - barWidth;
    vtkRenderer* panel = out.addRenderer();
    panel->SetViewport(x0, y0, split, y1);
    panel->SetBackground(0.12, 0.12, 0.14);
    addImagePanel(panel, image, array, lut);
    int* dims = image->GetDimensions();
    // Room at the top for the title (one line of the standard's text).
    const double titleShare = std::min(0.4, 1.6 * textPx(out.height()) / ((y1 - y0) * out.height()));
    fitImage(panel, dims[0], dims[1], (split - x0) * out.width() / ((y1 - y0) * (1.0 - titleShare) * out.height()));
    {
        vtkCamera* camera = panel->GetActiveCamera();
        const double scale = camera->GetParallelScale() / (1.0 - titleShare);
        double* f = camera->GetFocalPoint();
        const double shift = scale * titleShare;  // the image moves down by the title's share
        camera->SetParallelScale(scale);
        camera->SetFocalPoint(f[0], f[1] + shift, f[2]);
        double* p = camera->GetPosition();
        camera->SetPosition(p[0], p[1] + shift, p[2]);
    }
    panel->AddActor2D(titleActor(title, out.height()));
    vtkRenderer* side = out.addRenderer();
    side->SetViewport(split, y0, x1, y1);
    side->SetBackground(0.12, 0.12, 0.14);
    addColourBar(side, lut, barTitle, out.height());
}

vtkSmartPointer<vtkActor> lineActor(const std::vector<std::pair<glm::vec3, glm::vec3>>& lines, glm::vec3 rgb,
                                    float width) {
    vtkNew<FunctionSource> source;
    source->SetGenerator([lines](vtkPolyData* out) {
        vtkNew<vtkPoints> points;
        vtkNew<vtkCellArray> cells;
        for (const auto& [a, b] : lines) {
            vtkIdType ids[2] = {points->InsertNextPoint(a.x, a.y, a.z), points->InsertNextPoint(b.x, b.y, b.z)};
            cells->InsertNextCell(2, ids);
        }
        out->SetPoints(points);
        out->SetLines(cells);
    });
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(source->GetOutputPort());
    mapper->ScalarVisibilityOff();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(rgb.r, rgb.g, rgb.b);
    actor->GetProperty()->SetLineWidth(width);
    actor->GetProperty()->LightingOff();
    return actor;
}

void writePolyData(vtkPolyData* data, const std::string& path) {
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputData(data);
    writer->SetDataModeToAppended();
    if (writer->Write() != 1) throw InternalError("cannot write " + path);
}

void writeImageData(vtkImageData* data, const std::string& path) {
    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputData(data);
    writer->SetDataModeToAppended();
    if (writer->Write() != 1) throw InternalError("cannot write " + path);
}

// ---- rendering a view --------------------------------------------------------------------------------
static void checkRequest(const Renderer& renderer, const ViewRequest& request);

float framePanelsAspect(float frame, int panels) {
    // Each panel: the image and its colour bar (~15% of the panel's width), over the caption strip.
    return float(std::max(1, panels)) * frame * 1.15f * (1.0f - kCaptionShare);
}

float viewAspect(const Renderer& renderer, const ViewRequest& request, float frameAspect) {
    const ViewDesc& view = requireView(request.view);
    constexpr float kDefault = 4.0f / 3.0f;
    if (!view.aspect || !viewRefusal(renderer, request).empty()) return kDefault;
    const float frame = frameAspect > 0.0f ? frameAspect : float(renderer.width()) / float(std::max(1, renderer.height()));
    const float a = view.aspect(renderer, request, frame);
    return std::isfinite(a) && a > 0.0f ? std::clamp(a, 0.5f, 5.0f) : kDefault;
}

std::string viewRefusal(const Renderer& renderer, const ViewRequest& request) {
    const ViewDesc& view = requireView(request.view);
    checkRequest(renderer, request);
    return view.refusal ? view.refusal(*renderer.lights().at(size_t(request.light)), request) : "";
}

std::string viewRefusal(const LightState& light, const ViewRequest& request) {
    const ViewDesc& view = requireView(request.view);
    return view.refusal ? view.refusal(light, request) : "";
}

static void checkRequest(const Renderer& renderer, const ViewRequest& request) {
    if (request.pixel && (request.pixel->x < 0 || request.pixel->y < 0 || request.pixel->x >= renderer.width() ||
                          request.pixel->y >= renderer.height()))
        throw InputError("--pixel: expected x,y inside the " + std::to_string(renderer.width()) + "x" +
                         std::to_string(renderer.height()) + " image, got " + std::to_string(request.pixel->x) + "," +
                         std::to_string(request.pixel->y));
    if (request.light < 0 || request.light >= int(renderer.lights().size()))
        throw InputError("--light: expected a light index in 0.." + std::to_string(int(renderer.lights().size()) - 1) +
                         ", got " + std::to_string(request.light));
    if (request.rays < 1 || request.rays > 4096)
        throw InputError("--rays: expected 1..4096, got " + std::to_string(request.rays));
    if (!(request.zoom > 0.0f) || !std::isfinite(request.zoom))
        throw InputError("--zoom: expected a positive number, got " + formatNumber(request.zoom));
}

ViewResult renderView(Renderer& renderer, const Scene& scene, const ViewRequest& request, VtkOffscreen& out) {
    const ViewDesc& view = requireView(request.view);
    checkRequest(renderer, request);
    if (std::string why = view.refusal ? view.refusal(*renderer.lights().at(size_t(request.light)), request) : "";
        !why.empty())
        throw InputError("view " + view.info.name + ": " + why);
    if (!request.exportPath.empty() &&
        std::filesystem::path(request.exportPath).extension().string() != view.info.exportExtension)
        throw InputError("--export: view " + view.info.name + " exports " + view.info.exportExtension + " data, got '" +
                         request.exportPath + "'");

    // The frame data every view may read: the picture, visibility, G-buffer and the internals (with
    // the per-pixel records when a pixel is picked), at the renderer's current time.
    std::set<std::string> requested = {"image", "visibility", "gbuffer"};
    std::set<std::string> internals = renderer.internalRequests(request.pixel.has_value());
    requested.insert(internals.begin(), internals.end());
    const double time = renderer.time();
    renderer.setTime(time);
    renderer.renderFrame(int(std::lround(time / kSecondsPerFrame)), requested);

    ViewContext ctx(renderer, scene, request, out);
    renderer.writeInternals(ctx.collected_, request.pixel);

    out.resize(request.width, request.height);
    out.setCaptionMaxShare(request.captionMaxShare);
    // A fresh set of renderers for this view.
    while (out.window()->GetRenderers()->GetNumberOfItems() > 0)
        out.window()->RemoveRenderer(out.window()->GetRenderers()->GetFirstRenderer());
    ViewResult result;
    view.build(ctx, result);
    wrapTextsToViewports(out);
    result.image = out.render();
    result.texts = textLayout(out);
    return result;
}

ViewResult renderView(Renderer& renderer, const Scene& scene, const ViewRequest& request) {
    // The frame is sized by the request; renderView(.., out) resizes it again (a no-op).
    int w = request.width, h = request.height;
    if (w < 1 || h < 1 || w > 8192 || h > 8192)
        throw InputError("--size: expected WxH with each side in 1..8192, got " + std::to_string(w) + "x" +
                         std::to_string(h));
    VtkOffscreen out(w, h);
    return renderView(renderer, scene, request, out);
}

}  // namespace shadowlab
