// `hsm`: the hierarchical shadow map (guennebaud2007 section 3) as two stacks of levels, min (left)
// and max (right), HSM level 1 at the bottom (level 0 is the shadow map itself), each level scaled
// to the same footprint; with a picked pixel, the texels the kernel refinement read at each step
// (the per-pixel record's kernel.steps[{level, texels [x0,y0,x1,y1] from the bottom}]) outlined on
// their level, one colour per step, and the converged kernel (kernel.texel_range, level-0 texels)
// outlined under the stack. Every level is cropped to the same square around the casters (and the
// kernel), since casters often fill a corner of the map. Reads the `hsm` pyramid internal and the
// per-pixel record only.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDataSetMapper.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkProperty.h>
#include <vtkRectilinearGrid.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>

#include <algorithm>
#include <cmath>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {

bool hasHsm(const LightState& l) {
    const InternalDesc* i = l.desc->findInternal("hsm");
    return i && i->kind == InternalDesc::Kind::Pyramid && i->channels.size() >= 2;
}

std::string refusal(const Renderer& renderer, const ViewRequest& request) {
    const LightState& l = *renderer.lights().at(size_t(request.light));
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (!hasHsm(l)) return "technique " + l.desc->id + " builds no min/max pyramid (a pyramid internal 'hsm' with min and max)";
    return "";
}

