// The sssm/pcss heat-map views, in one file (viz/ holds at most 20 sources, scripts/check_layout.cmake):
// `kernel-size` and `reuse`.
//
// `kernel-size`: the filter kernel each pixel used, as a heat map with a colour bar, for every
// technique that exposes one: an image internal with a channel named `kernel_size` or `kernel_*`
// (pcss: `blockers.kernel_size`, texels of the shadow map; sssm: `kernel_size.kernel_x/kernel_y`,
// screen pixels). Background pixels show grey. The caption gives the mean and largest kernel over
// the pixels that filtered (kernel > 1).
//
// `reuse`: sssm's reuse maps (buades2015 Fig. 10: black = no reuse, white = every row reused) over
// the image, one panel per map (step 2: blocker rows within alpha; step 3: blur rows within beta),
// with the share of rows reused over the pixels where the step ran (-1 in the map: it did not run;
// shown in blue-grey).
#include <vtkActor.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>

#include <algorithm>
#include <cmath>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {
namespace kernel_size {

bool isKernelChannel(const std::string& c) { return c == "kernel_size" || c.rfind("kernel_", 0) == 0; }

// The first image internal of the light's technique with kernel channels, and those channels.
const InternalDesc* kernelInternal(const LightState& l, std::vector<int>* channels) {
    for (const InternalDesc& i : l.desc->internals) {
        if (i.kind != InternalDesc::Kind::Image) continue;
        std::vector<int> found;
        for (size_t c = 0; c < i.channels.size(); ++c)
            if (isKernelChannel(i.channels[c])) found.push_back(int(c));
        if (found.empty()) continue;
        if (channels) *channels = found;
        return &i;
    }
    return nullptr;
}

std::string refusal(const LightState& l, const ViewRequest& request) {
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    if (!kernelInternal(l, nullptr))
        return "technique " + l.desc->id + " exposes no kernel size (an image internal with a 'kernel_size' or 'kernel_*' channel)";
    return "";
}

void build(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    std::vector<int> channels;
    const InternalDesc& desc = *kernelInternal(l, &channels);
    const CollectedInternal* collected = ctx.internal(desc.name);
    if (!collected || collected->levels.empty())
        throw InputError("view kernel-size: technique " + l.desc->id + " wrote no '" + desc.name + "' this frame");
    const Image ids = ctx.renderer.ids();
    Image kernels(collected->levels[0].width, collected->levels[0].height, int(channels.size()));
    std::vector<std::string> names;
    nlohmann::json stats = nlohmann::json::array();
    std::string summary;
    for (size_t k = 0; k < channels.size(); ++k) {
        names.push_back(desc.channels[size_t(channels[k])]);
        double sum = 0.0;
        float largest = 0.0f;
        size_t filtered = 0;
        for (int y = 0; y < kernels.height; ++y)
            for (int x = 0; x < kernels.width; ++x) {
                bool background = ids.width == kernels.width && ids.height == kernels.height && ids.at(x, y) < 0.0f;
                float v = background ? NAN : collected->levels[0].at(x, y, channels[k]);
                kernels.at(x, y, int(k)) = v;
                if (std::isfinite(v) && v > 1.0f) {
                    sum += v;
                    largest = std::max(largest, v);
                    ++filtered;
                }
            }
        double mean = filtered ? sum / double(filtered) : 0.0;
        stats.push_back({{"channel", names.back()}, {"filtered_pixels", filtered}, {"mean", mean}, {"max", largest}});
        summary += (summary.empty() ? "" : "; ") + names.back() + ": mean " + formatNumber(mean) + ", max " +
                   formatNumber(largest) + " over " + std::to_string(filtered) + " pixels";
    }
    result.caption = "kernel-size  " + l.desc->id + ", L" + std::to_string(ctx.request.light) + ", " + desc.name +
                     " (kernel > 1): " + summary;
    result.data = {{"internal", desc.name}, {"channels", stats}};
    const double strip = addCaptionStrip(ctx.out, result.caption);
    auto image = toImageData(kernels, names);
    for (size_t k = 0; k < names.size(); ++k) {
        auto [lo, hi] = finiteRange(kernels, int(k));
        double x0 = double(k) / double(names.size()), x1 = double(k + 1) / double(names.size());
        addImagePanelWithBar(ctx.out, image, names[k], paletteLut(Palette::KernelSize, std::min(lo, 1.0f), std::max(hi, 1.0f)),
                             desc.name + "." + names[k], names[k], x0, strip, x1, 1.0);
    }
    if (!ctx.request.exportPath.empty()) writeImageData(image, ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace kernel_size
}  // namespace

const ViewDesc& kernelSizeView() {
    using namespace kernel_size;
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "kernel-size";
        d.aspect = [](const Renderer& r, const ViewRequest& q, float frame) {  // one panel per kernel channel
            std::vector<int> channels;
            kernelInternal(*r.lights().at(size_t(q.light)), &channels);
            return framePanelsAspect(frame, int(channels.size()));
        };
        d.info.doc = "the filter kernel (penumbra size) each pixel used, as a heat map with a colour bar; background grey";
        d.info.appliesTo = "techniques with a kernel-size internal channel (pcss, sssm)";
        d.info.exportExtension = ".vti";
        d.refusal = kernel_size::refusal;
        d.build = kernel_size::build;
        return d;
    }();
    return desc;
}


// ---- reuse ------------------------------------------------------------------------------------------

namespace {
namespace reuse {

std::vector<const InternalDesc*> reuseInternals(const LightState& l) {
    std::vector<const InternalDesc*> out;
    for (const InternalDesc& i : l.desc->internals)
        if (i.kind == InternalDesc::Kind::Image && i.name.rfind("reuse", 0) == 0) out.push_back(&i);
    return out;
}

std::string refusal(const LightState& l, const ViewRequest& request) {
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

}  // namespace reuse
}  // namespace

const ViewDesc& reuseView() {
    using namespace reuse;
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "reuse";
        d.aspect = [](const Renderer& r, const ViewRequest& q, float frame) {  // one panel per reuse map
            return framePanelsAspect(frame, int(reuseInternals(*r.lights().at(size_t(q.light))).size()));
        };
        d.info.doc = "sssm's reuse maps (buades2015 Fig. 10) over the image with the share of rows reused per step";
        d.info.appliesTo = "techniques with reuse maps (sssm)";
        d.info.exportExtension = ".vti";
        d.refusal = reuse::refusal;
        d.build = reuse::build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
