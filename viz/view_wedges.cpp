// `wedges`: soft shadow volumes (assarsson2004) in 3D: the scene, the light, the silhouette edges
// from the light's centre (each its own colour) and their penumbra wedges, translucent in their
// edge's colour, exactly the meshes the technique drew (its `silhouettes` and `wedges` internals, as
// `render --internals` writes them). With a picked pixel, its point and the wedges that hold it
// (those of the per-pixel record's edges) drawn bright, the others faint, and the caption the
// record's numbers: the hard count, the edges' coverage sum and the visibility.
// Export (.vtp): every part appended, cell arrays `part` (0 scene, 1 light, 2 silhouette, 3 wedge,
// 4 picked point), `edge` (the silhouette edge of a silhouette or a wedge's triangle, else -1),
// `face` (a wedge triangle's plane: 0 front, 1 back, 2 side, 3 bottom; else -1) and `holds_pixel`
// (1 for the silhouettes and wedge triangles of the wedges holding the picked point).
#include <vtkActor.h>
#include <vtkAppendPolyData.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>
#include <set>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {

enum Part { kScene = 0, kLight = 1, kSilhouette = 2, kWedge = 3, kPicked = 4 };

const glm::vec3 kLightRgb(1.0f, 0.85f, 0.25f), kPickedRgb(1.0f, 0.3f, 1.0f);

// A distinct colour per silhouette edge: hues a golden angle apart, saturated and bright.
glm::vec3 edgeColour(int edge) {
    const float h = std::fmod(float(edge) * 0.618034f, 1.0f) * 6.0f;
    const float x = 1.0f - std::abs(std::fmod(h, 2.0f) - 1.0f);
    glm::vec3 rgb = h < 1 ? glm::vec3(1, x, 0) : h < 2 ? glm::vec3(x, 1, 0) : h < 3 ? glm::vec3(0, 1, x)
                    : h < 4 ? glm::vec3(0, x, 1) : h < 5 ? glm::vec3(x, 0, 1) : glm::vec3(1, 0, x);
    return 0.25f + 0.75f * rgb;
}

// Cells with the view's cell arrays (colour with alpha, so translucent parts blend).
struct Cells {
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> lines, polys;
    struct Attributes {
        int part, edge, face, holds;
        std::array<unsigned char, 4> rgba;
    };
    std::vector<Attributes> lineAttributes, polyAttributes;

    static std::array<unsigned char, 4> bytes(glm::vec3 c, float alpha) {
        const glm::vec3 b = glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f;
        return {(unsigned char)b.x, (unsigned char)b.y, (unsigned char)b.z, (unsigned char)(alpha * 255.0f + 0.5f)};
    }
    void line(glm::vec3 a, glm::vec3 b, Attributes at) {
        vtkIdType ids[2] = {points->InsertNextPoint(a.x, a.y, a.z), points->InsertNextPoint(b.x, b.y, b.z)};
        lines->InsertNextCell(2, ids);
        lineAttributes.push_back(at);
    }
    void triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, Attributes at) {
        vtkIdType ids[3] = {points->InsertNextPoint(a.x, a.y, a.z), points->InsertNextPoint(b.x, b.y, b.z),
                            points->InsertNextPoint(c.x, c.y, c.z)};
        polys->InsertNextCell(3, ids);
        polyAttributes.push_back(at);
    }
    vtkSmartPointer<vtkPolyData> data() {
        auto out = vtkSmartPointer<vtkPolyData>::New();
        out->SetPoints(points);
        out->SetLines(lines);
        out->SetPolys(polys);
        vtkNew<vtkIntArray> part, edge, face, holds;
        part->SetName("part");
        edge->SetName("edge");
        face->SetName("face");
        holds->SetName("holds_pixel");
        vtkNew<vtkUnsignedCharArray> colour;
        colour->SetName("colour");
        colour->SetNumberOfComponents(4);
        for (const auto* list : {&lineAttributes, &polyAttributes})  // VTK orders lines before polys
            for (const Attributes& a : *list) {
                part->InsertNextValue(a.part);
                edge->InsertNextValue(a.edge);
                face->InsertNextValue(a.face);
                holds->InsertNextValue(a.holds);
                colour->InsertNextTypedTuple(a.rgba.data());
            }
        for (vtkIntArray* a : {part.Get(), edge.Get(), face.Get(), holds.Get()}) out->GetCellData()->AddArray(a);
        out->GetCellData()->AddArray(colour);
        return out;
    }
};

