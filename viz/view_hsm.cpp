// `hsm`: the hierarchical shadow map (guennebaud2007 section 3) as two stacks of levels, min (left)
// and max (right), HSM level 1 at the bottom (level 0 is the shadow map itself), each level scaled
// to the same footprint; with a picked pixel, the texels the kernel refinement read at each step
// (the per-pixel record's kernel.steps[{level, texels [x0,y0,x1,y1] from the bottom}]) outlined on
// their level, one colour per step, and the converged kernel (kernel.texel_range, level-0 texels)
// outlined under the stack. Reads the `hsm` pyramid internal and the per-pixel record only.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDataSetMapper.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkProperty.h>
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

// HSM level `hsmLevel` (its texels cover 2^hsmLevel level-0 texels) as a grid of cells at height z.
vtkSmartPointer<vtkActor> levelActor(const Image& level, int channel, vtkLookupTable* lut, double scale, double z,
                                     double x0) {
    vtkNew<vtkImageData> grid;
    grid->SetDimensions(level.width + 1, level.height + 1, 1);
    grid->SetSpacing(scale, scale, 1.0);
    grid->SetOrigin(x0, 0.0, z);
    vtkNew<vtkFloatArray> values;
    values->SetName("depth");
    values->SetNumberOfTuples(vtkIdType(level.pixelCount()));
    for (int y = 0; y < level.height; ++y)
        for (int x = 0; x < level.width; ++x) {
            float v = level.at(x, level.height - 1 - y, channel);
            values->SetValue(vtkIdType(y) * level.width + x, std::isfinite(v) ? v : NAN);
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
    const double gap = 0.45 * std::max(w0, h0);  // wide: every level seen obliquely, markers visible
    const double sideBySide = 1.25 * w0;  // the max stack's x offset

    nlohmann::json rec;
    const nlohmann::json all = ctx.pixelData();
    if (all.contains("lights") && all["lights"].size() > size_t(ctx.request.light))
        rec = all["lights"][size_t(ctx.request.light)];
    const bool hasKernel = rec.is_object() && rec.contains("kernel");

    std::string caption = "hsm  " + l.desc->id + ", L" + std::to_string(ctx.request.light) + ": " +
                          std::to_string(levels.size()) + " levels (" + std::to_string(levels[0].width) + "x" +
                          std::to_string(levels[0].height) + " .. 1x1) over a " + formatNumber(w0) + "x" +
                          formatNumber(h0) + " shadow map; min left, max right";
    nlohmann::json data{{"levels", levels.size()}, {"range", {lo, hi}}};
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
    vtkRenderer* r = ctx.out.addRenderer();
    r->SetViewport(0.0, strip, 0.86, 1.0);
    r->SetBackground(0.12, 0.12, 0.14);
    for (size_t k = 0; k < levels.size(); ++k) {
        const double scale = std::ldexp(1.0, int(k) + 1), z = double(k) * gap;
        r->AddActor(levelActor(levels[k], 0, lut, scale, z, 0.0));
        r->AddActor(levelActor(levels[k], 1, lut, scale, z, sideBySide));
    }
    static const glm::vec3 stepColours[] = {{1.0f, 0.2f, 0.2f}, {1.0f, 0.6f, 0.1f}, {1.0f, 1.0f, 1.0f},
                                            {0.9f, 0.3f, 0.9f}};
    for (size_t s = 0; s < stepLines.size(); ++s) r->AddActor(lineActor(stepLines[s], stepColours[std::min<size_t>(s, 3)], 3.0f));
    if (!kernelLines.empty()) r->AddActor(lineActor(kernelLines, glm::vec3(0.2f, 1.0f, 1.0f), 2.0f));
    vtkCamera* camera = r->GetActiveCamera();
    const double cx = sideBySide * 0.5 + w0 * 0.5, cy = h0 * 0.5, cz = 0.5 * gap * double(levels.size() - 1);
    camera->SetFocalPoint(cx, cy, cz);
    camera->SetPosition(cx + 0.2 * w0, cy - 3.0 * h0, cz + 1.6 * std::max(w0, h0));
    camera->SetViewUp(0, 0, 1);
    r->ResetCamera();
    camera->Zoom(1.1 * ctx.request.zoom);
    r->ResetCameraClippingRange();
    r->AddActor2D(titleActor("HSM min | max: texels each kernel step read (red, orange), kernel (cyan)",
                             ctx.out.height()));
    vtkRenderer* side = ctx.out.addRenderer();
    side->SetViewport(0.86, strip, 1.0, 1.0);
    side->SetBackground(0.12, 0.12, 0.14);
    auto bar = colourBar(lut, "depth");
    bar->SetPosition(0.05, 0.08);
    bar->SetPosition2(0.9, 0.84);
    side->AddActor2D(bar);
    // Export: HSM level 1 (min, max) as image data.
    if (!ctx.request.exportPath.empty())
        writeImageData(toImageData(levels[0], {"min", "max"}), ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& hsmView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "hsm";
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
