// `spsm-texels`: the look-up of sub-pixel shadow maps (lecocq2014) for the picked pixel, in light
// space, beside which step decided every pixel of the image.
//  - Left, SPSM space (texel units, y up; texel (i, j) is the square [i, i+1] x [j, j+1]): the k x k
//    texels around the receiver's texel (grid lines; k = 3 as the paper, larger when the look-up's
//    neighbourhood tested more), the stored triangles of the texels the look-up intersected (the
//    record's `tested`; a triangle stored in several texels is one triangle: each distinct one is
//    one colour, outline and translucent fill, and a square of that colour in the corner of each
//    texel storing it), the projected point p (the paper's "p in light
//    space", magenta +), and when the look-up reached the reconstruction (the paper's Fig. 1 right
//    and Fig. 2): the 3x3 depth comparisons (white squares: neighbours in front of p, hollow: not),
//    the approximate tangent (cyan, the line through the texel centre along the edge's tangent)
//    and the reconstructed edge (yellow, the segment joining the linked vertices `left` and
//    `right`; a yellow square where both are one vertex).
//  - Right: the `branches` internal over the image, one colour per look-up step, with a legend
//    naming each step and counting its pixels in that very image (the white square: the pick).
// The caption states the counts drawn: texels tested, distinct triangles, the edge's numbers.
// Export (.vtp): the distinct triangles (polygons, cell data `part` 0, `triangle` its index,
// `texels` how many tested texels store it), the grid (lines, part 1), p (a vertex, part 2), the
// tangent (part 3) and the edge (part 4), in SPSM coordinates.
// Reads only the technique's per-pixel record (fields `spsm_position`, `texel`, `tested`,
// `occluding`, `edge`, `branch`) and its `branches` image internal.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapper3D.h>
#include <vtkIntArray.h>
#include <vtkLookupTable.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPropCollection.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {

// The look-up steps by value (shaders/spsm/branches.glsl; the names the record and --stats use),
// each with its colour: the lit ends cream and green, the shadowed ones dark brown and red, the
// reconstructed edge yellow as the edge drawn on the left, background the no-data grey.
struct BranchClass {
    const char* name;
    glm::vec3 rgb;
};
constexpr int kBranches = 9;
const std::array<BranchClass, kBranches>& branchClasses() {
    static const std::array<BranchClass, kBranches> c = {{
        {"background", kBackgroundGrey},
        {"on_triangle", {0.97f, 0.93f, 0.80f}},
        {"hit", {0.22f, 0.10f, 0.03f}},
        {"neighbour_hit", {0.85f, 0.22f, 0.18f}},
        {"neighbour_cover", {0.45f, 0.82f, 0.40f}},
        {"reconstructed_edge", {1.00f, 0.82f, 0.10f}},
        {"fallback", {0.88f, 0.30f, 0.85f}},
        {"empty", {0.40f, 0.68f, 1.00f}},
        {"facing_away", {0.18f, 0.22f, 0.45f}},
    }};
    return c;
}

// The stored triangles' colours, one per distinct triangle (cycled past ten).
// None near the tangent's cyan, the edge's yellow, p's magenta or the marks' white.
const glm::vec3 kTriangleRgb[] = {{0.35f, 0.45f, 0.95f}, {1.00f, 0.50f, 0.10f}, {0.25f, 0.75f, 0.30f},
                                  {0.85f, 0.20f, 0.25f}, {0.60f, 0.40f, 0.90f}, {0.65f, 0.45f, 0.25f},
                                  {0.95f, 0.60f, 0.75f}, {0.60f, 0.65f, 0.15f}, {0.45f, 0.55f, 0.65f},
                                  {0.75f, 0.30f, 0.55f}};
constexpr int kTriangleColours = 10;
const glm::vec3 kPointRgb(1.0f, 0.2f, 0.9f), kTangentRgb(0.2f, 0.9f, 1.0f), kEdgeRgb(1.0f, 0.85f, 0.1f);

