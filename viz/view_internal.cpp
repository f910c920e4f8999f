// `internal`: any image or pyramid internal of the light's technique (--internal NAME; by default
// the first it declares), colour-mapped with a colour bar and the internal's doc line as caption.
// Images: one panel per channel, named by the descriptor's channel names. Pyramids: the levels as
// a stack in 3D, level 0 at the bottom, each scaled to the same footprint so a texel of level k
// covers the 2^k x 2^k texels of level 0 it summarises.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDataSetMapper.h>
#include <vtkFloatArray.h>
#include <vtkImageActor.h>
#include <vtkProperty.h>
#include <vtkImageData.h>
#include <vtkImageMapToColors.h>
#include <vtkImageMapper3D.h>
#include <vtkPointData.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>

#include <filesystem>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {

bool isPicture(const InternalDesc& i) {
    return i.kind == InternalDesc::Kind::Image || i.kind == InternalDesc::Kind::Pyramid;
}

bool appliesNow(const InternalDesc& i, const LightState& l) {
    return i.appliesWhen.empty() || Condition(i.appliesWhen, *l.desc, "internal view").holds(l.params);
}

// The image and pyramid internals of the light's technique that apply now, as "name (kind)".
std::vector<std::string> available(const LightState& l) {
    std::vector<std::string> out;
    for (const InternalDesc& i : l.desc->internals)
        if (isPicture(i) && appliesNow(i, l)) out.push_back(i.name);
    return out;
}

std::string chosenName(const LightState& l, const ViewRequest& request) {
    if (!request.internal.empty()) return request.internal;
    std::vector<std::string> names = available(l);
    return names.empty() ? "" : names.front();
}

std::string refusal(const LightState& l, const ViewRequest& request) {
    std::vector<std::string> names = available(l);
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (names.empty()) return "technique " + l.desc->id + " declares no image or pyramid internal that applies now";
    std::string name = chosenName(l, request);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string list;
        for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
        const InternalDesc* i = l.desc->findInternal(name);
        if (i && isPicture(*i))
            return "technique " + l.desc->id + " writes '" + name + "' only when " + i->appliesWhen + " (now: " + list + ")";
        return "technique " + l.desc->id + " has no image or pyramid internal '" + name + "' (expected one of: " + list +
               ")";
    }
    return "";
}


}  // namespace

