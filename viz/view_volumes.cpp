// The 3D volume views: `wedges` (below) and `penumbra-volumes` (after it), and the cells both draw.
//
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

glm::vec3 edgeColour(int edge) {
    const float h = std::fmod(float(edge) * 0.618034f, 1.0f) * 6.0f;
    const float x = 1.0f - std::abs(std::fmod(h, 2.0f) - 1.0f);
    glm::vec3 rgb = h < 1 ? glm::vec3(1, x, 0) : h < 2 ? glm::vec3(x, 1, 0) : h < 3 ? glm::vec3(0, 1, x)
                    : h < 4 ? glm::vec3(0, x, 1) : h < 5 ? glm::vec3(x, 0, 1) : glm::vec3(1, 0, x);
    return 0.25f + 0.75f * rgb;
}

std::vector<std::pair<glm::vec3, glm::vec3>> lightOutlineSegments(const Light& light) {
    std::vector<std::pair<glm::vec3, glm::vec3>> out;
    if (light.isPoint()) return out;
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
    for (size_t i = 0; i < ring.size(); ++i) out.emplace_back(ring[i], ring[(i + 1) % ring.size()]);
    return out;
}

ViewCells::ViewCells()
    : points(vtkSmartPointer<vtkPoints>::New()),
      lines(vtkSmartPointer<vtkCellArray>::New()),
      polys(vtkSmartPointer<vtkCellArray>::New()) {}

std::array<unsigned char, 4> ViewCells::bytes(glm::vec3 c, float alpha) {
    const glm::vec3 b = glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f;
    return {(unsigned char)b.x, (unsigned char)b.y, (unsigned char)b.z, (unsigned char)(alpha * 255.0f + 0.5f)};
}

void ViewCells::line(glm::vec3 a, glm::vec3 b, Attributes at) {
    vtkIdType ids[2] = {points->InsertNextPoint(a.x, a.y, a.z), points->InsertNextPoint(b.x, b.y, b.z)};
    lines->InsertNextCell(2, ids);
    lineAttributes.push_back(at);
}

void ViewCells::triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, Attributes at) {
    vtkIdType ids[3] = {points->InsertNextPoint(a.x, a.y, a.z), points->InsertNextPoint(b.x, b.y, b.z),
                        points->InsertNextPoint(c.x, c.y, c.z)};
    polys->InsertNextCell(3, ids);
    polyAttributes.push_back(at);
}

vtkSmartPointer<vtkPolyData> ViewCells::data() {
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
    if (blend) actor->ForceOpaqueOn();
    return actor;
}

namespace {

const glm::vec3 kLightRgb(1.0f, 0.85f, 0.25f), kPickedRgb(1.0f, 0.3f, 1.0f);

bool declaresInternal(const LightState& l, const std::string& name, InternalDesc::Kind kind) {
    const InternalDesc* i = l.desc->findInternal(name);
    return i && i->kind == kind;
}

// The 3D panel both views end with, above the caption strip: the scene's opaque cells (lit), the
// picked point, then the held and the translucent cells blended last (what they cover shows through);
// the scene camera orbited a little so the volumes' depth shows, fitted to the silhouette edges, the
// light, the picked point and the receivers below (the volumes reach beyond them); and the export,
// every part appended.
void drawVolumeScene(ViewContext& ctx, const Renderer& renderer, const Scene& scene, double t, const Light& light,
                     const MeshData& edges, const std::optional<glm::vec3>& point, ViewCells& opaque, ViewCells& held,
                     ViewCells& translucent, double strip) {
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
    r3->AddActor(cellsActor(heldData, 6.0f, false, true));
    r3->AddActor(cellsActor(translucentData, 1.0f, false, true));
    orbitSceneCamera(r3, renderer.camera(), 25.0 + ctx.request.azimuth, 10.0 + ctx.request.elevation);
    Bounds fit;
    for (const glm::vec3& p : edges.positions) fit.extend(p);
    fit.extend(light.position - glm::vec3(light.size));
    fit.extend(light.position + glm::vec3(light.size));
    if (point) fit.extend(*point);
    if (fit.empty()) fit = bounds;
    fit.extend(glm::vec3(fit.lo.x, bounds.lo.y, fit.lo.z));  // down to the receivers below the casters
    double box[6] = {fit.lo.x, fit.hi.x, fit.lo.y, fit.hi.y, fit.lo.z, fit.hi.z};
    r3->ResetCamera(box);
    r3->GetActiveCamera()->Zoom(1.1 * ctx.request.zoom);
    r3->ResetCameraClippingRange();

    if (!ctx.request.exportPath.empty()) {
        vtkNew<vtkAppendPolyData> all;
        for (vtkPolyData* d : {opaqueData.Get(), heldData.Get(), translucentData.Get()}) all->AddInputData(d);
        all->Update();
        writePolyData(all->GetOutput(), ctx.exportTarget(ctx.request.exportPath));
    }
}

}  // namespace

