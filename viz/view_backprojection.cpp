// `backprojection`: the picked pixel's light (the square [-1,1]^2 or the unit disk, in the light
// coordinates of the per-pixel record) with what the technique back-projected onto it
// (guennebaud2007 sections 3-4), drawn as exactly the regions whose areas the technique adds up.
//  - ssm-contour: each contour edge a -> b is the region its signed area measures (sec. 4.2,
//    Fig. 5a; edgeOccludedArea in shaders/shared/backprojection.glsl section 5): for the edge clipped
//    to the light, ca -> cb, the part of the light BEYOND the edge inside the edge's wedge from the
//    light centre, bounded by ca -> cb, the ray from cb out to the light's border, the border back
//    to the ray through ca, and that ray. Its area is triangle(centre, ca, cb) - radialSweep(ca, cb):
//    red and counter-clockwise-drawn when positive (a clockwise edge: crossing it going out enters
//    the occluder), blue and clockwise-drawn when negative (a counter-clockwise edge leaves it). An
//    edge through or ending on the centre covers half the light, on the side radialSweep's perturbed
//    centre decides. When the centre is occluded the whole light is one more red cell, the initial
//    area (Fig. 5b).
//  - ssv: the same regions for the silhouette edges whose penumbra wedge holds the point (the
//    record's projected edges, weight w drawn w times), and one whole light per hard shadow volume
//    holding it (the initial area, hard_count x light area). Split 2 (four lights) is refused.
//  - ssm-gbp06: each occluding sample is its quad (after gap filling) clipped to the light: the
//    square's box or, for a disk, the quad's intersection with the disk (the record's `area` is
//    rectOccludedArea, the clipped area).
//  - pvm (cournia2005 sec. 4.2, Fig. 4.4-4.5): inside a penumbra volume, the disk of the light's
//    radius about its centre perpendicular to the cutting plane through the volume's edge and the
//    point, drawn as the unit disk with the plane's normal to the right: the cutting line at
//    u = -s / r, the visible part u > -s / r (area 2a / r^2, a from eq. 4.1 at -s) and the hidden
//    part one red cell (area pi - 2a / r^2); k = 2a / (pi r^2) (eq. 4.2) and the caption's
//    v = 3k^2 - 2k^3. Outside every volume the shadow-map test: the whole disk hidden, or none.
// The left panel draws every region translucent, so overlaps add up in colour; the right panel
// draws their sum: each point of the light coloured by the net number of regions covering it
// (signed: the winding numbers of the cells), which is what the technique integrates, so its dark
// part is the occluded light. The caption prints the visible fraction recomputed from the record:
// clamp(1 - (initial_area + sum of areas) / light area, 0, 1).
// Export (.vtp): one polygon cell per drawn region (the initial-area light, then the record's items
// in order), cell data `signed_area` (the record's value), `kind` (0 the initial light, 1 an edge,
// 2 a sample, 3 pvm's hidden part of the disk) and `item` (index in the record's list, -1 for the initial light). Each cell's
// shoelace area (signed by its orientation) equals its `signed_area` to 1e-5 (square: exactly, up to
// float rounding; disk: the border is cut into chords of at most 2 pi / 2048, see kArcStep).
// Reads only the "pixel" record of the technique's Record internal (fields `samples` or `edges`).
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapToColors.h>
#include <vtkImageMapper3D.h>
#include <vtkIntArray.h>
#include <vtkLookupTable.h>
#include <vtkPointData.h>
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
#include "shared/shared.h"
#include "view_common.h"