vtkSmartPointer<vtkActor> cellsActor(vtkPolyData* data, float lineWidth, bool lit, bool blend) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(data);
    mapper->SetScalarModeToUseCellFieldData();
    mapper->SelectColorArray("colour");
    mapper->SetColorModeToDirectScalars();
    mapper->ScalarVisibilityOn();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetLineWidth(lineWidth);
    if (!lit) actor->GetProperty()->LightingOff();
    // Translucent parts are drawn in the opaque pass with GL blending (VTK's translucent pass blits a
    // depth buffer the offscreen frame cannot give it), after everything opaque.
    if (blend) actor->ForceOpaqueOn();
    return actor;
}

bool hasMesh(const LightState& l, const std::string& name, InternalDesc::Kind kind) {
    const InternalDesc* i = l.desc->findInternal(name);
    return i && i->kind == kind;
}

std::string refusal(const Renderer& renderer, const ViewRequest& request) {
    const LightState& l = *renderer.lights().at(size_t(request.light));
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (!hasMesh(l, "wedges", InternalDesc::Kind::Mesh) || !hasMesh(l, "silhouettes", InternalDesc::Kind::Lines))
        return "technique " + l.desc->id + " builds no penumbra wedges (ssv does)";
    return "";
}

void build(ViewContext& ctx, ViewResult& result) {
    const Renderer& renderer = ctx.renderer;
    const Scene& scene = ctx.scene;
    const LightState& l = ctx.light();
    const double t = renderer.time();
    const CollectedInternal* silhouettes = ctx.internal("silhouettes");
    const CollectedInternal* wedges = ctx.internal("wedges");
    if (!silhouettes || !wedges)
        throw InputError("view wedges: technique " + l.desc->id + " wrote no silhouettes or wedges this frame");
    const MeshData& edges = silhouettes->mesh;
    const MeshData& wedgeMesh = wedges->mesh;
    auto attribute = [](const MeshData& m, const std::string& name) -> const std::vector<float>& {
        for (const auto& a : m.primitiveAttributes)
            if (a.first == name) return a.second;
        throw InternalError("view wedges: the mesh has no attribute '" + name + "'");
    };
    const std::vector<float>& wedgeEdge = attribute(wedgeMesh, "edge");
    const std::vector<float>& wedgeFace = attribute(wedgeMesh, "face");
    const std::vector<float>& edgeKind = attribute(edges, "wedge_kind");

    // The picked pixel: its point and the record's edges (those whose wedge holds it).
    const nlohmann::json rec = ctx.pixelRecord();
    std::set<int> holding;
    std::optional<glm::vec3> point;
    std::string pixelLine;
    nlohmann::json data;
    if (ctx.request.pixel) {
        const glm::ivec2 px = *ctx.request.pixel;
        data["pixel"] = {px.x, px.y};
        const Image positions = renderer.positions();
        const glm::vec3 p(positions.at(px.x, px.y, 0), positions.at(px.x, px.y, 1), positions.at(px.x, px.y, 2));
        if (!std::isfinite(p.x) || rec.is_null() || rec.value("background", false)) {
            pixelLine = "pixel (" + std::to_string(px.x) + ", " + std::to_string(px.y) + "): background, no surface";
        } else {
            point = p;
            int everywhere = 0;
            double sum = 0.0;
            for (const auto& e : rec.value("edges", nlohmann::json::array())) {
                if (e.value("wedge", "") == "wedge") holding.insert(e.at("index").get<int>());
                else ++everywhere;
                sum += e.value("signed_area", 0.0);
            }
            double count = 0.0;
            for (const auto& s : rec.value("sub_lights", nlohmann::json::array())) count += s.value("hard_count", 0.0);
            char line[400];
            std::snprintf(line, sizeof line,
                          "pixel (%d, %d) at (%.4g, %.4g, %.4g): inside %zu wedge(s) (bright)%s, hard count %g, coverage "
                          "sum %.4g, v = %.4f",
                          px.x, px.y, p.x, p.y, p.z, holding.size(),
                          everywhere ? (", " + std::to_string(everywhere) + " edge(s) evaluated everywhere").c_str() : "",
                          count, sum, rec.value("visibility", std::nan("")));
            pixelLine = line;
            data["point"] = {p.x, p.y, p.z};
            data["holding"] = std::vector<int>(holding.begin(), holding.end());
            data["coverage_sum"] = sum;
        }
    }

    Cells opaque, translucent;
    // The scene, shaded by albedo; receivers paler.
    for (const WorldTriangle& tri : worldTriangles(scene, t, false)) {
        const Object& o = scene.objects[size_t(tri.object)];
        opaque.triangle(tri.a, tri.b, tri.c, {kScene, -1, -1, 0, Cells::bytes(o.albedo, 1.0f)});
    }
    // The light's outline.
    const Light& light = l.light;
    if (!light.isPoint()) {
        std::vector<glm::vec3> ring;
        const glm::vec3 c = light.position, r = light.right(), u = light.up;
        if (light.shape == LightShape::Square) {
            const float h = 0.5f * light.size;
            ring = {c - h * r - h * u, c + h * r - h * u, c + h * r + h * u, c - h * r + h * u};
        } else {
            for (int i = 0; i < 64; ++i) {
                const float a = float(i) / 64.0f * 6.2831853f;
                ring.push_back(c + light.size * (std::cos(a) * r + std::sin(a) * u));
            }
        }
        for (size_t i = 0; i < ring.size(); ++i)
            opaque.line(ring[i], ring[(i + 1) % ring.size()], {kLight, -1, -1, 0, Cells::bytes(kLightRgb, 1.0f)});
    }
    // Silhouette edges, each its colour; those holding the pick drawn again, thick, below.
    Cells held;
    for (size_t e = 0; e < edges.primitiveCount(); ++e) {
        const glm::vec3 a = edges.positions[edges.indices[2 * e]], b = edges.positions[edges.indices[2 * e + 1]];
        const bool holds = holding.count(int(e)) > 0;
        (holds ? held : opaque).line(a, b, {kSilhouette, int(e), -1, holds ? 1 : 0, Cells::bytes(edgeColour(int(e)), 1.0f)});
    }
    // Wedges: faint, or bright when they hold the pick (a pick makes the others fainter still).
    const float faint = point ? 0.06f : 0.14f;
    for (size_t tri = 0; tri < wedgeMesh.primitiveCount(); ++tri) {
        const int e = int(wedgeEdge[tri]);
        const bool holds = holding.count(e) > 0;
        const glm::vec3 a = wedgeMesh.positions[wedgeMesh.indices[3 * tri]],
                        b = wedgeMesh.positions[wedgeMesh.indices[3 * tri + 1]],
                        c = wedgeMesh.positions[wedgeMesh.indices[3 * tri + 2]];
        (holds ? held : translucent)
            .triangle(a, b, c, {kWedge, e, int(wedgeFace[tri]), holds ? 1 : 0, Cells::bytes(edgeColour(e), holds ? 0.4f : faint)});
    }
    size_t everywhere = 0;
    for (float k : edgeKind) everywhere += k == 1.0f;
    if (point) opaque.line(*point, *point, {kPicked, -1, -1, 0, Cells::bytes(kPickedRgb, 1.0f)});

    const size_t wedgeCount = wedgeMesh.primitiveCount() / 8;
    char head[320];
    std::snprintf(head, sizeof head,
                  "wedges  %s / %s, t = %.3g s: %zu silhouette edges from the light's centre (one colour each), %zu "
                  "penumbra wedges (translucent)%s, light (yellow)",
                  scene.name.c_str(), l.desc->id.c_str(), t, edges.primitiveCount(), wedgeCount,
                  everywhere ? (", " + std::to_string(everywhere) + " without a wedge (evaluated everywhere)").c_str() : "");
    result.caption = head;
    if (!pixelLine.empty()) result.caption += "\n" + pixelLine;
    data["edges"] = edges.primitiveCount();
    data["wedges"] = wedgeCount;
    data["everywhere"] = everywhere;
    result.data = data;
    const double strip = addCaptionStrip(ctx.out, result.caption);

    vtkRenderer* r3 = ctx.out.addRenderer();
    r3->SetViewport(0.0, strip, 1.0, 1.0);
    r3->SetBackground(0.10, 0.11, 0.14);
    r3->SetBackground2(0.22, 0.24, 0.30);
    r3->GradientBackgroundOn();
    auto opaqueData = opaque.data(), heldData = held.data(), translucentData = translucent.data();
    auto sceneActor = cellsActor(opaqueData, 3.0f, true, false);
    sceneActor->GetProperty()->SetAmbient(0.3);
    sceneActor->GetProperty()->SetDiffuse(0.7);
    r3->AddActor(sceneActor);
    const Bounds bounds = scene.bounds(t);
    const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.hi - bounds.lo);
    if (point) r3->AddActor(pointMarker(*point, 0.01 * diagonal, kPickedRgb));
    // The blended wedges last: what they cover stays visible through them.
    r3->AddActor(cellsActor(heldData, 6.0f, false, true));
    r3->AddActor(cellsActor(translucentData, 1.0f, false, true));
    // The scene camera's view, orbited a little so the wedges' depth shows; fit the casters, the
    // light and the picked point (the wedges reach down to their bottom plane, beyond the receivers).
    const Camera camera = renderer.camera();
    orbitSceneCamera(r3, camera, 25.0 + ctx.request.azimuth, 10.0 + ctx.request.elevation);
    vtkCamera* view = r3->GetActiveCamera();
    Bounds fit;
    for (const glm::vec3& p : edges.positions) fit.extend(p);
    fit.extend(light.position - glm::vec3(light.size));
    fit.extend(light.position + glm::vec3(light.size));
    if (point) fit.extend(*point);
    if (fit.empty()) fit = bounds;
    // Down to the receivers below the casters.
    fit.extend(glm::vec3(fit.lo.x, bounds.lo.y, fit.lo.z));
    double box[6] = {fit.lo.x, fit.hi.x, fit.lo.y, fit.hi.y, fit.lo.z, fit.hi.z};
    r3->ResetCamera(box);
    view->Zoom(1.1 * ctx.request.zoom);
    r3->ResetCameraClippingRange();

    if (!ctx.request.exportPath.empty()) {
        vtkNew<vtkAppendPolyData> all;
        for (vtkPolyData* d : {opaqueData.Get(), heldData.Get(), translucentData.Get()}) all->AddInputData(d);
        all->Update();
        writePolyData(all->GetOutput(), ctx.exportTarget(ctx.request.exportPath));
    }
}

}  // namespace

const ViewDesc& wedgesView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "wedges";
        d.info.doc = "soft shadow volumes in 3D: the silhouette edges from the light's centre (one colour each) and "
                     "their penumbra wedges, translucent, exactly as drawn; with --pixel the point and the wedges "
                     "holding it bright, with the record's hard count, coverage sum and visibility";
        d.info.appliesTo = "techniques with penumbra wedges (ssv)";
        d.info.exportExtension = ".vtp";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
