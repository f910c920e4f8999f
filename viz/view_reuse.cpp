// `reuse`: sssm's reuse maps (buades2015 Fig. 10: black = no reuse, white = every row reused) over
// the image, one panel per map (step 2: blocker rows within alpha; step 3: blur rows within beta),
// with the share of rows reused over the pixels where the step ran (-1 in the map: it did not run;
// shown in blue-grey).
#include <vtkActor.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>

#include <cmath>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {

std::vector<const InternalDesc*> reuseInternals(const LightState& l) {
    std::vector<const InternalDesc*> out;
    for (const InternalDesc& i : l.desc->internals)
        if (i.kind == InternalDesc::Kind::Image && i.name.rfind("reuse", 0) == 0) out.push_back(&i);
    return out;
}

std::string refusal(const Renderer& renderer, const ViewRequest& request) {
    const LightState& l = *renderer.lights().at(size_t(request.light));
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (reuseInternals(l).empty()) return "technique " + l.desc->id + " has no reuse maps (internals named reuse*: sssm)";
    return "";
}

// Black (0) to white (1); "did not run" (NaN) in blue-grey.
void build(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    std::vector<const InternalDesc*> maps = reuseInternals(l);
    nlohmann::json stats = nlohmann::json::array();
    std::string summary;
    std::vector<Image> images;
    for (const InternalDesc* m : maps) {
        const CollectedInternal* collected = ctx.internal(m->name);
        if (!collected || collected->levels.empty())
            throw InputError("view reuse: technique " + l.desc->id + " wrote no '" + m->name + "' this frame");
        Image img = collected->levels[0];
        double sum = 0.0;
        size_t ran = 0;
        for (float& v : img.data) {
            if (!std::isfinite(v) || v < 0.0f) {
                v = NAN;
                continue;
            }
            sum += v;
            ++ran;
        }
        double percent = ran ? 100.0 * sum / double(ran) : 0.0;
        stats.push_back({{"internal", m->name}, {"percent", percent}, {"pixels", ran}});
        summary += (summary.empty() ? "" : "; ") + m->name + ": " + formatNumber(percent, 3) + "% of rows reused over " +
                   std::to_string(ran) + " pixels";
        images.push_back(img);
    }
    result.caption = "reuse  " + l.desc->id + ", L" + std::to_string(ctx.request.light) + ": " + summary;
    result.data = {{"maps", stats}};
    const double strip = addCaptionStrip(ctx.out, result.caption);
    auto lut = paletteLut(Palette::Depth, 0.0, 1.0);  // 0 computed, 1 reused; no data grey
    for (size_t k = 0; k < images.size(); ++k) {
        auto image = toImageData(images[k], {"reuse"});
        double x0 = double(k) / double(images.size()), x1 = double(k + 1) / double(images.size());
        addImagePanelWithBar(ctx.out, image, "reuse", lut, maps[k]->name, "reused", x0, strip, x1, 1.0);
        if (k == 0 && !ctx.request.exportPath.empty()) writeImageData(image, ctx.exportTarget(ctx.request.exportPath));
    }
}

}  // namespace

const ViewDesc& reuseView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "reuse";
        d.aspect = [](const Renderer& r, const ViewRequest& q, float frame) {  // one panel per reuse map
            return framePanelsAspect(frame, int(reuseInternals(*r.lights().at(size_t(q.light))).size()));
        };
        d.info.doc = "sssm's reuse maps (buades2015 Fig. 10) over the image with the share of rows reused per step";
        d.info.appliesTo = "techniques with reuse maps (sssm)";
        d.info.exportExtension = ".vti";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