namespace shadowlab {

namespace {

namespace bp = shared;  // the shaders' back-projection math (shaders/shared/backprojection.glsl)

using Polygon = std::vector<glm::vec2>;

// The disk's border is drawn as chords of at most this angle. A chord of angle h cuts (h - sin h) / 2
// ~ h^3 / 12 off its sector, so an arc of angle theta loses theta h^2 / 12: at most 4.9e-6 for the
// whole disk (2 pi), 2.5e-6 for an edge's region (at most half the disk).
constexpr double kArcStep = 2.0 * M_PI / 2048.0;

// The list field of the light's per-pixel record this view draws: "edges" or "samples", or "disk"
// (pvm's disk and cutting plane, cournia2005 sec. 4.2); "" if none.
std::string recordList(const LightState& l) {
    for (const InternalDesc& i : l.desc->internals) {
        if (i.kind != InternalDesc::Kind::Record) continue;
        for (const auto& [field, doc] : i.schema)
            if (field == "edges" || field == "samples" || (field == "disk" && l.desc->id == "pvm")) return field;
    }
    return "";
}

std::string refusal(const LightState& l, const ViewRequest& request) {
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (recordList(l).empty())
        return "technique " + l.desc->id +
               " records no back-projection (a per-pixel record with 'edges' or 'samples' on the light, or pvm's disk)";
    if (!request.pixel) return "the backprojection view needs a picked pixel (--pixel x,y)";
    return "";
}

glm::vec2 vec2(const nlohmann::json& j) { return {j.at(0).get<float>(), j.at(1).get<float>()}; }

// The signed area of a polygon (shoelace), counter-clockwise positive.
double polygonArea(const Polygon& p) {
    double twice = 0.0;
    for (size_t i = 0; i < p.size(); ++i) {
        const glm::dvec2 a = p[i], b = p[(i + 1) % p.size()];
        twice += a.x * b.y - a.y * b.x;
    }
    return 0.5 * twice;
}

void push(Polygon& p, glm::vec2 v) {
    if (p.empty() || p.back() != v) p.push_back(v);
}

// Where the ray from the centre in direction d leaves the light.
glm::vec2 borderPoint(int shape, glm::vec2 d) {
    if (shape == bp::BP_LIGHT_SQUARE) return d / std::max(std::abs(d.x), std::abs(d.y));
    return d / std::sqrt(d.x * d.x + d.y * d.y);
}

// Corner of the square at border position c (an even number, squareBorderPosition's walk: 0 is
// (1, -1), 2 is (1, 1), 4 is (-1, 1), 6 is (-1, -1)).
glm::vec2 squareCorner(double c) {
    switch (((int(std::lround(c)) % 8) + 8) % 8) {
        case 0: return {1.0f, -1.0f};
        case 2: return {1.0f, 1.0f};
        case 4: return {-1.0f, 1.0f};
        default: return {-1.0f, -1.0f};
    }
}

// The light's border from the ray through direction `from` to the ray through `to`, turning so
// that the centre's ray sweeps the signed light area `sweep` (radialSweep's value, counter-clockwise
// positive; the sweep, not the directions, decides which way round): the two border points and the
// corners (square) or chord points (disk) between them. Walked that way, the border adds `sweep` to
// a shoelace area (each side of the square is at distance 1 from the centre; a disk chord nearly).
void appendBorder(Polygon& p, int shape, glm::vec2 from, glm::vec2 to, float sweep) {
    push(p, borderPoint(shape, from));
    if (shape == bp::BP_LIGHT_SQUARE) {
        const double start = bp::squareBorderPosition(from), end = start + 2.0 * double(sweep);
        if (end > start)
            for (double c = 2.0 * std::floor(start / 2.0) + 2.0; c < end; c += 2.0) push(p, squareCorner(c));
        else
            for (double c = 2.0 * std::ceil(start / 2.0) - 2.0; c > end; c -= 2.0) push(p, squareCorner(c));
    } else {
        const double angle = 2.0 * double(sweep), start = std::atan2(double(from.y), double(from.x));
        const int n = std::max(1, int(std::ceil(std::abs(angle) / kArcStep)));
        for (int k = 1; k < n; ++k) {
            const double t = start + angle * k / n;
            push(p, glm::vec2(float(std::cos(t)), float(std::sin(t))));
        }
    }
    push(p, borderPoint(shape, to));
}

// The region whose area edgeOccludedArea(shape, a, b) is (same clipping, same perturbation): the
// clipped edge ca -> cb, the ray out through cb, the border back (against the edge's turn) to the
// ray through ca. Its shoelace area is triangle(0, ca, cb) - radialSweep: the rays add nothing (they
// pass through the centre) and the border adds -sweep. Empty when the edge misses the light.
Polygon edgeRegion(int shape, glm::vec2 a, glm::vec2 b) {
    const glm::vec2 range = bp::clipSegmentToLight(shape, a, b);
    if (range.x > range.y) return {};
    const float turn = bp::edgeTurn(a, b);
    const glm::vec2 d = b - a, ca = a + d * range.x, cb = a + d * range.y;
    const float sweep = bp::radialSweep(shape, ca, cb, turn);
    // An end point on the centre has the direction from the perturbed centre (radialSweep's rule).
    auto direction = [](glm::vec2 v) { return v.x == 0.0f && v.y == 0.0f ? -bp::BP_PERTURBATION : v; };
    Polygon p{ca};
    push(p, cb);
    appendBorder(p, shape, direction(cb), direction(ca), -sweep);
    return p;
}

// The whole light, counter-clockwise (the initial area: the centre occluded).
Polygon lightPolygon(int shape) {
    if (shape == bp::BP_LIGHT_SQUARE) return {{1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}, {-1.0f, -1.0f}};
    Polygon p;
    const int n = int(std::ceil(2.0 * M_PI / kArcStep));
    for (int k = 0; k < n; ++k) p.push_back(glm::vec2(float(std::cos(2.0 * M_PI * k / n)), float(std::sin(2.0 * M_PI * k / n))));
    return p;
}

// A back-projected sample's quad (x0, y0, x1, y1) clipped to the light, counter-clockwise: the
// area rectOccludedArea gives it. Square: the box. Disk: walk the quad's sides counter-clockwise,
// keep their parts inside the disk (clipSegmentToDisk) and join a part that leaves the disk to the
// next one that enters it along the circle, counter-clockwise (the intersection of two convex
// regions is convex, its border turns one way). No side meets the disk: the quad holds the disk
// when it holds the centre, else misses it.
// pvm (cournia2005 sec. 4.2): the unit disk's part on the hidden side of the cutting line u = c
// (u along the cutting plane's normal, c = -s / r: the plane's positive half-space u > c is the
// visible part), counter-clockwise: the arc from the chord's top end round through u = -1 to its
// bottom end, closed by the chord. Empty for c <= -1 (all visible), the whole disk for c >= 1.
Polygon diskHiddenRegion(double c) {
    if (c <= -1.0) return {};
    if (c >= 1.0) return lightPolygon(bp::BP_LIGHT_DISK);
    const double t0 = std::acos(c), t1 = 2.0 * M_PI - t0;
    const int steps = std::max(1, int(std::ceil((t1 - t0) / kArcStep)));
    Polygon p;
    for (int i = 0; i <= steps; ++i) {
        const double t = t0 + (t1 - t0) * double(i) / double(steps);
        push(p, glm::vec2(float(std::cos(t)), float(std::sin(t))));
    }
    return p;
}

Polygon quadRegion(int shape, glm::vec4 q) {
    if (shape == bp::BP_LIGHT_SQUARE) {
        const float x0 = std::max(q.x, -1.0f), y0 = std::max(q.y, -1.0f);
        const float x1 = std::max(std::min(q.z, 1.0f), x0), y1 = std::max(std::min(q.w, 1.0f), y0);
        return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    }
    const glm::vec2 corners[4] = {{q.x, q.y}, {q.z, q.y}, {q.z, q.w}, {q.x, q.w}};
    struct Piece {
        glm::vec2 in, out;
        bool leaves;  // the side goes on outside the disk after `out`
    };
    std::vector<Piece> pieces;
    for (int k = 0; k < 4; ++k) {
        const glm::vec2 a = corners[k], b = corners[(k + 1) % 4];
        const glm::vec2 range = bp::clipSegmentToDisk(a, b);
        if (!(range.x < range.y)) continue;  // misses (or touches) the disk
        pieces.push_back({a + (b - a) * range.x, a + (b - a) * range.y, range.y < 1.0f});
    }
    if (pieces.empty()) return q.x < 0.0f && 0.0f < q.z && q.y < 0.0f && 0.0f < q.w ? lightPolygon(shape) : Polygon{};
    Polygon p;
    for (size_t i = 0; i < pieces.size(); ++i) {
        push(p, pieces[i].in);
        push(p, pieces[i].out);
        if (!pieces[i].leaves) continue;
        // The arc from this piece's exit to the next piece's entry (which the next piece pushes).
        const glm::vec2 from = pieces[i].out, to = pieces[(i + 1) % pieces.size()].in;
        double angle = std::atan2(double(bp::cross2(from, to)), double(glm::dot(from, to)));
        if (angle < 0.0) angle = angle > -1e-6 ? 0.0 : angle + 2.0 * M_PI;  // counter-clockwise, [0, 2 pi)
        const double start = std::atan2(double(from.y), double(from.x));
        const int n = std::max(1, int(std::ceil(angle / kArcStep)));
        for (int k = 1; k < n; ++k)
            push(p, glm::vec2(float(std::cos(start + angle * k / n)), float(std::sin(start + angle * k / n))));
    }
    if (p.size() > 1 && p.front() == p.back()) p.pop_back();
    return p;
}

// The sum the technique integrates, point by point: the net number of cells covering each point of
// a grid x grid raster of [-1,1]^2 (texel centres), each cell counting its winding number (+1
// inside a counter-clockwise cell, -1 inside a clockwise one). Scanlines: a side crossing a row at
// x adds its direction (up +1, down -1) to every texel left of x.
std::vector<int> netCoverage(const std::vector<Polygon>& cells, int grid) {
    const double h = 2.0 / grid;
    std::vector<int> acc(size_t(grid) * (grid + 1), 0);  // per row, at column k: applies to columns < k
    for (const Polygon& p : cells)
        for (size_t i = 0; i < p.size(); ++i) {
            const glm::dvec2 a = p[i], b = p[(i + 1) % p.size()];
            if (a.y == b.y) continue;
            const int dir = b.y > a.y ? 1 : -1;
            const double ylo = std::min(a.y, b.y), yhi = std::max(a.y, b.y);
            const int j0 = std::max(0, int(std::ceil((ylo + 1.0) / h - 0.5))), j1 = std::min(grid - 1, int(std::ceil((yhi + 1.0) / h - 0.5)) - 1);
            for (int j = j0; j <= j1; ++j) {  // rows whose centre y is in [ylo, yhi)
                const double y = -1.0 + (j + 0.5) * h, x = a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y);
                const int k = std::clamp(int(std::ceil((x + 1.0) / h - 0.5)), 0, grid);  // columns < k have centre < x
                acc[size_t(j) * (grid + 1) + k] += dir;
            }
        }
    std::vector<int> count(size_t(grid) * grid, 0);
    for (int j = 0; j < grid; ++j) {
        int sum = 0;
        for (int i = grid - 1; i >= 0; --i) {
            sum += acc[size_t(j) * (grid + 1) + i + 1];
            count[size_t(j) * grid + i] = sum;
        }
    }
    return count;
}

void outline(std::vector<std::pair<glm::vec3, glm::vec3>>& lines, const Polygon& p, float z) {
    for (size_t i = 0; i < p.size(); ++i) lines.push_back({glm::vec3(p[i], z), glm::vec3(p[(i + 1) % p.size()], z)});
}

// The camera both panels share: light coordinates, the light and a margin in view.
void lightCamera(vtkRenderer* r, double aspect) {
    vtkCamera* camera = r->GetActiveCamera();
    camera->ParallelProjectionOn();
    camera->SetFocalPoint(0, 0, 0);
    camera->SetPosition(0, 0, 10);
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(1.22 * std::max(1.0, 1.0 / aspect));
    r->ResetCameraClippingRange();
}

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
    // pvm: the disk of radius r perpendicular to the cutting plane (sec. 4.2), drawn as the unit disk
    // (areas divided by r^2) with the plane's normal to the right.
    const bool pvmDisk = list == "disk";
    if (!pvmDisk && !rec.contains("light_geometry"))
        throw InputError("view backprojection: the " + l.desc->id + " record of pixel " + std::to_string(px.x) + "," +
                         std::to_string(px.y) + " has no light_geometry");
    const nlohmann::json geometry = pvmDisk ? nlohmann::json{{"shape", "disk"}, {"area", M_PI}} : rec.at("light_geometry");
    const bool disk = geometry.value("shape", "square") != "square";
    const int shape = disk ? bp::BP_LIGHT_DISK : bp::BP_LIGHT_SQUARE;
    const double lightArea = geometry.at("area").get<double>();
    const double initial = rec.value("initial_area", 0.0);
    const nlohmann::json items = pvmDisk ? nlohmann::json::array() : rec.value(list, nlohmann::json::array());
    const bool edges = list == "edges";
    // ssv's record (soft shadow volumes): the initial area is the hard count times the light, each
    // edge's area its weight (1, or 2 for an open mesh's interior silhouette) times its region.
    const bool volumes = rec.contains("hard_count");
    if (rec.contains("sub_lights") && rec["sub_lights"].size() > 1)
        throw InputError("view backprojection: " + where + ": the light is split into " +
                         std::to_string(rec["sub_lights"].size()) +
                         " quarters (split 2), each with its own light square; the view draws one light (split 1)");