// The record internal of the light's technique with the SPSM look-up's fields ("" if none).
bool hasSpsmRecord(const LightState& l) {
    for (const InternalDesc& i : l.desc->internals) {
        if (i.kind != InternalDesc::Kind::Record) continue;
        bool position = false, tested = false;
        for (const auto& [field, doc] : i.schema) {
            position = position || field == "spsm_position";
            tested = tested || field == "tested";
        }
        if (position && tested) return true;
    }
    return false;
}

std::string refusal(const LightState& l, const ViewRequest& request) {
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    const InternalDesc* b = l.desc->findInternal("branches");
    if (!hasSpsmRecord(l) || !b || b->kind != InternalDesc::Kind::Image)
        return "technique " + l.desc->id + " stores no triangles per texel (a per-pixel record with 'spsm_position' "
               "and 'tested', and a 'branches' image: spsm)";
    if (!request.pixel) return "the spsm-texels view needs a picked pixel (--pixel x,y)";
    return "";
}

glm::vec2 vec2(const nlohmann::json& j) { return {j.at(0).get<float>(), j.at(1).get<float>()}; }

// Pixels per branch value of a `branches` image (values rounded; anything else is an error).
std::array<size_t, kBranches> branchCounts(const Image& branches) {
    std::array<size_t, kBranches> n{};
    for (size_t i = 0; i < branches.pixelCount(); ++i) {
        const float v = branches.data[i * size_t(branches.channels)];
        const long k = std::lround(v);
        if (!std::isfinite(v) || k < 0 || k >= kBranches)
            throw InternalError("spsm-texels: branch " + formatNumber(v) + " outside 0..8 at pixel " + std::to_string(i));
        ++n[size_t(k)];
    }
    return n;
}

vtkSmartPointer<vtkLookupTable> branchLut() {
    auto lut = vtkSmartPointer<vtkLookupTable>::New();
    lut->SetNumberOfTableValues(kBranches);
    lut->SetTableRange(-0.5, kBranches - 0.5);  // value k -> entry k
    for (int k = 0; k < kBranches; ++k) {
        const glm::vec3 c = branchClasses()[size_t(k)].rgb;
        lut->SetTableValue(k, c.r, c.g, c.b, 1.0);
    }
    lut->SetNanColor(kBackgroundGrey.r, kBackgroundGrey.g, kBackgroundGrey.b, 1.0);
    return lut;
}

// A distinct stored triangle of the record: its vertices and the tested texels that store it.
struct StoredTriangle {
    std::array<glm::vec2, 3> v;
    std::vector<glm::ivec2> texels;
    std::vector<std::string> results;
};

std::vector<StoredTriangle> distinctTriangles(const nlohmann::json& tested) {
    std::vector<StoredTriangle> out;
    for (const auto& t : tested) {
        const std::array<glm::vec2, 3> v = {vec2(t.at("vertices")[0]), vec2(t.at("vertices")[1]), vec2(t.at("vertices")[2])};
        const glm::ivec2 texel(t.at("texel")[0].get<int>(), t.at("texel")[1].get<int>());
        auto same = std::find_if(out.begin(), out.end(), [&](const StoredTriangle& s) { return s.v == v; });
        if (same == out.end()) {
            out.push_back({v, {}, {}});
            same = out.end() - 1;
        }
        same->texels.push_back(texel);
        same->results.push_back(t.at("result").get<std::string>());
    }
    return out;
}

using Segments = std::vector<std::pair<glm::vec3, glm::vec3>>;

void square(Segments& s, glm::vec2 c, float half, float z) {
    const glm::vec3 a(c.x - half, c.y - half, z), b(c.x + half, c.y - half, z), d(c.x + half, c.y + half, z),
        e(c.x - half, c.y + half, z);
    s.insert(s.end(), {{a, b}, {b, d}, {d, e}, {e, a}});
}

