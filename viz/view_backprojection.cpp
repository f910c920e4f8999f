// `backprojection`: the picked pixel's light (the square [-1,1]^2 or the unit disk, in the light
// coordinates of the per-pixel record) with what the technique back-projected onto it
// (guennebaud2007 sections 3-4): ssm-gbp06's occluding samples as quads (after gap filling,
// clipped to the light's square; overlaps darken, which is the overestimation) or ssm-contour's
// contour edges with their signed areas as fans from the light centre (Fig. 5a: red adds occluded
// area, clockwise; blue removes it, counter-clockwise). The caption prints the visible fraction
// recomputed from the record: clamp(1 - (initial_area + sum of areas) / light area, 0, 1).
// Reads only the "pixel" record of the technique's Record internal (fields `samples` or `edges`).
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {

// The list field of the light's per-pixel record this view draws: "edges" or "samples" ("" if none).
std::string recordList(const LightState& l) {
    for (const InternalDesc& i : l.desc->internals) {
        if (i.kind != InternalDesc::Kind::Record) continue;
        for (const auto& [field, doc] : i.schema)
            if (field == "edges" || field == "samples") return field;
    }
    return "";
}

std::string refusal(const Renderer& renderer, const ViewRequest& request) {
    const LightState& l = *renderer.lights().at(size_t(request.light));
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (recordList(l).empty())
        return "technique " + l.desc->id +
               " records no back-projection (a per-pixel record with 'edges' or 'samples' on the light)";
    if (!request.pixel) return "the backprojection view needs a picked pixel (--pixel x,y)";
    return "";
}

glm::vec2 vec2(const nlohmann::json& j) { return {j.at(0).get<float>(), j.at(1).get<float>()}; }

void build(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    const std::string list = recordList(l);
    const nlohmann::json rec = ctx.pixelRecord();
    const glm::ivec2 px = *ctx.request.pixel;
    const std::string where = l.desc->id + ", L" + std::to_string(ctx.request.light) + ", pixel " +
                              std::to_string(px.x) + "," + std::to_string(px.y);
    if (rec.is_null() || rec.value("background", false)) {
        throw InputError("view backprojection: pixel " + std::to_string(px.x) + "," + std::to_string(px.y) +
                         " shows no geometry (background)");
    }
    if (!rec.contains("light_geometry"))
        throw InputError("view backprojection: the " + l.desc->id + " record of pixel " + std::to_string(px.x) + "," +
                         std::to_string(px.y) + " has no light_geometry");
    const nlohmann::json& geometry = rec.at("light_geometry");
    const bool disk = geometry.value("shape", "square") != "square";
    const double lightArea = geometry.at("area").get<double>();
    const double initial = rec.value("initial_area", 0.0);
    const nlohmann::json items = rec.value(list, nlohmann::json::array());
    const bool edges = list == "edges";

    // Geometry: one polygon cell per item (edge: triangle centre, a, b; sample: its quad clipped to
    // the light's square), cell data signed_area.
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> polys;
    vtkNew<vtkFloatArray> areas;
    areas->SetName("signed_area");
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetName("colour");
    colours->SetNumberOfComponents(4);
    std::vector<std::pair<glm::vec3, glm::vec3>> edgeLines;
    double sum = 0.0, added = 0.0, removed = 0.0;
    double z = 0.0;
    for (const auto& it : items) {
        z += 0.01 / double(items.size() + 1);
        double area = it.at(edges ? "signed_area" : "area").get<double>();
        sum += area;
        (area >= 0.0 ? added : removed) += area;
        if (edges) {
            glm::vec2 a = vec2(it.at("a")), b = vec2(it.at("b"));
            vtkIdType ids[3] = {points->InsertNextPoint(0, 0, z), points->InsertNextPoint(a.x, a.y, z),
                                points->InsertNextPoint(b.x, b.y, z)};
            polys->InsertNextCell(3, ids);
            edgeLines.push_back({glm::vec3(a, 0.02f), glm::vec3(b, 0.02f)});
            if (area >= 0.0)
                colours->InsertNextTuple4(214, 60, 50, 110);
            else
                colours->InsertNextTuple4(60, 110, 220, 110);
        } else {
            const auto& q = it.at("quad");
            float x0 = std::max(q[0].get<float>(), -1.0f), y0 = std::max(q[1].get<float>(), -1.0f);
            float x1 = std::min(q[2].get<float>(), 1.0f), y1 = std::min(q[3].get<float>(), 1.0f);
            x1 = std::max(x1, x0);
            y1 = std::max(y1, y0);
            vtkIdType ids[4] = {points->InsertNextPoint(x0, y0, z), points->InsertNextPoint(x1, y0, z),
                                points->InsertNextPoint(x1, y1, z), points->InsertNextPoint(x0, y1, z)};
            polys->InsertNextCell(4, ids);
            edgeLines.push_back({glm::vec3(x0, y0, 0.02f), glm::vec3(x1, y0, 0.02f)});
            edgeLines.push_back({glm::vec3(x1, y0, 0.02f), glm::vec3(x1, y1, 0.02f)});
            edgeLines.push_back({glm::vec3(x1, y1, 0.02f), glm::vec3(x0, y1, 0.02f)});
            edgeLines.push_back({glm::vec3(x0, y1, 0.02f), glm::vec3(x0, y0, 0.02f)});
            colours->InsertNextTuple4(225, 130, 30, 110);  // overlaps add up: darker = counted again
        }
        areas->InsertNextValue(float(area));
    }
    poly->SetPoints(points);
    poly->SetPolys(polys);
    poly->GetCellData()->AddArray(areas);
    poly->GetCellData()->SetScalars(colours);

    const double occluded = initial + sum;
    const double visible = std::clamp(1.0 - occluded / lightArea, 0.0, 1.0);
    const double gpu = rec.value("visibility", std::nan(""));

    std::string caption = "backprojection  " + where + ", " + rec.value("classification", "") + "\n";
    if (edges)
        caption += std::to_string(items.size()) + " contour edges: +" + formatNumber(added) + " (red, cw) " +
                   formatNumber(removed) + " (blue, ccw), initial " + formatNumber(initial) + " (centre " +
                   (initial > 0.0 ? "occluded" : "visible") + ")\n";
    else
        caption += std::to_string(items.size()) + " occluding samples (quads): sum " + formatNumber(sum) +
                   ", initial " + formatNumber(initial) + "; overlaps count twice\n";
    caption += "occluded " + formatNumber(occluded, 5) + " of " + formatNumber(lightArea, 5) + ": visible fraction " +
               formatNumber(visible, 6) + " (image: " + formatNumber(gpu, 6) + ")";
    result.caption = caption;
    result.data = {{"pixel", {px.x, px.y}},        {"list", list},         {"count", items.size()},
                   {"light_shape", disk ? "disk" : "square"}, {"light_area", lightArea},
                   {"initial_area", initial},      {"sum_areas", sum},     {"occluded_area", occluded},
                   {"visible_fraction", visible},  {"visibility", gpu},    {"cells", poly->GetNumberOfCells()}};

    const double strip = addCaptionStrip(ctx.out, caption, true);
    vtkRenderer* r = ctx.out.addRenderer();
    r->SetViewport(0.0, strip, 1.0, 1.0);
    r->SetBackground(0.12, 0.12, 0.14);
    // The light: filled pale, outlined.
    {
        vtkNew<FunctionSource> src;
        src->SetGenerator([disk](vtkPolyData* out) {
            vtkNew<vtkPoints> p;
            vtkNew<vtkCellArray> c;
            const int n = disk ? 96 : 4;
            std::vector<vtkIdType> ids;
            for (int i = 0; i < n; ++i) {
                double a = 2.0 * M_PI * (i + (disk ? 0.0 : 0.5)) / n;
                double s = disk ? 1.0 : std::sqrt(2.0);
                ids.push_back(p->InsertNextPoint(s * std::cos(a), s * std::sin(a), -0.01));
            }
            c->InsertNextCell(vtkIdType(ids.size()), ids.data());
            out->SetPoints(p);
            out->SetPolys(c);
        });
        vtkNew<vtkPolyDataMapper> m;
        m->SetInputConnection(src->GetOutputPort());
        m->ScalarVisibilityOff();
        vtkNew<vtkActor> a;
        a->SetMapper(m);
        a->GetProperty()->SetColor(0.96, 0.93, 0.78);
        a->GetProperty()->LightingOff();
        r->AddActor(a);
    }
    {
        vtkNew<vtkPolyDataMapper> m;
        m->SetInputData(poly);
        m->SetScalarModeToUseCellData();
        m->SetColorModeToDirectScalars();
        vtkNew<vtkActor> a;
        a->SetMapper(m);
        a->GetProperty()->LightingOff();
        // Drawn in the opaque pass with GL blending (VTK's translucent pass blits a depth buffer the
        // offscreen frame cannot give it): each item lies a little above the previous one, so
        // overlaps blend and show.
        a->ForceOpaqueOn();
        r->AddActor(a);
    }
    r->AddActor(lineActor(edgeLines, edges ? glm::vec3(0.05f) : glm::vec3(0.55f, 0.3f, 0.05f), edges ? 2.0f : 1.0f));
    // Axes through the light centre, the light's border on top.
    std::vector<std::pair<glm::vec3, glm::vec3>> border;
    const int n = disk ? 96 : 4;
    for (int i = 0; i < n; ++i) {
        double s = disk ? 1.0 : std::sqrt(2.0), o = disk ? 0.0 : 0.5;
        double a0 = 2.0 * M_PI * (i + o) / n, a1 = 2.0 * M_PI * (i + 1 + o) / n;
        border.push_back({glm::vec3(s * std::cos(a0), s * std::sin(a0), 0.03), glm::vec3(s * std::cos(a1), s * std::sin(a1), 0.03)});
    }
    r->AddActor(lineActor(border, glm::vec3(0.95f), 2.0f));
    r->AddActor(lineActor({{glm::vec3(-0.06f, 0, 0.04f), glm::vec3(0.06f, 0, 0.04f)},
                           {glm::vec3(0, -0.06f, 0.04f), glm::vec3(0, 0.06f, 0.04f)}},
                          glm::vec3(0.9f, 0.1f, 0.1f), 2.0f));
    r->AddActor2D(titleActor(std::string(disk ? "light disk" : "light square [-1,1]^2") + " seen from the pixel: " +
                                 (edges ? "contour edges, fans from the centre" : "back-projected samples"),
                             ctx.out.height()));
    vtkCamera* camera = r->GetActiveCamera();
    camera->ParallelProjectionOn();
    camera->SetFocalPoint(0, 0, 0);
    camera->SetPosition(0, 0, 10);
    camera->SetViewUp(0, 1, 0);
    const double aspect = ctx.out.width() / ((1.0 - strip) * ctx.out.height());
    camera->SetParallelScale(1.25 * std::max(1.0, 1.0 / aspect));
    r->ResetCameraClippingRange();

    if (!ctx.request.exportPath.empty()) writePolyData(poly, ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& backprojectionView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "backprojection";
        // The light's square, over a caption of four lines.
        d.aspect = [](const Renderer&, const ViewRequest&, float) { return 1.0f - 1.6f * kCaptionShare; };
        d.info.doc = "the picked pixel's light with the back-projected samples (quads) or contour edges (signed fans "
                     "from the light centre, red adds, blue removes) and the visible fraction";
        d.info.appliesTo = "techniques whose per-pixel record lists back-projected 'samples' or 'edges' "
                           "(ssm-gbp06, ssm-contour); needs --pixel";
        d.info.exportExtension = ".vtp";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