    // The regions: one polygon cell each, the initial light first.
    struct Cell {
        Polygon polygon;
        double area;  // the record's
        int kind, item;
    };
    std::vector<Cell> cells;
    // The initial area as whole lights (ssv: one per hard shadow volume containing the point).
    const int initialLights = initial > 0.0 ? std::max(1, int(std::lround(initial / lightArea))) : 0;
    for (int k = 0; k < initialLights; ++k) cells.push_back({lightPolygon(shape), initial / initialLights, 0, -1});
    double sum = 0.0, added = 0.0, removed = 0.0;
    std::vector<std::pair<glm::vec3, glm::vec3>> edgeLines, clippedLines;
    // pvm: inside a volume one cell, the disk beyond the cutting line (area pi - 2a / r^2, eq. 4.1 at
    // -s gives a, the visible part being 2a); outside every volume the shadow-map test: the whole
    // disk (umbra) or nothing (lit).
    double pvmChord = NAN;
    const bool inVolume = pvmDisk && rec.value("in_volume", false);
    if (inVolume) {
        const nlohmann::json& d = rec.at("disk");
        const double r = d.at("radius").get<double>(), s = rec.at("light_distance").get<double>();
        pvmChord = r > 0.0 ? std::clamp(-s / r, -1.0, 1.0) : 0.0;
        const double hidden = M_PI - 2.0 * d.at("segment_area").get<double>() / (r * r);
        sum = added = hidden;
        cells.push_back({diskHiddenRegion(pvmChord), hidden, 3, 0});
        const float c = float(pvmChord), h = float(std::sqrt(std::max(0.0, 1.0 - pvmChord * pvmChord)));
        clippedLines.push_back({glm::vec3(c, -h, 0.04f), glm::vec3(c, h, 0.04f)});
    } else if (pvmDisk && rec.contains("shadow_test") && rec["shadow_test"].is_number() &&
               rec["shadow_test"].get<double>() < 0.5) {
        sum = added = M_PI;
        cells.push_back({lightPolygon(shape), M_PI, 3, 0});
    }
    for (size_t i = 0; i < items.size(); ++i) {
        const auto& it = items[i];
        const double area = it.at(edges ? "signed_area" : "area").get<double>();
        sum += area;
        (area >= 0.0 ? added : removed) += area;
        if (edges) {
            const glm::vec2 a = vec2(it.at("a")), b = vec2(it.at("b"));
            Polygon p = edgeRegion(shape, a, b);
            edgeLines.push_back({glm::vec3(a, 0.03f), glm::vec3(b, 0.03f)});
            if (p.size() >= 2) clippedLines.push_back({glm::vec3(p[0], 0.04f), glm::vec3(p[1], 0.04f)});
            const int weight = std::max(1, int(std::lround(it.value("weight", 1.0))));
            for (int k = 0; k < weight; ++k) cells.push_back({p, area / weight, 1, int(i)});
        } else {
            const auto& q = it.at("quad");
            cells.push_back({quadRegion(shape, glm::vec4(q[0].get<float>(), q[1].get<float>(), q[2].get<float>(), q[3].get<float>())),
                             area, 2, int(i)});
        }
    }