// Small filled squares (the depth comparisons' marks, the edge's single vertex) as one actor.
vtkSmartPointer<vtkActor> filledSquares(const std::vector<glm::vec2>& centres, float half, float z, glm::vec3 rgb) {
    vtkNew<FunctionSource> source;
    source->SetGenerator([centres, half, z](vtkPolyData* out) {
        vtkNew<vtkPoints> points;
        vtkNew<vtkCellArray> cells;
        for (const glm::vec2 c : centres) {
            vtkIdType ids[4] = {points->InsertNextPoint(c.x - half, c.y - half, z), points->InsertNextPoint(c.x + half, c.y - half, z),
                                points->InsertNextPoint(c.x + half, c.y + half, z), points->InsertNextPoint(c.x - half, c.y + half, z)};
            cells->InsertNextCell(4, ids);
        }
        out->SetPoints(points);
        out->SetPolys(cells);
    });
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(source->GetOutputPort());
    mapper->ScalarVisibilityOff();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(rgb.r, rgb.g, rgb.b);
    actor->GetProperty()->LightingOff();
    return actor;
}

// A panel's camera showing the world box [c - half, c + half] (square) below a title band of
// `titleShare` of the panel's height, in a viewport of aspect w / h.
void boxCamera(vtkRenderer* r, glm::dvec2 c, double half, double aspect, double titleShare) {
    vtkCamera* camera = r->GetActiveCamera();
    camera->ParallelProjectionOn();
    const double usable = 1.0 - titleShare;
    const double scale = std::max(half, half / (aspect / usable)) / usable;  // half the viewport's height
    const double shift = scale * titleShare;
    camera->SetFocalPoint(c.x, c.y + shift, 0.0);
    camera->SetPosition(c.x, c.y + shift, 100.0);
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(scale);
    r->ResetCameraClippingRange();
}