// Cells [c.x, c.z] x [c.y, c.w] (inclusive, from the bottom) of an HSM level whose texels cover
// `scale` level-0 texels, as a grid at height z in level-0 texel coordinates shifted by x0, its
// outer cells cut at the crop (a coarse level's one cell may span the whole map).
vtkSmartPointer<vtkActor> levelActor(const Image& level, int channel, vtkLookupTable* lut, double scale, double z,
                                     double x0, glm::ivec4 c, const glm::dvec4& crop) {
    const int w = c.z - c.x + 1, h = c.w - c.y + 1;
    vtkNew<vtkRectilinearGrid> grid;
    grid->SetDimensions(w + 1, h + 1, 1);
    vtkNew<vtkDoubleArray> xs, ys, zs;
    for (int i = 0; i <= w; ++i) xs->InsertNextValue(x0 + std::clamp((c.x + i) * scale, crop.x, crop.z));
    for (int j = 0; j <= h; ++j) ys->InsertNextValue(std::clamp((c.y + j) * scale, crop.y, crop.w));
    zs->InsertNextValue(z);
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
// whole map when nothing casts. Every level is cut at it (levelActor), so the stacks line up.
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

void rect(std::vector<std::pair<glm::vec3, glm::vec3>>& lines, double x0, double y0, double x1, double y1, double z) {
    glm::vec3 a(x0, y0, z), b(x1, y0, z), c(x1, y1, z), d(x0, y1, z);
    lines.push_back({a, b});
    lines.push_back({b, c});
    lines.push_back({c, d});
    lines.push_back({d, a});
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
    auto lut = sequentialLut(lo, hi, glm::vec3(0.25f));

    const nlohmann::json rec = ctx.pixelRecord();
    const bool hasKernel = rec.is_object() && rec.contains("kernel") && rec["kernel"].is_object();
    // Level-0 rectangles of the kernel's steps and converged range: they must stay in the crop.
    std::vector<glm::dvec4> marks;
    if (hasKernel) {
        for (const auto& st : rec["kernel"].value("steps", nlohmann::json::array())) {
            const double scale = std::ldexp(1.0, st.at("level").get<int>());
            const auto& t = st.at("texels");
            marks.push_back(glm::dvec4(t[0].get<double>() * scale, t[1].get<double>() * scale, (t[2].get<double>() + 1) * scale,
                                       (t[3].get<double>() + 1) * scale));
        }
        if (rec["kernel"].contains("texel_range")) {
            const auto& t = rec["kernel"]["texel_range"];
            marks.push_back(glm::dvec4(t[0].get<double>(), t[1].get<double>(), t[2].get<double>() + 1, t[3].get<double>() + 1));
        }
    }
    // Casters often fill a corner of the map: each level is cropped to the same square around them.
    const glm::dvec4 crop = cropOfInterest(levels[0], marks, w0, h0);
    const double cw = crop.z - crop.x, ch = crop.w - crop.y;
    const double gap = 0.45 * std::max(cw, ch);  // wide: every level seen obliquely, markers visible
    const double sideBySide = 1.25 * cw;           // the max stack's x offset

    std::string caption = "hsm  " + l.desc->id + ", L" + std::to_string(ctx.request.light) + ": " +
                          std::to_string(levels.size()) + " levels (" + std::to_string(levels[0].width) + "x" +
                          std::to_string(levels[0].height) + " .. 1x1) over a " + formatNumber(w0) + "x" +
                          formatNumber(h0) + " shadow map; min left, max right";
    const bool cropped = cw < w0 || ch < h0;
    if (cropped)
        caption += "; texels " + formatNumber(crop.x) + ".." + formatNumber(crop.z) + " x " + formatNumber(crop.y) + ".." +
                   formatNumber(crop.w) + " shown (the casters)";
    nlohmann::json data{{"levels", levels.size()}, {"range", {lo, hi}}, {"crop", {crop.x, crop.y, crop.z, crop.w}}};
    std::vector<std::vector<std::pair<glm::vec3, glm::vec3>>> stepLines;
    std::vector<std::pair<glm::vec3, glm::vec3>> kernelLines;
    if (hasKernel) {
        const auto& k = rec["kernel"];
        caption += "\npixel " + std::to_string(ctx.request.pixel->x) + "," + std::to_string(ctx.request.pixel->y) +
                   " (" + rec.value("classification", "") + "): global min " +
                   formatNumber(k.value("global_min", 0.0)) + ", " + std::to_string(k.value("iterations", 0)) +
                   " steps:";
        nlohmann::json steps = nlohmann::json::array();
        for (const auto& s : k.value("steps", nlohmann::json::array())) {
            const int level = s.at("level").get<int>();
            const auto& t = s.at("texels");
            const double scale = std::ldexp(1.0, level);
            const double z = double(std::max(level - 1, 0)) * gap + 0.5;
            std::vector<std::pair<glm::vec3, glm::vec3>> lines;
            for (double off : {0.0, sideBySide})
                rect(lines, off + t[0].get<double>() * scale, t[1].get<double>() * scale,
                     off + (t[2].get<double>() + 1) * scale, (t[3].get<double>() + 1) * scale, z);
            stepLines.push_back(lines);
            caption += " L" + std::to_string(level) + " -> w_k " + formatNumber(s.value("refined_texels", 0.0));
            steps.push_back(s);
        }
        if (k.contains("texel_range")) {
            const auto& t = k["texel_range"];
            for (double off : {0.0, sideBySide})
                rect(kernelLines, off + t[0].get<double>(), t[1].get<double>(), off + t[2].get<double>() + 1,
                     t[3].get<double>() + 1, -0.5 * gap);
        }
        data["steps"] = steps;
        data["kernel_texels"] = k.value("texels", 0.0);
    }
    result.caption = caption;
    result.data = data;

    const double strip = addCaptionStrip(ctx.out, caption);
    const double split = 1.0 - std::min(0.4, double(colourBarWidthPx(lut, "depth", ctx.out.height())) / ctx.out.width());
    vtkRenderer* r = ctx.out.addRenderer();
    r->SetViewport(0.0, strip, split, 1.0);
    r->SetBackground(0.12, 0.12, 0.14);
    for (size_t k = 0; k < levels.size(); ++k) {
        const double scale = std::ldexp(1.0, int(k) + 1), z = double(k) * gap;
        const glm::ivec4 cells = levelCells(crop, scale, levels[k].width, levels[k].height);
        r->AddActor(levelActor(levels[k], 0, lut, scale, z, 0.0, cells, crop));
        r->AddActor(levelActor(levels[k], 1, lut, scale, z, sideBySide, cells, crop));
    }
    static const glm::vec3 stepColours[] = {{1.0f, 0.2f, 0.2f}, {1.0f, 0.6f, 0.1f}, {1.0f, 1.0f, 1.0f},
                                            {0.9f, 0.3f, 0.9f}};
    for (size_t s = 0; s < stepLines.size(); ++s) r->AddActor(lineActor(stepLines[s], stepColours[std::min<size_t>(s, 3)], 3.0f));
    if (!kernelLines.empty()) r->AddActor(lineActor(kernelLines, glm::vec3(0.2f, 1.0f, 1.0f), 2.0f));
    vtkCamera* camera = r->GetActiveCamera();
    const double cx = crop.x + 0.5 * (sideBySide + cw), cy = crop.y + 0.5 * ch, cz = 0.5 * gap * double(levels.size() - 1);
    camera->SetFocalPoint(cx, cy, cz);
    camera->SetPosition(cx + 0.2 * cw, cy - 3.0 * ch, cz + 1.6 * std::max(cw, ch));
    camera->SetViewUp(0, 0, 1);
    r->ResetCamera();
    camera->Zoom(1.1 * ctx.request.zoom);
    r->ResetCameraClippingRange();
    r->AddActor2D(titleActor("HSM min | max: each step's texels (red, orange), kernel (cyan)",
                             ctx.out.height()));
    vtkRenderer* side = ctx.out.addRenderer();
    side->SetViewport(split, strip, 1.0, 1.0);
    side->SetBackground(0.12, 0.12, 0.14);
    addColourBar(side, lut, "depth", ctx.out.height());
    // Export: HSM level 1 (min, max) as image data.
    if (!ctx.request.exportPath.empty())
        writeImageData(toImageData(levels[0], {"min", "max"}), ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& hsmView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "hsm";
        // The min and max pyramids side by side in the left 86%, over the caption.
        d.aspect = [](const Renderer&, const ViewRequest&, float) { return 2.0f * (1.0f - kCaptionShare) / 0.86f; };
        d.info.doc = "the min/max depth pyramid (HSM) as two stacks of levels, with the texels the picked pixel's kernel "
                     "refinement visited at each step";
        d.info.appliesTo = "techniques with a pyramid internal 'hsm' (min, max): ssm-gbp06, ssm-contour";
        d.info.exportExtension = ".vti";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