    // A region with fewer than three corners (an edge that only touches the light: a point or a
    // segment of its border) has no area; it is not drawn (its recorded area is 0 within rounding).
    size_t degenerate = 0;
    for (size_t c = 0; c < cells.size();)
        if (cells[c].polygon.size() < 3) {
            if (std::abs(cells[c].area) > 1e-5)
                throw InternalError("view backprojection: " + where + ": item " + std::to_string(cells[c].item) +
                                    " has area " + std::to_string(cells[c].area) + " but no region on the light");
            cells.erase(cells.begin() + std::ptrdiff_t(c));
            ++degenerate;
        } else {
            ++c;
        }
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> polys;
    vtkNew<vtkFloatArray> areas;
    areas->SetName("signed_area");
    vtkNew<vtkIntArray> kinds, itemIds;
    kinds->SetName("kind");
    itemIds->SetName("item");
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetName("colour");
    colours->SetNumberOfComponents(4);
    std::vector<std::pair<glm::vec3, glm::vec3>> redOutlines, blueOutlines;
    double maxAreaError = 0.0, drawnSum = 0.0;
    for (size_t c = 0; c < cells.size(); ++c) {
        const Cell& cell = cells[c];
        // Each cell a little above the previous one, so overlaps blend in a fixed order.
        const double z = 0.01 * double(c + 1) / double(cells.size() + 1);
        std::vector<vtkIdType> ids;
        for (const glm::vec2 v : cell.polygon) ids.push_back(points->InsertNextPoint(v.x, v.y, z));
        polys->InsertNextCell(vtkIdType(ids.size()), ids.data());
        areas->InsertNextValue(float(cell.area));
        kinds->InsertNextValue(cell.kind);
        itemIds->InsertNextValue(cell.item);
        const double drawn = polygonArea(cell.polygon);
        drawnSum += drawn;
        maxAreaError = std::max(maxAreaError, std::abs(drawn - cell.area));
        if (cell.kind == 2)
            colours->InsertNextTuple4(225, 130, 30, 95);  // samples: overlaps add up, darker = counted again
        else if (cell.kind == 3)
            colours->InsertNextTuple4(214, 60, 50, 140);  // pvm: the disk beyond the cutting line
        else if (cell.area >= 0.0)
            colours->InsertNextTuple4(214, 60, 50, 95);
        else
            colours->InsertNextTuple4(60, 110, 220, 95);
        outline(cell.kind == 1 && cell.area < 0.0 ? blueOutlines : redOutlines, cell.polygon, 0.02f);
    }
    poly->SetPoints(points);
    poly->SetPolys(polys);
    poly->GetCellData()->AddArray(areas);
    poly->GetCellData()->AddArray(kinds);
    poly->GetCellData()->AddArray(itemIds);
    poly->GetCellData()->SetScalars(colours);

