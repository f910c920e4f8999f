// `hsm`: the hierarchical shadow map (guennebaud2007 section 3) laid flat, one tile per level (HSM
// levels 1, 2, ... up to the 1x1 top; level 0 is the shadow map itself): the min of each level on
// one row and its max on the row below, levels left to right, in blocks of at most six columns (a
// 1024^2 map has 10 levels: two blocks of five). A parallel camera looks straight at them: a
// texel of level k is a square of 2^k x 2^k level-0 texels, every tile shows the same square of
// the map (cropped to the casters and the kernel, since casters often fill a corner of it) and is
// labelled "level k, NxN texels" (N = 2^k, on two lines) above its min. With a picked pixel, the texels each kernel
// refinement step read (the per-pixel record's kernel.steps[{level, texels [x0,y0,x1,y1] from the
// bottom}]) are outlined on their level's two tiles, numbered in order (a step at level 0, the
// shadow map, is drawn on level 1's tiles and says so), and the converged kernel
// (kernel.texel_range, level-0 texels) is outlined in cyan on every tile. Reads the `hsm` pyramid
// internal and the per-pixel record only.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkCoordinate.h>
#include <vtkDataSetMapper.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkProperty.h>
#include <vtkRectilinearGrid.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "error.h"
#include "shared/shared.h"
#include "view_common.h"

