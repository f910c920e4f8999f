// `error`: the technique's visibility against a reference: the signed error v - v_ref (blue: too
// dark, red: too bright) and the absolute error |v - v_ref|, each with a colour bar, and in the
// caption the metrics of techniques/core/image/metrics.h over all pixels and over the penumbra, printed
// exactly as `shadowlab compare` prints them (a test compares the two).
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkRenderer.h>

#include <cmath>

#include "error.h"
#include "image/metrics.h"
#include "view_common.h"

namespace shadowlab {

namespace {

// `shadowlab compare`'s line for one set of metrics (app/cli/cli.cpp, commandCompare).
std::string compareLine(const char* label, const Metrics& m) {
    char line[256];
    std::snprintf(line, sizeof line, "%-9s pixels %8zu  RMSE %.6f  max %.6f  PSNR %s dB  SSIM %.6f", label, m.pixels,
                  m.rmse, m.maxAbs, std::isinf(m.psnr) ? "inf" : std::to_string(m.psnr).c_str(), m.ssim);
    return line;
}

nlohmann::json metricsJson(const Metrics& m) {
    return {{"rmse", m.rmse},
            {"max_abs", m.maxAbs},
            {"psnr", std::isinf(m.psnr) ? nlohmann::json("inf") : nlohmann::json(m.psnr)},
            {"ssim", m.ssim},
            {"pixels", m.pixels}};
}

// The reference of the renderer's current state: the `reference` technique (its default
// parameters but `samples`), same size, camera, lights, ambient and time.
Image computeReference(const Renderer& renderer, const Scene& scene, int samples) {
    RenderOptions options;
    options.width = renderer.width();
    options.height = renderer.height();
    options.technique = "reference";
    if (samples > 0) options.sets.push_back({"samples", std::to_string(samples)});
    Renderer reference(scene, options);
    reference.setCamera(renderer.camera());
    reference.setAmbient(renderer.ambient());
    for (size_t i = 0; i < renderer.lights().size(); ++i) reference.setLight(i, renderer.lightAt(i));
    reference.setTime(renderer.time());
    reference.renderFrame(int(std::lround(renderer.time() / kSecondsPerFrame)), {"visibility"});
    return reference.visibility();
}

void build(ViewContext& ctx, ViewResult& result) {
    const Image visibility = ctx.renderer.visibility();
    Image computed;
    const Image* reference = ctx.request.reference;
    if (!reference) {
        computed = computeReference(ctx.renderer, ctx.scene, ctx.request.referenceSamples);
        reference = &computed;
    }
    if (reference->channels != 1)
        throw InputError("view error: the reference must be a 1-channel visibility image, got " +
                         std::to_string(reference->channels) + " channels");
    if (reference->width != visibility.width || reference->height != visibility.height)
        throw InputError("view error: the reference is " + std::to_string(reference->width) + "x" +
                         std::to_string(reference->height) + ", the technique renders " +
                         std::to_string(visibility.width) + "x" + std::to_string(visibility.height) +
                         " (give --size of the reference)");

    const Metrics all = computeMetrics(visibility, *reference);
    const std::vector<uint8_t> penumbra = penumbraMask(*reference);
    const Metrics pen = computeMetrics(visibility, *reference, &penumbra);

    Image errors(visibility.width, visibility.height, 4);
    float maxAbs = 0.0f;
    // The pictures show no data (the background grey) where the pixel sees no geometry, so the sky is
    // never mistaken for zero error; the caption's metrics are compare's, over every pixel.
    const Image ids = ctx.renderer.ids();
    for (size_t i = 0; i < visibility.pixelCount(); ++i) {
        float v = visibility.data[i], r = reference->data[i];
        const bool geometry = ids.pixelCount() != visibility.pixelCount() || ids.data[i] >= 0.0f;
        float e = std::isfinite(v) && std::isfinite(r) && geometry ? v - r : NAN;
        errors.data[i * 4 + 0] = e;
        errors.data[i * 4 + 1] = std::abs(e);
        errors.data[i * 4 + 2] = v;
        errors.data[i * 4 + 3] = r;
        if (std::isfinite(e)) maxAbs = std::max(maxAbs, std::abs(e));
    }
    auto image = toImageData(errors, {"signed_error", "abs_error", "visibility", "reference"});

    // A choosing technique (`auto`) names its pick for this light beside its own id.
    const LightState& light = ctx.light();
    const std::string runs = light.requested && light.requested != light.desc
                                 ? light.requested->id + " (" + light.desc->id + " on light " + std::to_string(light.index) + ")"
                                 : light.desc->id;
    result.caption = "error  " + runs + " against " +
                     (ctx.request.reference ? std::string("the given reference")
                                             : "`reference` (" + (ctx.request.referenceSamples > 0
                                                                      ? std::to_string(ctx.request.referenceSamples)
                                                                      : std::string("default")) +
                                                   " light samples)") +
                     "\n" + compareLine("all", all) + "\n" + compareLine("penumbra", pen);
    result.data = {{"all", metricsJson(all)}, {"penumbra", metricsJson(pen)}, {"max_abs_error", maxAbs}};
    const double strip = addCaptionStrip(ctx.out, result.caption, true);
    const double scale = maxAbs > 0.0f ? maxAbs : 1.0;
    addImagePanelWithBar(ctx.out, image, "signed_error", divergingLut(scale), "signed error v - v_ref", "error", 0.0,
                         strip, 0.5, 1.0);
    addImagePanelWithBar(ctx.out, image, "abs_error", paletteLut(Palette::AbsoluteError, 0.0, scale), "absolute error |v - v_ref|",
                         "|error|", 0.5, strip, 1.0, 1.0);

    if (!ctx.request.exportPath.empty()) writeImageData(image, ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& errorView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "error";
        d.aspect = [](const Renderer&, const ViewRequest&, float frame) { return framePanelsAspect(frame, 2); };  // signed | absolute
        d.info.doc = "signed and absolute error of the visibility against the reference, with colour bars; the caption "
                     "gives compare's RMSE, max, PSNR and SSIM over all pixels and the penumbra";
        d.info.appliesTo = "every technique (against --reference FILE, else `reference` with --reference-samples N)";
        d.info.exportExtension = ".vti";
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