void build(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    const glm::ivec2 px = *ctx.request.pixel;
    const nlohmann::json rec = ctx.pixelRecord();
    const std::string where = l.desc->id + ", L" + std::to_string(ctx.request.light) + ", pixel " +
                              std::to_string(px.x) + "," + std::to_string(px.y);
    if (rec.is_null() || rec.value("background", false))
        throw InputError("view spsm-texels: pixel " + std::to_string(px.x) + "," + std::to_string(px.y) +
                         " shows no geometry (background)");
    const CollectedInternal* branchesInternal = ctx.internal("branches");
    if (!branchesInternal || branchesInternal->levels.empty())
        throw InputError("view spsm-texels: technique " + l.desc->id + " wrote no 'branches' this frame");
    const Image& branches = branchesInternal->levels[0];
    const std::array<size_t, kBranches> counts = branchCounts(branches);

    const glm::vec2 p = vec2(rec.at("spsm_position"));
    const glm::ivec2 texel(rec.at("texel")[0].get<int>(), rec.at("texel")[1].get<int>());
    const glm::vec2 centre = glm::vec2(texel) + 0.5f;
    const std::string branch = rec.value("branch", "");
    const nlohmann::json tested = rec.value("tested", nlohmann::json::array());
    const std::vector<StoredTriangle> triangles = distinctTriangles(tested);
    // The neighbourhood drawn: 3x3, or as wide as the tested texels reach (neighbourhood 5, 7).
    int radius = 1;
    for (const auto& t : tested)
        radius = std::max({radius, std::abs(t.at("texel")[0].get<int>() - texel.x), std::abs(t.at("texel")[1].get<int>() - texel.y)});
    const int k = 2 * radius + 1;
    size_t hits = 0, covers = 0, misses = 0;
    for (const auto& t : tested) {
        const std::string r = t.at("result").get<std::string>();
        (r == "hit" ? hits : r == "miss" ? misses : covers) += 1;
    }
    // The 3x3 depth comparisons (rows from the bottom), when the look-up reached them.
    std::vector<glm::vec2> inFront, notInFront;
    const bool compared = rec.contains("occluding") && rec["occluding"].is_array();
    if (compared)
        for (int dy = 0; dy < 3; ++dy)
            for (int dx = 0; dx < 3; ++dx)
                (rec["occluding"][size_t(dy)][size_t(dx)].get<bool>() ? inFront : notInFront)
                    .push_back(centre + glm::vec2(float(dx - 1), float(dy - 1)));
    const nlohmann::json edge = rec.contains("edge") ? rec["edge"] : nlohmann::json();
    const bool hasEdge = edge.is_object();

    // ---- the geometry, in SPSM coordinates (one poly data for the export, one actor per part drawn)
    auto exported = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> polys, lines, verts;
    vtkNew<vtkIntArray> part, triangleIndex, texelCount;
    part->SetName("part");
    triangleIndex->SetName("triangle");
    texelCount->SetName("texels");
    vtkNew<vtkUnsignedCharArray> fills;
    fills->SetName("colour");
    fills->SetNumberOfComponents(4);
    Segments grid, tangentLine, edgeLine, hollow, pointCross;
    std::vector<Segments> outlines(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) {
        const glm::vec3 c = kTriangleRgb[i % kTriangleColours];
        const float z = 0.01f * float(i + 1) / float(triangles.size() + 1);  // overlaps blend in a fixed order
        vtkIdType ids[3];
        for (int v = 0; v < 3; ++v) ids[v] = points->InsertNextPoint(triangles[i].v[size_t(v)].x, triangles[i].v[size_t(v)].y, z);
        polys->InsertNextCell(3, ids);
        fills->InsertNextTuple4(c.r * 255.0, c.g * 255.0, c.b * 255.0, 90);
        for (int v = 0; v < 3; ++v)
            outlines[i].push_back({glm::vec3(triangles[i].v[size_t(v)], 0.03f), glm::vec3(triangles[i].v[size_t((v + 1) % 3)], 0.03f)});
    }
    const glm::vec2 lo = glm::vec2(texel - glm::ivec2(radius));
    for (int g = 0; g <= k; ++g) {
        grid.push_back({glm::vec3(lo.x + g, lo.y, 0.02f), glm::vec3(lo.x + g, lo.y + k, 0.02f)});
        grid.push_back({glm::vec3(lo.x, lo.y + g, 0.02f), glm::vec3(lo.x + k, lo.y + g, 0.02f)});
    }
    const float cross = 0.12f;
    pointCross = {{glm::vec3(p.x - cross, p.y, 0.06f), glm::vec3(p.x + cross, p.y, 0.06f)},
                  {glm::vec3(p.x, p.y - cross, 0.06f), glm::vec3(p.x, p.y + cross, 0.06f)}};
    for (const glm::vec2 c : notInFront) square(hollow, c, 0.07f, 0.04f);
    glm::vec2 left(0.0f), right(0.0f), tangent(0.0f);
    if (hasEdge) {
        tangent = vec2(edge.at("tangent"));
        const float reach = 0.5f * float(k) * 1.42f;
        tangentLine.push_back({glm::vec3(centre - reach * tangent, 0.045f), glm::vec3(centre + reach * tangent, 0.045f)});
        left = vec2(edge.at("left"));
        right = vec2(edge.at("right"));
        edgeLine.push_back({glm::vec3(left, 0.05f), glm::vec3(right, 0.05f)});
    }
    auto addSegments = [&](const Segments& s, int which) {
        for (const auto& [a, b] : s) {
            vtkIdType ids[2] = {points->InsertNextPoint(a.x, a.y, a.z), points->InsertNextPoint(b.x, b.y, b.z)};
            lines->InsertNextCell(2, ids);
            part->InsertNextValue(which);
            triangleIndex->InsertNextValue(-1);
            texelCount->InsertNextValue(0);
        }
    };
    // Cell data follow VTK's cell order: verts, lines, polys.
    {
        vtkIdType id = points->InsertNextPoint(p.x, p.y, 0.06);
        verts->InsertNextCell(1, &id);
        part->InsertNextValue(2);
        triangleIndex->InsertNextValue(-1);
        texelCount->InsertNextValue(0);
    }
    addSegments(grid, 1);
    addSegments(tangentLine, 3);
    addSegments(edgeLine, 4);
    for (size_t i = 0; i < triangles.size(); ++i) {
        part->InsertNextValue(0);
        triangleIndex->InsertNextValue(int(i));
        texelCount->InsertNextValue(int(triangles[i].texels.size()));
    }
    exported->SetPoints(points);
    exported->SetVerts(verts);
    exported->SetLines(lines);
    exported->SetPolys(polys);
    exported->GetCellData()->AddArray(part);
    exported->GetCellData()->AddArray(triangleIndex);
    exported->GetCellData()->AddArray(texelCount);

    // ---- the caption: what is drawn, with its counts
    const float vis = rec.value("visibility", NAN), cpu = rec.value("cpu_visibility", NAN);
    // Short lines: in the window's cells the caption must leave the panels room.
    std::string caption = "spsm-texels  " + where + ": p (" + formatNumber(p.x, 6) + ", " + formatNumber(p.y, 6) +
                          ") in texel (" + std::to_string(texel.x) + ", " + std::to_string(texel.y) + "), decided by " +
                          branch + ": visibility " + formatNumber(vis, 3) + " (CPU " + formatNumber(cpu, 3) + ")\n";
    caption += "left, SPSM texels: " + std::to_string(k) + "x" + std::to_string(k) + " around p's; " +
               std::to_string(tested.size()) + " tested (" + std::to_string(hits) + " hit, " + std::to_string(covers) +
               " cover, " + std::to_string(misses) + " miss), " + std::to_string(triangles.size()) +
               " distinct triangles (corner squares: which texel stores which); p magenta\n";
    if (hasEdge)
        caption += "white: " + std::to_string(inFront.size()) + " of the 3x3 in front of p; tangent cyan; edge yellow (" +
                   std::to_string(edge.value("kept_vertices", 0)) + " vertices kept): d_p " +
                   formatNumber(edge.value("d_p", 0.0), 3) + ", d_edge " + formatNumber(edge.value("d_edge", 0.0), 3) +
                   ": " + (edge.value("shadowed", false) ? "shadowed" : "lit") + "\n";
    else if (compared)
        caption += "white: " + std::to_string(inFront.size()) + " of the 3x3 in front of p; no edge (" + branch + ")\n";
    else
        caption += "no reconstruction: " + branch + " decided first\n";
    caption += "right: the step that decided each of the " + std::to_string(branches.width) + "x" +
               std::to_string(branches.height) + " pixels, counted in the legend; white square: the pick";

    // ---- layout: [texels | branch map | legend] over the caption strip
    std::vector<LegendEntry> entries;
    nlohmann::json legend = nlohmann::json::array(), countsJ = nlohmann::json::object();
    for (int b = 0; b < kBranches; ++b) {
        const BranchClass& c = branchClasses()[size_t(b)];
        entries.push_back({c.rgb, std::string(c.name) + ": " + std::to_string(counts[size_t(b)])});
        legend.push_back({{"branch", b}, {"name", c.name}, {"count", counts[size_t(b)]}, {"rgb", {c.rgb.r, c.rgb.g, c.rgb.b}}});  // "drawn" below
        countsJ[c.name] = counts[size_t(b)];
    }
    const int W = ctx.out.width(), H = ctx.out.height();
    // A short picture (a window cell, whose tooltip shows the whole caption) draws the caption's
    // counts on one line, so that the panels keep their room.
    const std::string shortCaption = "texel (" + std::to_string(texel.x) + ", " + std::to_string(texel.y) + "): " + branch +
                                     ", " + std::to_string(tested.size()) + " tested, " + std::to_string(triangles.size()) +
                                     " triangles" + (hasEdge ? ", edge yellow" : "");
    auto shown = [&](const std::string& full) { return H < 320 ? shortCaption : full; };
    // The legend in one column, or two when one is taller than the panels (the window's short cells).
    // The caption strip's share of the picture as addCaptionStrip lays it out (captionStripLayout).
    auto stripShare = [&](const std::string& text) { return captionStripLayout(ctx.out, shown(text)).share; };
    const double panelPx = H * (1.0 - stripShare(caption + "; shown at 99.9%, counts of every pixel"));
    // Every step when they fit in one column; in a short picture only the steps that decided some
    // pixel (the others are nowhere in the map), in two columns if one is still too tall.
    std::vector<LegendEntry> drawnEntries = entries;
    if (legendHeightPx("", entries, H, legendWidthPx("", entries, H)) > panelPx) {
        drawnEntries.clear();
        for (int b = 0; b < kBranches; ++b)
            if (counts[size_t(b)] > 0) drawnEntries.push_back(entries[size_t(b)]);
    }
    const size_t half = (drawnEntries.size() + 1) / 2;
    const std::vector<LegendEntry> firstHalf(drawnEntries.begin(), drawnEntries.begin() + std::ptrdiff_t(half)),
        secondHalf(drawnEntries.begin() + std::ptrdiff_t(half), drawnEntries.end());
    const int oneColumnW = legendWidthPx("", drawnEntries, H);
    const int twoColumnW = legendWidthPx("", firstHalf, H) + legendWidthPx("", secondHalf, H);
    const bool twoColumns = legendHeightPx("", drawnEntries, H, oneColumnW) > panelPx;
    const int legendW = std::min(int(0.55 * W), twoColumns ? twoColumnW : oneColumnW);
    const double legendShare = double(legendW) / W;
    const double frameAspect = double(branches.width) / std::max(1, branches.height);
    const double texShare = (1.0 - legendShare) * std::clamp(1.0 / (1.0 + frameAspect), 0.4, 0.6);

    // The branch map's magnification (picture pixels per frame pixel): under 1 not every pixel is drawn.
    auto titleShareOf = [&](double strip) { return std::min(0.4, 1.6 * textPx(H) / ((1.0 - strip) * H)); };
    auto magnification = [&](double strip) {
        const double w = (1.0 - legendShare - texShare) * W, h = (1.0 - strip) * H, t = titleShareOf(strip);
        const double fitted = 0.5 * std::max<double>(branches.height, branches.width / (w / (h * (1.0 - t)))) * 1.08;
        return h / (2.0 * fitted / (1.0 - t));
    };
    const std::string note = "; shown at " + formatNumber(100.0 * magnification(stripShare(caption + "; shown at 99.9%, counts of every pixel")), 3) +
                             "%, counts of every pixel";
    if (magnification(stripShare(caption)) < 1.0) caption += note;
    result.caption = caption;
    const double strip = addCaptionStrip(ctx.out, shown(caption));
    const double titleShare = titleShareOf(strip);
    const double panelH = (1.0 - strip) * H;

    // Left: the texels.
    vtkRenderer* left3 = ctx.out.addRenderer();
    left3->SetViewport(0.0, strip, texShare, 1.0);
    left3->SetBackground(0.12, 0.12, 0.14);
    {
        vtkNew<FunctionSource> texelsSource;  // the k x k texels, filled a shade lighter than the panel
        texelsSource->SetGenerator([lo, k](vtkPolyData* out) {
            vtkNew<vtkPoints> pts;
            vtkNew<vtkCellArray> c;
            vtkIdType ids[4] = {pts->InsertNextPoint(lo.x, lo.y, -0.01), pts->InsertNextPoint(lo.x + k, lo.y, -0.01),
                                pts->InsertNextPoint(lo.x + k, lo.y + k, -0.01), pts->InsertNextPoint(lo.x, lo.y + k, -0.01)};
            c->InsertNextCell(4, ids);
            out->SetPoints(pts);
            out->SetPolys(c);
        });
        vtkNew<vtkPolyDataMapper> m;
        m->SetInputConnection(texelsSource->GetOutputPort());
        m->ScalarVisibilityOff();
        vtkNew<vtkActor> a;
        a->SetMapper(m);
        a->GetProperty()->SetColor(0.2, 0.2, 0.23);
        a->GetProperty()->LightingOff();
        left3->AddActor(a);
    }
    if (!triangles.empty()) {
        vtkNew<FunctionSource> fillSource;  // the distinct triangles, translucent
        vtkSmartPointer<vtkPolyData> tri = vtkSmartPointer<vtkPolyData>::New();
        tri->SetPoints(points);
        tri->SetPolys(polys);
        tri->GetCellData()->SetScalars(fills);
        fillSource->SetGenerator([tri](vtkPolyData* out) { out->ShallowCopy(tri); });
        vtkNew<vtkPolyDataMapper> m;
        m->SetInputConnection(fillSource->GetOutputPort());
        m->SetScalarModeToUseCellData();
        m->SetColorModeToDirectScalars();
        vtkNew<vtkActor> a;
        a->SetMapper(m);
        a->GetProperty()->LightingOff();
        a->ForceOpaqueOn();  // GL blending in the opaque pass (the offscreen frame has no depth for VTK's translucent pass)
        left3->AddActor(a);
    }
    left3->AddActor(lineActor(grid, glm::vec3(0.62f), 1.0f));
    for (size_t i = 0; i < triangles.size(); ++i) left3->AddActor(lineActor(outlines[i], kTriangleRgb[i % kTriangleColours], 2.0f));
    // Which triangle each tested texel stores: a square of its colour in the texel's lower-left corner.
    for (size_t i = 0; i < triangles.size(); ++i) {
        std::vector<glm::vec2> corners;
        for (const glm::ivec2 q : triangles[i].texels) corners.push_back(glm::vec2(q) + 0.14f);
        left3->AddActor(filledSquares(corners, 0.09f, 0.04f, kTriangleRgb[i % kTriangleColours]));
    }
    if (!inFront.empty()) left3->AddActor(filledSquares(inFront, 0.07f, 0.04f, glm::vec3(0.95f)));
    if (!hollow.empty()) left3->AddActor(lineActor(hollow, glm::vec3(0.95f), 1.5f));
    if (hasEdge) {
        left3->AddActor(lineActor(tangentLine, kTangentRgb, 2.0f));
        if (glm::length(right - left) > 1e-6f) left3->AddActor(lineActor(edgeLine, kEdgeRgb, 3.5f));
        left3->AddActor(filledSquares({left, right}, 0.06f, 0.05f, kEdgeRgb));
    }
    left3->AddActor(lineActor(pointCross, kPointRgb, 3.0f));
    boxCamera(left3, glm::dvec2(lo) + 0.5 * k, 0.5 * k + 0.25, texShare * W / panelH, titleShare);
    {
        // Slivers reach past the k x k box into the title's band: the title on the panel's colour, so
        // their outlines pass behind it rather than through its letters.
        vtkSmartPointer<vtkTextActor> title =
            titleActor("texels around (" + std::to_string(texel.x) + ", " + std::to_string(texel.y) + ")", H);
        title->GetTextProperty()->SetBackgroundColor(0.12, 0.12, 0.14);
        title->GetTextProperty()->SetBackgroundOpacity(1.0);
        left3->AddActor2D(title);
    }

    // Middle: the branch map.
    vtkRenderer* map = ctx.out.addRenderer();
    map->SetViewport(texShare, strip, 1.0 - legendShare, 1.0);
    map->SetBackground(0.12, 0.12, 0.14);
    auto image = toImageData(branches, {"branch"});
    addImagePanel(map, image, "branch", branchLut());
    vtkPropCollection* props = map->GetViewProps();
    props->InitTraversal();
    for (vtkProp* prop = props->GetNextProp(); prop; prop = props->GetNextProp())
        if (auto* a = vtkImageActor::SafeDownCast(prop)) a->GetMapper()->BorderOn();  // every pixel whole
    {
        const double mapW = (1.0 - legendShare - texShare) * W;
        // Fit the whole frame: the larger of its half height and half width over the aspect, 8% margin.
        const double usable = 1.0 - titleShare, aspect = mapW / panelH;
        const double half = 0.54 * std::max<double>(branches.height, branches.width / (aspect / usable));
        boxCamera(map, glm::dvec2(0.5 * (branches.width - 1), 0.5 * (branches.height - 1)), half, aspect, titleShare);
        // The pick: pixel (x, y from the top) is VTK's point (x, height - 1 - y).
        const glm::vec2 at(float(px.x), float(branches.height - 1 - px.y));
        Segments ring;
        square(ring, at, std::max(2.5f, 0.025f * float(std::max(branches.width, branches.height))), 0.1f);
        map->AddActor(lineActor(ring, glm::vec3(1.0f), 2.0f));
    }
    map->AddActor2D(titleActor("look-up step per pixel (legend: pixels)", H));

    // Right: the legend.
    if (twoColumns) {
        const double split = 1.0 - legendShare + legendShare * double(legendWidthPx("", firstHalf, H)) / twoColumnW;
        vtkRenderer* first = ctx.out.addRenderer();
        first->SetViewport(1.0 - legendShare, strip, split, 1.0);
        first->SetBackground(0.12, 0.12, 0.14);
        addLegend(first, "", firstHalf, H);
        vtkRenderer* second = ctx.out.addRenderer();
        second->SetViewport(split, strip, 1.0, 1.0);
        second->SetBackground(0.12, 0.12, 0.14);
        addLegend(second, "", secondHalf, H);
    } else {
        vtkRenderer* side = ctx.out.addRenderer();
        side->SetViewport(1.0 - legendShare, strip, 1.0, 1.0);
        side->SetBackground(0.12, 0.12, 0.14);
        addLegend(side, "", drawnEntries, H);
    }

    nlohmann::json trianglesJ = nlohmann::json::array();
    for (const StoredTriangle& t : triangles) {
        nlohmann::json texels = nlohmann::json::array();
        for (const glm::ivec2 q : t.texels) texels.push_back({q.x, q.y});
        trianglesJ.push_back({{"vertices", {{t.v[0].x, t.v[0].y}, {t.v[1].x, t.v[1].y}, {t.v[2].x, t.v[2].y}}},
                              {"texels", texels},
                              {"results", t.results}});
    }
    result.data = {{"pixel", {px.x, px.y}},
                   {"spsm_position", {p.x, p.y}},
                   {"texel", {texel.x, texel.y}},
                   {"neighbourhood_drawn", k},
                   {"branch", branch},
                   {"visibility", vis},
                   {"cpu_visibility", cpu},
                   {"tested", tested.size()},
                   {"results", {{"hit", hits}, {"behind_or_on", covers}, {"miss", misses}}},
                   {"triangles", trianglesJ},
                   {"triangles_drawn", triangles.size()},
                   {"in_front", inFront.size()},
                   {"edge", edge},
                   {"counts", countsJ},
                   {"legend", legend},
                   {"legend_drawn", drawnEntries.size()},
                   {"magnification", magnification(strip)}};
    if (!ctx.request.exportPath.empty()) writePolyData(exported, ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& spsmTexelsView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "spsm-texels";
        // The texels' square, the frame-shaped branch map and the legend, over a caption of four lines.
        d.aspect = [](const Renderer&, const ViewRequest&, float frame) {
            return (1.0f + frame + 0.75f) * (1.0f - 1.6f * kCaptionShare);
        };
        d.info.doc = "the picked pixel's SPSM look-up in light space: its texel and neighbours, the stored triangles it "
                     "intersected, p, the approximate tangent and the reconstructed edge; beside it the look-up step "
                     "that decided every pixel, with its pixel count";
        d.info.appliesTo = "techniques whose per-pixel record has 'spsm_position' and 'tested' and with a 'branches' "
                           "image (spsm); needs --pixel";
        d.info.exportExtension = ".vtp";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