    // The sum, point by point.
    constexpr int kGrid = 256;
    std::vector<Polygon> polygons;
    for (const Cell& cell : cells) polygons.push_back(cell.polygon);
    const std::vector<int> count = netCoverage(polygons, kGrid);
    auto coverage = vtkSmartPointer<vtkImageData>::New();
    coverage->SetDimensions(kGrid, kGrid, 1);
    coverage->SetSpacing(2.0 / kGrid, 2.0 / kGrid, 1.0);
    coverage->SetOrigin(-1.0 + 1.0 / kGrid, -1.0 + 1.0 / kGrid, -0.01);
    vtkNew<vtkFloatArray> counts;
    counts->SetName("count");
    counts->SetNumberOfTuples(vtkIdType(kGrid) * kGrid);
    double rasterArea = 0.0;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            const double x = -1.0 + (i + 0.5) * 2.0 / kGrid, y = -1.0 + (j + 0.5) * 2.0 / kGrid;
            const bool inside = !disk || x * x + y * y <= 1.0;
            const int n = count[size_t(j) * kGrid + i];
            if (inside) rasterArea += n * (4.0 / (double(kGrid) * kGrid));
            counts->SetValue(vtkIdType(j) * kGrid + i, inside ? float(n) : NAN);
        }
    coverage->GetPointData()->SetScalars(counts);

    const double occluded = initial + sum;
    // The part of the light behind the receiver's tangent plane lights nothing: the techniques scale
    // the unoccluded fraction by the fraction in front (the record's front_fraction).
    const double unoccluded = std::clamp(1.0 - occluded / lightArea, 0.0, 1.0);
    const double front = rec.value("front_fraction", 1.0);
    // pvm: v = 3k^2 - 2k^3 of the disk's visible fraction k (sec. 4.2, after Parker et al.).
    const double edgeShaped = inVolume ? unoccluded * unoccluded * (3.0 - 2.0 * unoccluded) : unoccluded;
    // split_sides (techniques/pvm/README.md, "Sides kept apart"): a value on the other side of 1/2
    // than the shadow-map test's is held at 1/2; the disk drawn is still the edge's answer.
    const bool held = inVolume && rec.contains("v_side") && rec["v_side"].is_number() &&
                      rec["v_side"].get<double>() != rec.value("v_volume", rec["v_side"].get<double>());
    const double shaped = held ? rec["v_side"].get<double>() : edgeShaped;
    const double visible = shaped * front;
    const double gpu = rec.value("visibility", std::nan(""));

    const std::string classification = rec.value("classification", "");
    std::string caption = "backprojection  " + where + (classification.empty() ? "" : ", " + classification) + "\n";
    if (pvmDisk && inVolume) {
        const nlohmann::json& vol = rec.at("volume");
        caption += vol.value("side", std::string("?")) + " volume of edge " + std::to_string(vol.value("edge", -1)) +
                   ": disk cut at s/r = " + formatNumber(-pvmChord, 4) + ", visible 2a = " +
                   formatNumber(2.0 * rec.at("disk").at("segment_area").get<double>(), 5) + " (eq. 4.1)\n";
    } else if (pvmDisk && front <= 0.0) {
        caption += "the light is behind the receiver's tangent plane: no volume or shadow test is read, v = 0\n";
    } else if (pvmDisk) {
        caption += std::string("outside every penumbra volume: the shadow-map test, ") +
                   (sum > 0.0 ? "umbra (the whole disk hidden)" : "lit (the whole disk visible)") + "\n";
    } else if (volumes)
        caption += std::to_string(items.size()) + " silhouette edges whose wedge holds the point, the light beyond each: +" +
                   formatNumber(added) + " (red, cw) " + formatNumber(removed) + " (blue, ccw)\ninitial " +
                   formatNumber(initial) + " (" + std::to_string(initialLights) +
                   " hard shadow volume(s) hold the point: a whole light each, red); right: their net count\n";
    else if (edges)
        caption += std::to_string(items.size()) + " contour edges, the light beyond each: +" + formatNumber(added) +
                   " (red, cw) " + formatNumber(removed) + " (blue, ccw)\ninitial " + formatNumber(initial) +
                   (initial > 0.0 ? " (centre occluded: the whole light, red)" : " (centre visible)") +
                   "; right: their net count\n";
    else
        caption += std::to_string(items.size()) + " occluding samples, quads clipped to the light: sum " + formatNumber(sum) +
                   ", initial " + formatNumber(initial) + "\noverlaps count twice; right: the net count of quads\n";
    if (inVolume)
        caption += "k = 2a/(pi r^2) = " + formatNumber(unoccluded, 5) + " (eq. 4.2), v = 3k^2 - 2k^3 = " +
                   formatNumber(edgeShaped, 5) +
                   (held ? std::string(", held at 1/2: the shadow-map test puts the centre ") +
                               (rec.value("maps", std::string()) == "outer" ? "in view" : "out of view")
                         : std::string()) +
                   (front < 1.0 ? " x " + formatNumber(front, 4) + " (front)" : "") + " = " +
                   formatNumber(visible, 6) + " (image: " + formatNumber(gpu, 6) + ")";
    else
        caption += "occluded " + formatNumber(occluded, 5) + " of " + formatNumber(lightArea, 5) + ": visible fraction " +
                   (front < 1.0 ? formatNumber(unoccluded, 4) + " x " + formatNumber(front, 4) + " (front) = " : "") +
                   formatNumber(visible, 6) + " (image: " + formatNumber(gpu, 6) + ")";
    result.caption = caption;
    result.data = {{"pixel", {px.x, px.y}},
                   {"list", list},
                   {"count", items.size()},
                   {"light_shape", disk ? "disk" : "square"},
                   {"light_area", lightArea},
                   {"initial_area", initial},
                   {"sum_areas", sum},
                   {"occluded_area", occluded},
                   {"unoccluded_fraction", unoccluded},  // clamp(1 - occluded / light area, 0, 1)
                   {"front_fraction", front},            // of the light, in front of the receiver's tangent plane
                   {"visible_fraction", visible},        // their product: the technique's visibility
                   {"visibility", gpu},
                   {"cells", poly->GetNumberOfCells()},
                   {"degenerate_regions", degenerate},  // items touching the light in a point or a segment: not drawn
                   {"drawn_area", drawnSum},               // the cells' shoelace areas, summed
                   {"max_cell_area_error", maxAreaError},  // |shoelace - record| over the cells
                   {"coverage_area", rasterArea}};         // the right panel's net count, integrated (256^2 texels)

    const double strip = addCaptionStrip(ctx.out, caption, true);
    // The two panels' titles in a strip of their own above the light squares (wrapped to a half
    // width, measured), so that at any size they never cover the drawing.
    const std::string leftTitle = pvmDisk ? "the disk, its cutting line, the hidden part red" : edges ? (initial > 0.0 ? "each edge's region: red adds, blue removes; the whole light starts red"
                                                         : "each edge's region of the light: red adds, blue removes")
                                        : "each sample's quad on the light: overlaps add up";
    const std::string rightTitle = pvmDisk ? "hidden dark, visible pale"
                                           : "their sum: occluded light dark (orange: twice, blue: < 0)";
    double titleTop = 1.0;
    std::string leftWrapped, rightWrapped;
    {
        auto probe = titleActor("", ctx.out.height());
        const int margin = std::max(4, textPx(ctx.out.height()) / 3);
        const int width = ctx.out.width() / 2 - 2 * margin;
        leftWrapped = wrapText(probe->GetTextProperty(), leftTitle, width);
        rightWrapped = wrapText(probe->GetTextProperty(), rightTitle, width);
        int w = 0, hl = 0, hr = 0;
        textExtent(probe->GetTextProperty(), leftWrapped, w, hl);
        textExtent(probe->GetTextProperty(), rightWrapped, w, hr);
        titleTop = 1.0 - std::min(0.4, double(std::max(hl, hr) + 2 * margin) / ctx.out.height());
        for (int side = 0; side < 2; ++side) {
            vtkRenderer* t = ctx.out.addRenderer();
            t->SetViewport(0.5 * side, titleTop, 0.5 * (side + 1), 1.0);
            t->SetBackground(0.12, 0.12, 0.14);
            auto title = titleActor(side == 0 ? leftWrapped : rightWrapped, ctx.out.height());
            title->GetPositionCoordinate()->SetCoordinateSystemToViewport();
            title->SetPosition(margin, int(std::lround((1.0 - titleTop) * ctx.out.height())) - margin);
            t->AddActor2D(title);
        }
    }
    const double panelAspect = 0.5 * ctx.out.width() / ((titleTop - strip) * ctx.out.height());
    auto lightBorder = [&] {
        std::vector<std::pair<glm::vec3, glm::vec3>> border;
        outline(border, lightPolygon(shape), 0.05f);
        return lineActor(border, glm::vec3(0.95f), 2.0f);
    };
    auto centreMark = [] {
        return lineActor({{glm::vec3(-0.06f, 0, 0.06f), glm::vec3(0.06f, 0, 0.06f)},
                          {glm::vec3(0, -0.06f, 0.06f), glm::vec3(0, 0.06f, 0.06f)}},
                         glm::vec3(0.9f, 0.1f, 0.1f), 2.0f);
    };

    // Left: the terms.
    vtkRenderer* r = ctx.out.addRenderer();
    r->SetViewport(0.0, strip, 0.5, titleTop);
    r->SetBackground(0.12, 0.12, 0.14);
    {
        vtkNew<FunctionSource> src;  // the light, filled pale
        src->SetGenerator([shape](vtkPolyData* out) {
            vtkNew<vtkPoints> p;
            vtkNew<vtkCellArray> c;
            std::vector<vtkIdType> ids;
            for (const glm::vec2 v : lightPolygon(shape)) ids.push_back(p->InsertNextPoint(v.x, v.y, -0.01));
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
        // offscreen frame cannot give it): each cell lies a little above the previous one, so
        // overlaps blend and show.
        a->ForceOpaqueOn();
        r->AddActor(a);
    }
    if (!redOutlines.empty()) r->AddActor(lineActor(redOutlines, edges ? glm::vec3(0.6f, 0.12f, 0.1f) : glm::vec3(0.55f, 0.3f, 0.05f), 1.0f));
    if (!blueOutlines.empty()) r->AddActor(lineActor(blueOutlines, glm::vec3(0.12f, 0.25f, 0.6f), 1.0f));
    if (!edgeLines.empty()) r->AddActor(lineActor(edgeLines, glm::vec3(0.45f), 1.0f));        // as recorded
    if (!clippedLines.empty()) r->AddActor(lineActor(clippedLines, glm::vec3(0.02f), 2.5f));  // the part on the light
    r->AddActor(lightBorder());
    r->AddActor(centreMark());
    lightCamera(r, panelAspect);

    // Right: the sum.
    vtkRenderer* s = ctx.out.addRenderer();
    s->SetViewport(0.5, strip, 1.0, titleTop);
    s->SetBackground(0.12, 0.12, 0.14);
    {
        vtkNew<vtkLookupTable> lut;  // one colour per count: -1 and below, 0, 1, 2 and above
        lut->SetNumberOfTableValues(4);
        lut->SetTableRange(-1.5, 2.5);
        lut->SetTableValue(0, 0.24, 0.43, 0.86);  // uncovered more than once: negative
        lut->SetTableValue(1, 0.96, 0.93, 0.78);  // visible
        lut->SetTableValue(2, 0.22, 0.2, 0.2);    // occluded
        lut->SetTableValue(3, 0.85, 0.42, 0.1);   // occluded twice or more
        lut->SetNanColor(0.12, 0.12, 0.14, 1.0);
        lut->Build();
        vtkNew<vtkImageMapToColors> colourise;
        colourise->SetInputData(coverage);
        colourise->SetLookupTable(lut);
        colourise->SetOutputFormatToRGB();
        vtkNew<vtkImageActor> image;
        image->GetMapper()->SetInputConnection(colourise->GetOutputPort());
        image->InterpolateOff();
        s->AddActor(image);
    }
    s->AddActor(lightBorder());
    s->AddActor(centreMark());
    lightCamera(s, panelAspect);

    if (!ctx.request.exportPath.empty()) writePolyData(poly, ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& backprojectionView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "backprojection";
        // Two light squares side by side, over a caption of four lines.
        d.aspect = [](const Renderer&, const ViewRequest&, float) { return 2.0f * (1.0f - 1.6f * kCaptionShare); };
        d.info.doc = "the picked pixel's light with the regions the technique adds up: each contour edge's part of "
                     "the light beyond it in its wedge (red adds, blue removes) or each sample's quad clipped to the "
                     "light, and beside them their net count over the light; the visible fraction";
        d.info.appliesTo = "techniques whose per-pixel record lists back-projected 'samples' or 'edges' "
                           "(ssm-gbp06, ssm-contour, ssv with split 1), and pvm's disk and cutting line; needs --pixel";
        d.info.exportExtension = ".vtp";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