// One level as a grid of cells, one per texel (so a 1x1 level is a full square): texel (i, j) of
// level k covers [i 2^k, (i + 1) 2^k] x [j 2^k, (j + 1) 2^k] of level 0's texels, at height z.
static vtkSmartPointer<vtkActor> levelActor(const Image& level, vtkLookupTable* lut, double scale, double z) {
    vtkNew<vtkImageData> grid;
    grid->SetDimensions(level.width + 1, level.height + 1, 1);
    grid->SetSpacing(scale, scale, 1.0);
    grid->SetOrigin(-0.5, -0.5, z);
    vtkNew<vtkFloatArray> values;
    values->SetName("value");
    values->SetNumberOfTuples(vtkIdType(level.pixelCount()));
    for (int y = 0; y < level.height; ++y)
        for (int x = 0; x < level.width; ++x) {
            float v = level.at(x, level.height - 1 - y, 0);  // cell row j counts from the bottom
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

std::pair<float, float> addPyramidStack(VtkOffscreen& out, const std::vector<Image>& levels, const std::string& channel,
                                        const std::string& title, double y0, float zoom) {
    // Channel 0 of every level, one colour scale for all of them.
    float lo = INFINITY, hi = -INFINITY;
    for (const Image& level : levels) {
        auto [a, b] = finiteRange(level, 0);
        lo = std::min(lo, a);
        hi = std::max(hi, b);
    }
    auto lut = sequentialLut(lo, hi);
    const double split = 1.0 - std::min(0.4, double(colourBarWidthPx(lut, channel, out.height())) / out.width());
    vtkRenderer* r = out.addRenderer();
    r->SetViewport(0.0, y0, split, 1.0);
    r->SetBackground(0.12, 0.12, 0.14);
    const double w0 = levels[0].width, h0 = levels[0].height;
    const double gap = 0.18 * std::max(w0, h0);
    for (size_t k = 0; k < levels.size(); ++k) {
        r->AddActor(levelActor(levels[k], lut, w0 / levels[k].width, double(k) * gap));
    }
    vtkCamera* camera = r->GetActiveCamera();
    const double cx = w0 * 0.5 - 0.5, cy = h0 * 0.5 - 0.5, cz = 0.5 * gap * double(levels.size() - 1);
    camera->SetFocalPoint(cx, cy, cz);
    camera->SetPosition(cx + 0.9 * w0, cy - 1.6 * h0, cz + 1.1 * std::max(w0, h0));
    camera->SetViewUp(0, 0, 1);
    r->ResetCamera();
    camera->Zoom(0.95 * zoom);
    r->ResetCameraClippingRange();
    r->AddActor2D(titleActor(title + ": " + std::to_string(levels.size()) + " levels, level 0 (" +
                                 std::to_string(levels[0].width) + "x" + std::to_string(levels[0].height) +
                                 ") at the bottom",
                             out.height()));
    vtkRenderer* side = out.addRenderer();
    side->SetViewport(split, y0, 1.0, 1.0);
    side->SetBackground(0.12, 0.12, 0.14);
    addColourBar(side, lut, channel, out.height());
    return {lo, hi};
}

namespace {

void build(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    const std::string name = chosenName(l, ctx.request);
    const InternalDesc& desc = *l.desc->findInternal(name);
    const CollectedInternal* collected = ctx.internal(name);
    if (!collected || collected->levels.empty())
        throw InputError("view internal: technique " + l.desc->id + " wrote no '" + name + "' this frame");
    const std::vector<Image>& levels = collected->levels;
    const int channels = levels[0].channels;
    auto channelName = [&](int c) {
        return c < int(desc.channels.size()) ? desc.channels[size_t(c)] : "c" + std::to_string(c);
    };
    std::vector<std::string> names;
    for (int c = 0; c < channels; ++c) names.push_back(channelName(c));

    result.caption = "internal  " + l.desc->id + ", L" + std::to_string(ctx.request.light) + ", " + name + " (" +
                     internalKindName(desc.kind) + (levels.size() > 1 ? ", " + std::to_string(levels.size()) + " levels" : "") +
                     "): " + desc.doc;
    nlohmann::json data{{"internal", name}, {"kind", internalKindName(desc.kind)}, {"levels", levels.size()},
                        {"size", {levels[0].width, levels[0].height}}, {"channels", names}};
    const double strip = addCaptionStrip(ctx.out, result.caption);

    std::vector<vtkSmartPointer<vtkImageData>> images;
    for (const Image& level : levels) images.push_back(toImageData(level, names));

    if (desc.kind == InternalDesc::Kind::Pyramid) {
        auto [lo, hi] = addPyramidStack(ctx.out, levels, names[0], name, strip, ctx.request.zoom);
        data["range"] = {lo, hi};
    } else {
        nlohmann::json ranges = nlohmann::json::array();
        for (int c = 0; c < channels; ++c) {
            auto [lo, hi] = finiteRange(levels[0], c);
            ranges.push_back({lo, hi});
            double x0 = double(c) / channels, x1 = double(c + 1) / channels;
            // A signed internal (negative values are data, not markers) on the diverging palette,
            // symmetric about 0.
            const double maxAbs = std::max({1e-6, double(std::fabs(lo)), double(std::fabs(hi))});
            addImagePanelWithBar(ctx.out, images[0], names[size_t(c)],
                                 desc.signedValues ? divergingLut(maxAbs) : sequentialLut(lo, hi),
                                 name + "." + names[size_t(c)], names[size_t(c)], x0, strip, x1, 1.0);
        }
        data["ranges"] = ranges;
    }
    result.data = data;

    if (!ctx.request.exportPath.empty()) {
        // Level 0 at the path; level k of a pyramid beside it as <stem>-<k>.vti.
        writeImageData(images[0], ctx.exportTarget(ctx.request.exportPath));
        std::filesystem::path p(ctx.request.exportPath);
        for (size_t k = 1; k < images.size(); ++k) {
            std::string ext = p.extension().string();
            std::string stem = ctx.request.exportPath.substr(0, ctx.request.exportPath.size() - ext.size());
            writeImageData(images[k], ctx.exportTarget(stem + "-" + std::to_string(k) + ext));
        }
    }
}

}  // namespace

const ViewDesc& internalView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "internal";
        d.info.doc = "any image or pyramid internal of the technique (--internal NAME), one panel per channel with a "
                     "colour bar, pyramids as a stack of levels; the internal's doc line as caption";
        d.info.appliesTo = "techniques with an image or pyramid internal (hard, pcf, reference)";
        d.info.exportExtension = ".vti";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