namespace shadowlab {

namespace {

bool hasHsm(const LightState& l) {
    const InternalDesc* i = l.desc->findInternal("hsm");
    return i && i->kind == InternalDesc::Kind::Pyramid && i->channels.size() >= 2;
}

std::string refusal(const LightState& l, const ViewRequest& request) {
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (!hasHsm(l)) return "technique " + l.desc->id + " builds no min/max pyramid (a pyramid internal 'hsm' with min and max)";
    return "";
}

// ---- the layout, in units of the tile side (the crop's side, S level-0 texels) --------------------
constexpr double kGap = 0.06;       // between tiles
constexpr double kLabel = 0.40;     // the level's label band above its min tile (two lines)
constexpr double kRowLabel = 0.36;  // the "min" / "max" column at the left
constexpr double kBlockGap = 0.10;  // between blocks
constexpr double kTitle = 0.04;     // a margin on top (the title has its own strip above)
constexpr double kMapShare = 0.88;  // of the picture's width; the colour bar has the rest
constexpr double kTitleShare = 0.1; // of the picture's height, for the aspect: the title's two lines
const glm::vec3 kKernelRgb(0.2f, 1.0f, 1.0f);  // cyan: in no step colour, not in the depth map

struct Grid {
    int levels = 1, blocks = 1, columns = 1;
    double width = 1.0, height = 1.0;  // of the whole layout, in tile sides
    // The lower-left corners of level index i's (0 = HSM level 1) min and max tiles and the top of
    // its label band, in tile sides (y up, the layout's top at 0).
    glm::dvec2 minTile(int i) const { return {kRowLabel + (i % columns) * (1.0 + kGap), blockTop(i / columns) - kLabel - 1.0}; }
    glm::dvec2 maxTile(int i) const { return minTile(i) - glm::dvec2(0.0, 1.0 + kGap); }
    double blockTop(int b) const { return -(kTitle + b * (kLabel + 2.0 + kGap + kBlockGap)); }
};

Grid gridOf(int levels) {
    Grid g;
    g.levels = std::max(1, levels);
    g.blocks = (g.levels + 5) / 6;
    g.columns = (g.levels + g.blocks - 1) / g.blocks;
    g.width = kRowLabel + g.columns * (1.0 + kGap);
    g.height = kTitle + g.blocks * (kLabel + 2.0 + kGap) + (g.blocks - 1) * kBlockGap;
    return g;
}

// HSM levels above the shadow map for a map of smSize texels: 1, 2, ... up to the first of one
// texel (hsmLevelSize's chain, as techniques/hsm builds it).
int hsmLevelCount(int smSize) {
    int n = 0;
    while (shared::hsmLevelSize(n, smSize) > 1) ++n;
    return n;
}

// Cells [c.x, c.z] x [c.y, c.w] (inclusive, from the bottom) of an HSM level whose texels cover
// `scale` level-0 texels, as a flat grid: level-0 texel (u, v) of the crop lands at origin + (u, v)
// - crop's lower-left corner; the outer cells are cut at the crop (a coarse level's one cell may
// span the whole map).
vtkSmartPointer<vtkActor> levelActor(const Image& level, int channel, vtkLookupTable* lut, double scale,
                                     glm::dvec2 origin, glm::ivec4 c, const glm::dvec4& crop) {
    const int w = c.z - c.x + 1, h = c.w - c.y + 1;
    vtkNew<vtkRectilinearGrid> grid;
    grid->SetDimensions(w + 1, h + 1, 1);
    vtkNew<vtkDoubleArray> xs, ys, zs;
    for (int i = 0; i <= w; ++i) xs->InsertNextValue(origin.x + std::clamp((c.x + i) * scale, crop.x, crop.z) - crop.x);
    for (int j = 0; j <= h; ++j) ys->InsertNextValue(origin.y + std::clamp((c.y + j) * scale, crop.y, crop.w) - crop.y);
    zs->InsertNextValue(0.0);
    grid->SetXCoordinates(xs);
    grid->SetYCoordinates(ys);
    grid->SetZCoordinates(zs);
    vtkNew<vtkFloatArray> values;
    values->SetName("depth");
    values->SetNumberOfTuples(vtkIdType(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float v = level.at(c.x + x, level.height - 1 - (c.y + y), channel);
            values->SetValue(vtkIdType(y) * w + x, std::isfinite(v) ? v : NAN);
        }
    grid->GetCellData()->SetScalars(values);
    vtkNew<vtkDataSetMapper> mapper;
    mapper->SetInputData(grid);
    mapper->SetLookupTable(lut);
    mapper->SetScalarModeToUseCellData();
    mapper->UseLookupTableScalarRangeOn();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->LightingOff();
    return actor;
}

// The part of the map worth showing, in level-0 texels [x0, x1) x [y0, y1) from the bottom: where
// HSM level 1 holds a caster (finite min depth), grown to hold `marks` (the kernel's steps and
// range), padded by an eighth of its size (at least 4 texels) and made square within the map; the
// whole map when nothing casts. Every level is cut at it (levelActor), so the tiles line up.
glm::dvec4 cropOfInterest(const Image& level1, const std::vector<glm::dvec4>& marks, double w0, double h0) {
    glm::dvec4 box(INFINITY, INFINITY, -INFINITY, -INFINITY);
    for (int y = 0; y < level1.height; ++y)
        for (int x = 0; x < level1.width; ++x) {
            if (!std::isfinite(level1.at(x, level1.height - 1 - y, 0))) continue;
            box = glm::dvec4(std::min(box.x, 2.0 * x), std::min(box.y, 2.0 * y), std::max(box.z, 2.0 * x + 2.0),
                             std::max(box.w, 2.0 * y + 2.0));
        }
    for (const glm::dvec4& m : marks)
        box = glm::dvec4(std::min(box.x, m.x), std::min(box.y, m.y), std::max(box.z, m.z), std::max(box.w, m.w));
    if (!(box.x < box.z)) return glm::dvec4(0.0, 0.0, w0, h0);
    const double pad = std::max(4.0, 0.125 * std::max(box.z - box.x, box.w - box.y));
    box = glm::dvec4(std::max(0.0, box.x - pad), std::max(0.0, box.y - pad), std::min(w0, box.z + pad), std::min(h0, box.w + pad));
    // Square it (levels are square), within the map.
    const double side = std::min(std::max(box.z - box.x, box.w - box.y), std::min(w0, h0));
    auto fit = [side](double lo, double hi, double extent) {
        double centre = 0.5 * (lo + hi), a = std::clamp(centre - 0.5 * side, 0.0, std::max(0.0, extent - side));
        return glm::dvec2(a, a + side);
    };
    const glm::dvec2 x = fit(box.x, box.z, w0), y = fit(box.y, box.w, h0);
    return glm::dvec4(x.x, y.x, x.y, y.y);
}

// The cells of a level (texels of `scale` level-0 texels, size w x h) that overlap the crop.
glm::ivec4 levelCells(const glm::dvec4& crop, double scale, int w, int h) {
    return glm::ivec4(std::clamp(int(std::floor(crop.x / scale)), 0, w - 1), std::clamp(int(std::floor(crop.y / scale)), 0, h - 1),
                      std::clamp(int(std::ceil(crop.z / scale)) - 1, 0, w - 1), std::clamp(int(std::ceil(crop.w / scale)) - 1, 0, h - 1));
}

using Lines = std::vector<std::pair<glm::vec3, glm::vec3>>;

void rect(Lines& lines, double x0, double y0, double x1, double y1, double z) {
    glm::vec3 a(x0, y0, z), b(x1, y0, z), c(x1, y1, z), d(x0, y1, z);
    lines.push_back({a, b});
    lines.push_back({b, c});
    lines.push_back({c, d});
    lines.push_back({d, a});
}

// Text anchored at a world point of the layout (the levels' labels, the steps' numbers).
vtkSmartPointer<vtkTextActor> worldText(const std::string& text, glm::dvec2 at, int font, glm::vec3 rgb, bool right = false,
                                        bool top = true) {
    auto actor = vtkSmartPointer<vtkTextActor>::New();
    actor->SetInput(text.c_str());
    vtkTextProperty* p = actor->GetTextProperty();
    p->SetFontSize(font);
    p->SetFontFamilyToArial();
    p->SetColor(rgb.r, rgb.g, rgb.b);
    p->BoldOn();
    if (right) p->SetJustificationToRight();
    if (top) p->SetVerticalJustificationToTop();
    actor->GetPositionCoordinate()->SetCoordinateSystemToWorld();
    actor->GetPositionCoordinate()->SetValue(at.x, at.y, 0.5);
    return actor;
}

// "level 2, 4x4 texels": a texel of level k covers 2^k x 2^k level-0 texels.
std::string levelLabel(int level) {
    const std::string n = std::to_string(1 << level);
    return "level " + std::to_string(level) + ", " + n + "x" + n + " texels";
}

void build(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    const CollectedInternal* hsm = ctx.internal("hsm");
    if (!hsm || hsm->levels.empty())
        throw InputError("view hsm: technique " + l.desc->id + " wrote no 'hsm' this frame");
    const std::vector<Image>& levels = hsm->levels;  // HSM levels 1, 2, ...
    const double w0 = 2.0 * levels[0].width, h0 = 2.0 * levels[0].height;  // level-0 (shadow map) texels
    float lo = INFINITY, hi = -INFINITY;
    for (const Image& level : levels)
        for (int c = 0; c < 2; ++c) {
            auto [a, b] = finiteRange(level, c);
            lo = std::min(lo, a);
            hi = std::max(hi, b);
        }
    auto lut = sequentialLut(lo, hi);

    const nlohmann::json rec = ctx.pixelRecord();
    const bool hasKernel = rec.is_object() && rec.contains("kernel") && rec["kernel"].is_object();
    const nlohmann::json steps = hasKernel ? rec["kernel"].value("steps", nlohmann::json::array()) : nlohmann::json::array();
    // Level-0 rectangles of the kernel's steps and converged range: they must stay in the crop.
    auto stepRect = [](const nlohmann::json& st) {
        const double scale = std::ldexp(1.0, st.at("level").get<int>());
        const auto& t = st.at("texels");
        return glm::dvec4(t[0].get<double>() * scale, t[1].get<double>() * scale, (t[2].get<double>() + 1) * scale,
                          (t[3].get<double>() + 1) * scale);
    };
    std::vector<glm::dvec4> marks;
    for (const auto& st : steps) marks.push_back(stepRect(st));
    std::optional<glm::dvec4> kernel;
    if (hasKernel && rec["kernel"].contains("texel_range") && rec["kernel"]["texel_range"].is_array()) {
        const auto& t = rec["kernel"]["texel_range"];
        kernel = glm::dvec4(t[0].get<double>(), t[1].get<double>(), t[2].get<double>() + 1, t[3].get<double>() + 1);
        marks.push_back(*kernel);
    }
    // Casters often fill a corner of the map: each level is cropped to the same square around them.
    const glm::dvec4 crop = cropOfInterest(levels[0], marks, w0, h0);
    const double side = std::max(crop.z - crop.x, crop.w - crop.y);  // a tile's side, level-0 texels
    const Grid grid = gridOf(int(levels.size()));

    std::string caption = "hsm  " + l.desc->id + ", L" + std::to_string(ctx.request.light) + ": " +
                          std::to_string(levels.size()) + " levels (" + std::to_string(levels[0].width) + "x" +
                          std::to_string(levels[0].height) + " .. 1x1) over a " + formatNumber(w0) + "x" +
                          formatNumber(h0) + " shadow map, min above max; a label 'Lk N' is level k, texels of N x N";
    if (crop.z - crop.x < w0 || crop.w - crop.y < h0)
        caption += "\nevery level cut at texels " + formatNumber(crop.x) + ".." + formatNumber(crop.z) + " x " + formatNumber(crop.y) + ".." +
                   formatNumber(crop.w) + " shown (the casters)";
    const std::string title = "HSM: each level's min (upper row), max (lower)\n"
                              "refinement steps numbered; converged kernel (cyan)";
    nlohmann::json data{{"levels", levels.size()},
                        {"range", {lo, hi}},
                        {"crop", {crop.x, crop.y, crop.z, crop.w}},
                        {"layout", {{"blocks", grid.blocks}, {"columns", grid.columns}, {"rows", "min above max"}}},
                        {"title", title},
                        {"kernel_colour", {kKernelRgb.r, kKernelRgb.g, kKernelRgb.b}}};
    nlohmann::json drawn = nlohmann::json::array();
    for (size_t k = 0; k < levels.size(); ++k)
        drawn.push_back({{"level", k + 1}, {"texel_size", 1 << (k + 1)}, {"label", levelLabel(int(k) + 1)}});
    data["levels_drawn"] = drawn;

    // World coordinates: level-0 texels, the layout's top-left corner at the origin.
    auto at = [side](glm::dvec2 tile) { return tile * side; };
    auto onTile = [&](glm::dvec2 tile, double u, double v) { return at(tile) + glm::dvec2(u - crop.x, v - crop.y); };
    static const glm::vec3 stepColours[] = {{1.0f, 0.2f, 0.2f}, {1.0f, 0.6f, 0.1f}, {1.0f, 1.0f, 1.0f},
                                            {0.9f, 0.3f, 0.9f}, {1.0f, 0.95f, 0.3f}, {1.0f, 0.6f, 0.7f}};
    // Steps that read the same texels of the same level share an outline and a label ("2, 3").
    struct StepGroup {
        int level;
        glm::dvec4 rect;
        std::string numbers;
        glm::vec3 rgb;
    };
    std::vector<StepGroup> groups;
    nlohmann::json stepData = nlohmann::json::array();
    if (hasKernel) {
        const auto& k = rec["kernel"];
        caption += "\npixel " + std::to_string(ctx.request.pixel->x) + "," + std::to_string(ctx.request.pixel->y) +
                   " (" + rec.value("classification", "") + "): global min " + formatNumber(k.value("global_min", 0.0)) +
                   ", " + std::to_string(k.value("iterations", 0)) + " steps:";
        for (size_t i = 0; i < steps.size(); ++i) {
            const auto& s = steps[i];
            const int level = s.at("level").get<int>();
            const glm::dvec4 r = stepRect(s);
            auto same = std::find_if(groups.begin(), groups.end(), [&](const StepGroup& g) { return g.level == level && g.rect == r; });
            if (same == groups.end())
                groups.push_back({level, r, std::to_string(i + 1), stepColours[groups.size() % 6]});
            else
                same->numbers += ", " + std::to_string(i + 1);
            caption += " " + std::to_string(i + 1) + ": L" + std::to_string(level) + " -> w_k " +
                       formatNumber(s.value("refined_texels", 0.0));
            stepData.push_back(s);
        }
        caption += "; kernel " + formatNumber(k.value("texels", 0.0)) + " texels (cyan)";
        data["steps"] = stepData;
        data["kernel_texels"] = k.value("texels", 0.0);
        if (kernel) data["kernel_range"] = k["texel_range"];
    }
    result.caption = caption;

    const double strip = addCaptionStrip(ctx.out, caption);
    // The title's strip on top, two lines of titleActor's font (a 30th of the frame's height).
    const double titleTop = 1.0 - std::min(0.3, (2.0 * 1.3 * textPx(ctx.out.height()) + 10.0) / ctx.out.height());
    vtkRenderer* titleStrip = ctx.out.addRenderer();
    titleStrip->SetViewport(0.0, titleTop, 1.0, 1.0);
    titleStrip->SetBackground(0.12, 0.12, 0.14);
    titleStrip->AddActor2D(titleActor(title, ctx.out.height()));
    vtkRenderer* r = ctx.out.addRenderer();
    // The bar's panel: the rest of the width, at least what its labels need (style.h).
    const double mapShare = std::min(kMapShare, 1.0 - double(colourBarWidthPx(lut, "depth", ctx.out.height())) / ctx.out.width());
    r->SetViewport(0.0, strip, mapShare, titleTop);
    r->SetBackground(0.12, 0.12, 0.14);
    const double viewportW = mapShare * ctx.out.width(), viewportH = (titleTop - strip) * ctx.out.height();
    const double worldW = grid.width * side, worldH = grid.height * side;
    const double scale = 0.5 * std::max(worldH, worldW * viewportH / viewportW) * 1.01;  // parallel scale: half the height shown
    const double pxPerTexel = viewportH / (2.0 * scale);
    const double tilePx = side * pxPerTexel;
    const int font = textPx(ctx.out.height());  // the text standard (style.h): never smaller
    data["tile_px"] = tilePx;

    Lines texelLines;
    for (size_t k = 0; k < levels.size(); ++k) {
        const int level = int(k) + 1;
        const double texel = std::ldexp(1.0, level);
        const glm::ivec4 cells = levelCells(crop, texel, levels[k].width, levels[k].height);
        const glm::dvec2 minTile = grid.minTile(int(k)), maxTile = grid.maxTile(int(k));
        r->AddActor(levelActor(levels[k], 0, lut, texel, at(minTile), cells, crop));
        r->AddActor(levelActor(levels[k], 1, lut, texel, at(maxTile), cells, crop));
        // The level's texels, when they are big enough on screen to count.
        if (texel * pxPerTexel >= 6.0)
            for (const glm::dvec2 tile : {minTile, maxTile}) {
                for (int i = cells.x + 1; i <= cells.z; ++i) {
                    const double u = i * texel;
                    if (u <= crop.x || u >= crop.z) continue;
                    texelLines.push_back({glm::vec3(onTile(tile, u, crop.y), 0.1), glm::vec3(onTile(tile, u, crop.w), 0.1)});
                }
                for (int j = cells.y + 1; j <= cells.w; ++j) {
                    const double v = j * texel;
                    if (v <= crop.y || v >= crop.w) continue;
                    texelLines.push_back({glm::vec3(onTile(tile, crop.x, v), 0.1), glm::vec3(onTile(tile, crop.z, v), 0.1)});
                }
            }
        // The label band above the min tile holds, at the standard's font (measured with VTK's text
        // renderer), the first that fits: "level k," over "NxN texels"; "Lk NxN"; "Lk" over "NxN";
        // "Lk" over "N" (the caption then says what "Lk N" means).
        const std::string n = std::to_string(1 << level), lk = "L" + std::to_string(level);
        const int levelFont = font;
        std::string text;
        {
            auto probe = worldText("", glm::dvec2(0.0), levelFont, glm::vec3(1.0f));
            const double roomW = tilePx * (1.0 + kGap) - 4.0, roomH = tilePx * kLabel - 1.0;
            for (const std::string& candidate : {"level " + std::to_string(level) + ",\n" + n + "x" + n + " texels",
                                                 lk + " " + n + "x" + n, lk + "\n" + n + "x" + n, lk + "\n" + n}) {
                int tw = 0, th = 0;
                textExtent(probe->GetTextProperty(), candidate, tw, th);
                text = candidate;
                if (tw <= roomW && th <= roomH) break;
            }
        }
        data["levels_drawn"][k]["text"] = text;

        r->AddActor2D(worldText(text,
                                at(glm::dvec2(minTile.x, grid.blockTop(int(k) / grid.columns))) + glm::dvec2(0.01 * side, -0.03 * side),
                                levelFont, glm::vec3(0.95f)));
    }
    for (int b = 0; b < grid.blocks; ++b) {
        const glm::dvec2 minTile = grid.minTile(b * grid.columns), maxTile = grid.maxTile(b * grid.columns);
        r->AddActor2D(worldText("min", at(glm::dvec2(0.03, minTile.y + 0.6)), font, glm::vec3(0.85f), false, true));
        r->AddActor2D(worldText("max", at(glm::dvec2(0.03, maxTile.y + 0.6)), font, glm::vec3(0.85f), false, true));
    }
    if (!texelLines.empty()) r->AddActor(lineActor(texelLines, glm::vec3(0.08f), 1.0f));

    // The steps, numbered, on their level's tiles (level 0, the shadow map, on level 1's).
    nlohmann::json labels = nlohmann::json::array();
    for (const StepGroup& g : groups) {
        const int index = std::max(g.level, 1) - 1;
        const std::string text = g.numbers + (g.level == 0 ? " (level 0)" : "");
        Lines lines;
        for (const glm::dvec2 tile : {grid.minTile(index), grid.maxTile(index)}) {
            const glm::dvec2 p0 = onTile(tile, g.rect.x, g.rect.y), p1 = onTile(tile, g.rect.z, g.rect.w);
            rect(lines, p0.x, p0.y, p1.x, p1.y, 0.2);
            // Beside the outline: right of it, or left when it reaches the tile's right side.
            const double tileRight = at(tile).x + side, tileBottom = at(tile).y;
            const bool left = p1.x + 0.25 * side > tileRight;
            const glm::dvec2 anchor(left ? p0.x - 0.02 * side : p1.x + 0.02 * side,
                                    std::max(p1.y, tileBottom + font / pxPerTexel));
            auto number = worldText(text, anchor, font, g.rgb, left);
            number->GetTextProperty()->SetBackgroundColor(0.05, 0.05, 0.06);  // readable over any depth
            number->GetTextProperty()->SetBackgroundOpacity(0.8);
            r->AddActor2D(number);
        }
        r->AddActor(lineActor(lines, g.rgb, 3.0f));
        labels.push_back({{"text", text}, {"level", g.level}, {"drawn_on_level", index + 1}});
    }
    data["step_labels"] = labels;
    // The converged kernel, on every tile, on top.
    if (kernel) {
        Lines lines;
        for (size_t k = 0; k < levels.size(); ++k)
            for (const glm::dvec2 tile : {grid.minTile(int(k)), grid.maxTile(int(k))}) {
                const glm::dvec2 p0 = onTile(tile, kernel->x, kernel->y), p1 = onTile(tile, kernel->z, kernel->w);
                rect(lines, p0.x, p0.y, p1.x, p1.y, 0.3);
            }
        r->AddActor(lineActor(lines, kKernelRgb, 2.0f));
    }
    result.data = data;

    vtkCamera* camera = r->GetActiveCamera();
    camera->ParallelProjectionOn();
    const double cx = 0.5 * worldW, cy = -0.5 * worldH;
    camera->SetFocalPoint(cx, cy, 0.0);
    camera->SetPosition(cx, cy, 10.0 * side);
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(scale / ctx.request.zoom);
    r->ResetCameraClippingRange();
    vtkRenderer* sideBar = ctx.out.addRenderer();
    sideBar->SetViewport(mapShare, strip, 1.0, titleTop);
    sideBar->SetBackground(0.12, 0.12, 0.14);
    addColourBar(sideBar, lut, "depth", ctx.out.height());
    // Export: HSM level 1 (min, max) as image data.
    if (!ctx.request.exportPath.empty())
        writeImageData(toImageData(levels[0], {"min", "max"}), ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& hsmView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "hsm";
        // The layout of the light's map size (its levels in blocks of two rows) in the left 88%,
        // between the title and the caption.
        d.aspect = [](const Renderer& renderer, const ViewRequest& request, float) {
            const LightState& l = *renderer.lights().at(size_t(request.light));
            const auto& values = l.params.values();
            const auto size = values.find("sm_size");
            const Grid g = gridOf(hsmLevelCount(size == values.end() ? 1024 : int(size->second)));
            return float(g.width / g.height * (1.0 - kCaptionShare - kTitleShare) / kMapShare);
        };
        d.info.doc = "the min/max depth pyramid (HSM) laid flat, one labelled tile per level (min above max), with the "
                     "texels the picked pixel's kernel refinement read at each step, numbered, and the converged "
                     "kernel (cyan)";
        d.info.appliesTo = "techniques with a pyramid internal 'hsm' (min, max): ssm-gbp06, ssm-contour";
        d.info.exportExtension = ".vti";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
