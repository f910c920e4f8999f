// `shadow-map`: the light-view depth map a technique rendered (its `shadow_map` internal, or another
// depth internal named with --internal), colour-mapped with a colour bar; texels with no caster are
// grey. With --pixel: the receiver's texel (magenta) and the texels its depth tests read (orange),
// both from the technique's per-pixel record ("shadow_map_texel", "texels_read"), and a close-up of
// that neighbourhood beside the map.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>

#include "error.h"
#include "view_common.h"

namespace shadowlab {

namespace {

// Marker colours outside the viridis map of the depths: magenta and orange.
const glm::vec3 kTexelRgb(1.0f, 0.2f, 1.0f), kReadRgb(1.0f, 0.45f, 0.0f);

std::string mapName(const ViewRequest& request) { return request.internal.empty() ? "shadow_map" : request.internal; }

std::string refusal(const LightState& l, const ViewRequest& request) {
    const std::string name = mapName(request);
    const InternalDesc* i = l.desc->findInternal(name);
    if (!i || i->kind != InternalDesc::Kind::Image)
        return "technique " + l.desc->id + " renders no light-view depth map '" + name +
               "' (the view shows a technique's 'shadow_map' image internal; see `shadowlab list`)";
    if (!i->appliesWhen.empty() && !Condition(i->appliesWhen, *l.desc, "shadow-map view").holds(l.params))
        return "technique " + l.desc->id + " writes '" + name + "' only when " + i->appliesWhen;
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    return "";
}

// Outline of texels [x0, x1] x [y0, y1] (inclusive; texel (x, y) covers [x - 0.5, x + 0.5] around its
// image point) at height z above the image.
void addRect(std::vector<std::pair<glm::vec3, glm::vec3>>& lines, int x0, int y0, int x1, int y1, float z) {
    glm::vec3 a(x0 - 0.5f, y0 - 0.5f, z), b(x1 + 0.5f, y0 - 0.5f, z), c(x1 + 0.5f, y1 + 0.5f, z), d(x0 - 0.5f, y1 + 0.5f, z);
    lines.push_back({a, b});
    lines.push_back({b, c});
    lines.push_back({c, d});
    lines.push_back({d, a});
}

void build(ViewContext& ctx, ViewResult& result) {
    const std::string name = mapName(ctx.request);
    const CollectedInternal* map = ctx.internal(name);
    if (!map || map->levels.empty()) throw InputError("view shadow-map: the technique wrote no '" + name + "' this frame");
    const Image& depth = map->levels[0];
    auto image = toImageData(depth, {"depth"});
    auto [lo, hi] = finiteRange(depth);
    auto lut = sequentialLut(lo, hi);
    nlohmann::json data{{"internal", name}, {"size", {depth.width, depth.height}}, {"depth_range", {lo, hi}}};

    // What the technique recorded for the picked pixel.
    nlohmann::json record = ctx.pixelRecord();
    const bool picked = ctx.request.pixel.has_value() && record.contains("shadow_map_texel");
    std::string pixelLine;
    glm::ivec2 texel(0), readLo(0), readHi(0);
    std::vector<std::pair<glm::vec3, glm::vec3>> texelLines, readLines, cross;
    if (ctx.request.pixel && !picked) {
        pixelLine = "pixel (" + std::to_string(ctx.request.pixel->x) + ", " + std::to_string(ctx.request.pixel->y) +
                    "): " + (record.value("background", false) ? "background, no shadow-map look-up"
                                                               : "the technique records no texel for it");
    }
    if (picked) {
        texel = glm::ivec2(record["shadow_map_texel"][0].get<int>(), record["shadow_map_texel"][1].get<int>());
        readLo = readHi = texel;
        int readCount = 0;
        if (record.contains("texels_read"))
            for (const auto& r : record["texels_read"]) {
                int x0 = r[0], y0 = r[1], x1 = r[2], y1 = r[3];
                addRect(readLines, x0, y0, x1, y1, 1.0f);
                readCount += (x1 - x0 + 1) * (y1 - y0 + 1);
                readLo = glm::min(readLo, glm::ivec2(x0, y0));
                readHi = glm::max(readHi, glm::ivec2(x1, y1));
            }
        addRect(texelLines, texel.x, texel.y, texel.x, texel.y, 2.0f);
        // On the whole map a texel is smaller than a screen pixel: a cross-hair finds it.
        const float arm = 0.04f * float(std::max(depth.width, depth.height));
        const glm::vec3 c(texel.x, texel.y, 2.0f);
        cross = {{c - glm::vec3(2.5f * arm, 0, 0), c - glm::vec3(0.5f * arm, 0, 0)},
                 {c + glm::vec3(0.5f * arm, 0, 0), c + glm::vec3(2.5f * arm, 0, 0)},
                 {c - glm::vec3(0, 2.5f * arm, 0), c - glm::vec3(0, 0.5f * arm, 0)},
                 {c + glm::vec3(0, 0.5f * arm, 0), c + glm::vec3(0, 2.5f * arm, 0)}};
        auto fmt = [](const nlohmann::json& v) { return v.is_number() ? formatNumber(v.get<double>()) : std::string("none"); };
        char line[400];
        std::snprintf(line, sizeof line,
                      "pixel (%d, %d): texel (%d, %d) (magenta), receiver z %s, stored z %s; %d texel(s) read (orange); "
                      "v = %s",
                      ctx.request.pixel->x, ctx.request.pixel->y, texel.x, texel.y, fmt(record["receiver_depth"]).c_str(),
                      fmt(record["stored_depth"]).c_str(), readCount, fmt(record["visibility"]).c_str());
        pixelLine = line;
        data["texel"] = {texel.x, texel.y};
        data["texels_read"] = record.value("texels_read", nlohmann::json::array());
        data["texels_read_count"] = readCount;
    }
    result.caption = "shadow-map  " + ctx.light().desc->id + ", L" + std::to_string(ctx.request.light) + ": " + map->doc;
    if (!pixelLine.empty()) result.caption += "\n" + pixelLine;
    result.data = data;
    const double strip = addCaptionStrip(ctx.out, result.caption);

    // Layout: the map (left); with a pixel, a close-up (right, top) above a horizontal colour bar;
    // else a vertical colour bar at the right.
    const std::string barTitle = "light-view depth z";
    const double barShare = std::min(0.4, double(colourBarWidthPx(lut, barTitle, ctx.out.height())) / ctx.out.width());
    const double mapRight = picked ? 0.62 : 1.0 - barShare;
    vtkRenderer* main = ctx.out.addRenderer();
    main->SetBackground(0.12, 0.12, 0.14);
    main->SetViewport(0.0, strip, mapRight, 1.0);
    addImagePanel(main, image, "depth", lut);
    fitImage(main, depth.width, depth.height, ctx.out.width() * mapRight / (ctx.out.height() * (1.0 - strip)));
    main->AddActor2D(titleActor(name + " (" + std::to_string(depth.width) + "x" + std::to_string(depth.height) + ")",
                                ctx.request.height));
    vtkRenderer* side = ctx.out.addRenderer();
    side->SetBackground(0.12, 0.12, 0.14);
    if (!picked) {
        side->SetViewport(mapRight, strip, 1.0, 1.0);
        addColourBar(side, lut, barTitle, ctx.out.height());
    } else {
        main->AddActor(lineActor(cross, kTexelRgb, 2.0f));
        main->AddActor(lineActor(readLines, kReadRgb, 1.5f));
        main->AddActor(lineActor(texelLines, kTexelRgb, 2.0f));
        // A horizontal bar under the close-up, as tall as its title, strip and labels need.
        const int px = textPx(ctx.out.height());
        const double barHeight = std::min(0.45 * (1.0 - strip), (4.6 * px + 12.0) / ctx.out.height());
        side->SetViewport(mapRight, strip, 1.0, strip + barHeight);
        addColourBar(side, lut, barTitle, ctx.out.height(), true);
        // The close-up: the texels read plus a margin of 4 texels.
        vtkRenderer* zoom = ctx.out.addRenderer();
        zoom->SetViewport(mapRight, strip + barHeight, 1.0, 1.0);
        zoom->SetBackground(0.12, 0.12, 0.14);
        addImagePanel(zoom, image, "depth", lut);
        zoom->AddActor(lineActor(readLines, kReadRgb, 2.5f));
        zoom->AddActor(lineActor(texelLines, kTexelRgb, 3.0f));
        glm::vec2 centre = glm::vec2(readLo + readHi) * 0.5f;
        float extent = float(std::max(readHi.x - readLo.x, readHi.y - readLo.y)) + 1.0f + 8.0f;
        vtkCamera* zc = zoom->GetActiveCamera();
        zc->SetFocalPoint(centre.x, centre.y, 0.0);
        zc->SetPosition(centre.x, centre.y, 1e4);
        zc->SetParallelScale(extent * 0.5);
        zoom->ResetCameraClippingRange();
        zoom->AddActor2D(titleActor("close-up", ctx.request.height));
    }

    if (!ctx.request.exportPath.empty()) writeImageData(image, ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& shadowMapView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "shadow-map";
        // The square map in the left 84% (62% with a picked pixel's close-up), over the caption.
        d.aspect = [](const Renderer&, const ViewRequest& q, float) { return (1.0f - kCaptionShare) / (q.pixel ? 0.62f : 0.84f); };
        d.info.doc = "the light-view depth map with a colour bar; with --pixel the receiver's texel and the texels "
                     "the technique read for it, and a close-up";
        d.info.appliesTo = "techniques with a 'shadow_map' image internal (hard, pcf; --internal picks another depth map)";
        d.info.exportExtension = ".vti";
        d.refusal = refusal;
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