namespace {

using Cells = ViewCells;

enum Part { kScene = 0, kLight = 1, kSilhouette = 2, kWedge = 3, kPicked = 4 };

std::string refusal(const LightState& l, const ViewRequest& request) {
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (!declaresInternal(l, "wedges", InternalDesc::Kind::Mesh) ||
        !declaresInternal(l, "silhouettes", InternalDesc::Kind::Lines))
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
    for (const auto& [a, b] : lightOutlineSegments(l.light))
        opaque.line(a, b, {kLight, -1, -1, 0, Cells::bytes(kLightRgb, 1.0f)});
    const Light& light = l.light;
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
    drawVolumeScene(ctx, renderer, scene, t, light, edges, point, opaque, held, translucent,
                    addCaptionStrip(ctx.out, result.caption));
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

// `penumbra-volumes`: penumbra volume maps and mask filtering (cournia2005 ch. 4, 5) in 3D: the
// scene, the light, the silhouette edges from the light's centre, the outer penumbra volumes (orange,
// between the hard shadow plane and the lit side) and the inner ones (blue, towards the umbra),
// translucent, exactly the quads the technique rasterized from the light (its `penumbra_volumes`
// internal, as `render --internals` writes it). With a picked pixel, its point and the volume that
// covered it drawn bright: for pvm the volume whose edge the PVEM held there (the record's `volume`),
// for pvmf the nearest volume the ray from the light centre to the point crosses (the mask's rule:
// the mask keeps the nearest volume in front of the receiver). The caption gives the record's
// numbers: k and v (pvm), or d_o, w_pcf, the samples and the visibility before and after the blur
// (pvmf).
// Export (.vtp): every part appended, cell arrays `part` (0 scene, 1 light, 2 silhouette, 3 volume,
// 4 picked point), `edge` (the silhouette edge of a silhouette or a volume triangle, else -1), `face`
// (a volume triangle's side: 0 outer, 1 inner; else -1) and `holds_pixel` (1 for the volume covering
// the picked point and its edge).
namespace shadowlab {

namespace penumbra_volumes_view {

enum Part { kScene = 0, kLight = 1, kSilhouette = 2, kVolume = 3, kPicked = 4 };

const glm::vec3 kOuterRgb(1.0f, 0.55f, 0.15f), kInnerRgb(0.25f, 0.55f, 1.0f), kEdgeRgb(0.95f, 0.95f, 0.95f);

std::string refusal(const LightState& l, const ViewRequest& request) {
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (!declaresInternal(l, "penumbra_volumes", InternalDesc::Kind::Mesh) ||
        !declaresInternal(l, "silhouettes", InternalDesc::Kind::Lines))
        return "technique " + l.desc->id + " builds no penumbra volumes (pvm and pvmf do)";
    return "";
}

// Ray-triangle intersection (Moller-Trumbore): the distance along the unit ray, or +inf.
float rayHit(const glm::vec3& o, const glm::vec3& d, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
    const float det = glm::dot(e1, h);
    if (std::abs(det) < 1e-12f) return INFINITY;
    const glm::vec3 s = o - a;
    const float u = glm::dot(s, h) / det;
    if (u < 0.0f || u > 1.0f) return INFINITY;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) / det;
    if (v < 0.0f || u + v > 1.0f) return INFINITY;
    const float t = glm::dot(e2, q) / det;
    return t > 0.0f ? t : INFINITY;
}

std::string num(const nlohmann::json& j, const char* key, int digits = 4) {
    return j.contains(key) && j[key].is_number() ? formatNumber(j[key].get<double>(), digits) : "-";
}

void build(ViewContext& ctx, ViewResult& result) {
    const Renderer& renderer = ctx.renderer;
    const Scene& scene = ctx.scene;
    const LightState& l = ctx.light();
    const double t = renderer.time();
    const CollectedInternal* silhouettes = ctx.internal("silhouettes");
    const CollectedInternal* volumes = ctx.internal("penumbra_volumes");
    if (!silhouettes || !volumes)
        throw InputError("view penumbra-volumes: technique " + l.desc->id +
                         " wrote no silhouettes or penumbra volumes this frame");
    const MeshData& edges = silhouettes->mesh;
    const MeshData& mesh = volumes->mesh;
    auto attribute = [](const MeshData& m, const std::string& name) -> const std::vector<float>& {
        for (const auto& a : m.primitiveAttributes)
            if (a.first == name) return a.second;
        throw InternalError("view penumbra-volumes: the mesh has no attribute '" + name + "'");
    };
    const std::vector<float>& volumeEdge = attribute(mesh, "edge");
    const std::vector<float>& volumeSide = attribute(mesh, "side");
    const Light& light = l.light;
    const bool isPvm = l.desc->id == "pvm";

    // The picked pixel: its point and the volume covering it.
    const nlohmann::json rec = ctx.pixelRecord();
    int holdEdge = -1, holdSide = -1;
    std::optional<glm::vec3> point;
    std::string pixelLine;
    nlohmann::json data;
    if (ctx.request.pixel) {
        const glm::ivec2 px = *ctx.request.pixel;
        data["pixel"] = {px.x, px.y};
        const Image positions = renderer.positions();
        const glm::vec3 p(positions.at(px.x, px.y, 0), positions.at(px.x, px.y, 1), positions.at(px.x, px.y, 2));
        char where[160];
        std::snprintf(where, sizeof where, "pixel (%d, %d)", px.x, px.y);
        if (!std::isfinite(p.x) || rec.is_null() || rec.value("background", false)) {
            pixelLine = std::string(where) + ": background, no surface";
        } else {
            point = p;
            if (isPvm) {
                if (rec.value("in_volume", false) && rec["volume"].is_object()) {
                    holdEdge = rec["volume"]["edge"].get<int>();
                    holdSide = rec["volume"]["side"].get<std::string>() == "outer" ? 0 : 1;
                }
            } else if (rec.value("in_volume", false)) {
                // The mask's rule: the nearest volume between the light centre and the point.
                const glm::vec3 d = glm::normalize(p - light.position);
                float best = glm::length(p - light.position);
                for (size_t i = 0; i < mesh.primitiveCount(); ++i) {
                    const float h = rayHit(light.position, d, mesh.positions[mesh.indices[3 * i]],
                                           mesh.positions[mesh.indices[3 * i + 1]], mesh.positions[mesh.indices[3 * i + 2]]);
                    if (h < best) best = h, holdEdge = int(volumeEdge[i]), holdSide = int(volumeSide[i]);
                }
            }
            std::string inside = holdEdge >= 0 ? std::string("inside the ") + (holdSide == 0 ? "outer" : "inner") +
                                                     " volume of edge " + std::to_string(holdEdge) + " (bright)"
                                               : "outside every volume";
            std::string numbers;
            if (isPvm)
                numbers = holdEdge >= 0 ? "k = " + num(rec["disk"], "k") + ", v = " + num(rec, "v_volume") +
                                              (rec.contains("v_side") && rec["v_side"].is_number() &&
                                                       rec["v_side"] != rec["v_volume"]
                                                   ? ", held at " + num(rec, "v_side") + " (split_sides)"
                                                   : std::string())
                                        : "shadow-map test " + num(rec, "shadow_test");
            else if (rec.value("listed", false))
                numbers = rec["samples"].is_array()
                              ? "d_o = " + num(rec, "d_o") + ", d_r = " + num(rec, "d_r") + ", w_pcf = " +
                                    num(rec, "w_pcf_texels", 3) + " texels, " + std::to_string(rec["samples"].size()) +
                                    " samples, before blur " + num(rec, "visibility_before_blur")
                              : "no volume texel about it: shadow test " + num(rec, "shadow_test");
            else
                numbers = "not listed: lit, never filtered";
            char line[480];
            std::snprintf(line, sizeof line, "%s at (%.4g, %.4g, %.4g): %s; %s; v = %s", where, p.x, p.y, p.z,
                          inside.c_str(), numbers.c_str(), num(rec, "visibility").c_str());
            pixelLine = line;
            data["point"] = {p.x, p.y, p.z};
            data["volume"] = holdEdge >= 0 ? nlohmann::json{{"edge", holdEdge}, {"side", holdSide == 0 ? "outer" : "inner"}}
                                           : nlohmann::json(nullptr);
        }
    }

    ViewCells opaque, translucent, held;
    for (const WorldTriangle& tri : worldTriangles(scene, t, false)) {
        const Object& o = scene.objects[size_t(tri.object)];
        opaque.triangle(tri.a, tri.b, tri.c, {kScene, -1, -1, 0, ViewCells::bytes(o.albedo, 1.0f)});
    }
    for (const auto& [a, b] : lightOutlineSegments(light))
        opaque.line(a, b, {kLight, -1, -1, 0, ViewCells::bytes(kLightRgb, 1.0f)});
    for (size_t e = 0; e < edges.primitiveCount(); ++e) {
        const glm::vec3 a = edges.positions[edges.indices[2 * e]], b = edges.positions[edges.indices[2 * e + 1]];
        const bool holds = int(e) == holdEdge;
        (holds ? held : opaque).line(a, b, {kSilhouette, int(e), -1, holds ? 1 : 0, ViewCells::bytes(kEdgeRgb, 1.0f)});
    }
    size_t outer = 0, inner = 0;
    const float faint = point ? 0.08f : 0.16f;
    for (size_t tri = 0; tri < mesh.primitiveCount(); ++tri) {
        const int e = int(volumeEdge[tri]), side = int(volumeSide[tri]);
        (side == 0 ? outer : inner) += 1;
        const bool holds = e == holdEdge && side == holdSide;
        const glm::vec3 a = mesh.positions[mesh.indices[3 * tri]], b = mesh.positions[mesh.indices[3 * tri + 1]],
                        c = mesh.positions[mesh.indices[3 * tri + 2]];
        (holds ? held : translucent)
            .triangle(a, b, c, {kVolume, e, side, holds ? 1 : 0,
                                ViewCells::bytes(side == 0 ? kOuterRgb : kInnerRgb, holds ? 0.55f : faint)});
    }
    if (point) opaque.line(*point, *point, {kPicked, -1, -1, 0, ViewCells::bytes(kPickedRgb, 1.0f)});

    char head[400];
    std::snprintf(head, sizeof head,
                  "penumbra-volumes  %s / %s, t = %.3g s: %zu silhouette edges (white), %zu outer volumes "
                  "(orange) and %zu inner (blue) as rasterized; light (yellow)",
                  scene.name.c_str(), l.desc->id.c_str(), t, edges.primitiveCount(), outer / 2, inner / 2);
    result.caption = head;
    if (!pixelLine.empty()) result.caption += "\n" + pixelLine;
    data["edges"] = edges.primitiveCount();
    data["outer_volumes"] = outer / 2;
    data["inner_volumes"] = inner / 2;
    result.data = data;
    drawVolumeScene(ctx, renderer, scene, t, light, edges, point, opaque, held, translucent,
                    addCaptionStrip(ctx.out, result.caption));
}

}  // namespace penumbra_volumes_view

const ViewDesc& penumbraVolumesView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "penumbra-volumes";
        d.info.doc = "penumbra volumes in 3D: the silhouette edges from the light's centre, the outer (orange) and "
                     "inner (blue) volumes translucent, exactly as rasterized; with --pixel the point and the volume "
                     "covering it bright, with the record's k and v (pvm) or d_o, w_pcf and samples (pvmf)";
        d.info.appliesTo = "techniques with penumbra volumes (pvm, pvmf)";
        d.info.exportExtension = ".vtp";
        d.refusal = penumbra_volumes_view::refusal;
        d.build = penumbra_volumes_view::build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
