// The views of the screen-space multi-resolution (guennebaud2007 sec. 5.2 and 6; ssm-contour and
// ssm-gbp06 while screen_adaptive is on), in one file (viz/ holds at most 20 sources,
// scripts/check_layout.cmake): `skipped-pixels` and `pull-push`.
//
// `skipped-pixels`: over the image, which pixels the visibility pass evaluated and which it skipped (pull-push fills them).
// Reads the `selection` image internal (one code per pixel, SEL_* of shaders/shared/
// screen_selection.glsl): background, lit and umbra (known from the classification), penumbra
// selected by eq. 6, forced by a discontinuity, evaluated with its whole block (sec. 6, > 80% of
// it selected), skipped; each in its own colour with a legend that gives its count. The 16 x 16
// blocks that sec. 6 processes whole (`block_occupancy` > 0.8) are outlined in white. The caption's
// counts are those of the very image the picture maps, pixel for pixel.
//
// `pull-push`: the pull-push reconstruction of guennebaud2007 sec. 5.2 (after Gortler et al. 1996)
// laid flat, level by level: on top the pull, levels 0 (the sparse v-buffer, `visibility_sparse`:
// its skipped pixels, weight 0, in orange as the paper's Fig. 8), 1, 2, ... up to the 1x1 top
// (`pull_push.pull`: weighted mean visibility, saturated weight); below it the push, from the top
// back down to level 0, the final visibility (`pull_push.push`: the completed visibility and the
// pull weight of the level). Each level is a tile of the same size (a texel of level k covers the
// 2^k x 2^k pixels it summarises), labelled with its level and size; the pull's visibility above its
// weight, the push's visibility alone (it keeps the pull's weights).
// With more than five levels the first four and the 1x1 top are drawn, and the caption says which
// are left out. Reads those internals and the ids read-back (background grey at level 0) only.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapToColors.h>
#include <vtkImageMapper3D.h>
#include <vtkPropCollection.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "error.h"
#include "shared/shared.h"
#include "view_common.h"

namespace shadowlab {

namespace {

const glm::vec3 kSkippedRgb(1.0f, 0.55f, 0.0f);  // skipped, weight 0: Fig. 8's orange, in both views

// The classes, by code (SEL_*), with their colours: skipped in orange as the paper's Fig. 8 marks
// the pixels pull-push fills; the evaluated ones in green, blue and magenta; lit and umbra as the
// visibility palette's ends would read them (cream, dark); background the standard's no-data grey.
struct SelectionClass {
    int code;
    glm::vec3 rgb;
    const char* label;
};
const std::array<SelectionClass, 7>& classes() {
    static const std::array<SelectionClass, 7> c = {{
        {SEL_SELECTED, {0.15f, 0.75f, 0.25f}, "eq. 6 (evaluated)"},
        {SEL_FORCED, {0.90f, 0.25f, 0.85f}, "discontinuity (evaluated)"},
        {SEL_BLOCK, {0.25f, 0.50f, 1.00f}, "whole block (evaluated)"},
        {SEL_SKIPPED, kSkippedRgb, "skipped (pull-push fills)"},
        {SEL_LIT, {0.97f, 0.93f, 0.80f}, "lit"},
        {SEL_UMBRA, {0.22f, 0.10f, 0.03f}, "umbra"},
        {SEL_BACKGROUND, kBackgroundGrey, "background"},
    }};
    return c;
}
constexpr int kCodes = 7;  // SEL_BACKGROUND .. SEL_SKIPPED
const glm::vec3 kWholeBlockRgb(1.0f);

bool appliesNow(const InternalDesc& i, const LightState& l) {
    return i.appliesWhen.empty() || Condition(i.appliesWhen, *l.desc, "skipped-pixels view").holds(l.params);
}

}  // namespace

// Shared with the pull-push view: "" when the light's technique writes the screen-adaptive
// internals `names` now, else why not (the technique has none; or it has them only when its
// screen_adaptive parameter is on, and says to turn it on).
std::string screenAdaptiveRefusal(const LightState& l, const ViewRequest& request, const std::vector<std::string>& names) {
    if (!l.light.castsShadows) return "light " + std::to_string(request.light) + " casts no shadows";
    for (const std::string& name : names) {
        const InternalDesc* i = l.desc->findInternal(name);
        if (!i)
            return "technique " + l.desc->id + " computes every pixel's visibility (no screen-space multi-resolution: "
                   "no '" + name + "' internal; ssm-contour and ssm-gbp06 have one)";
        if (!appliesNow(*i, l))
            return "technique " + l.desc->id + " writes '" + name + "' only when " + i->appliesWhen +
                   ": turn screen_adaptive on (--set screen_adaptive=true, or its box in the parameters)";
    }
    return "";
}

// Pixels of each code 0..6 of a selection image (codes rounded; anything else is an error).
std::array<size_t, 7> selectionCounts(const Image& selection) {
    std::array<size_t, 7> n{};
    for (size_t i = 0; i < selection.pixelCount(); ++i) {
        const float v = selection.data[i * size_t(selection.channels)];
        const int code = int(std::lround(v));
        if (!std::isfinite(v) || code < 0 || code >= kCodes)
            throw InternalError("skipped-pixels: selection code " + formatNumber(v) + " outside 0..6 at pixel " +
                                std::to_string(i));
        ++n[size_t(code)];
    }
    return n;
}

namespace {

std::string skippedPixelsRefusal(const LightState& l, const ViewRequest& request) {
    return screenAdaptiveRefusal(l, request, {"selection"});
}

vtkSmartPointer<vtkLookupTable> classLut() {
    auto lut = vtkSmartPointer<vtkLookupTable>::New();
    lut->SetNumberOfTableValues(kCodes);
    lut->SetTableRange(-0.5, kCodes - 0.5);  // code k -> entry k
    for (const SelectionClass& c : classes()) lut->SetTableValue(c.code, c.rgb.r, c.rgb.g, c.rgb.b, 1.0);
    lut->SetNanColor(kBackgroundGrey.r, kBackgroundGrey.g, kBackgroundGrey.b, 1.0);
    return lut;
}

void buildSkippedPixels(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    const CollectedInternal* sel = ctx.internal("selection");
    if (!sel || sel->levels.empty())
        throw InputError("view skipped-pixels: technique " + l.desc->id + " wrote no 'selection' this frame");
    const Image& codes = sel->levels[0];
    const std::array<size_t, 7> n = selectionCounts(codes);
    const size_t evaluated = n[SEL_SELECTED] + n[SEL_FORCED] + n[SEL_BLOCK], skipped = n[SEL_SKIPPED];
    const size_t penumbra = evaluated + skipped;
    const double fraction = penumbra ? double(evaluated) / double(penumbra) : 1.0;

    // The blocks of sec. 6 (16 x 16 from the bottom-left, as GL counts them): whole (> 0.8 of it
    // selected), skipped (none), compacted (the rest).
    const CollectedInternal* occ = ctx.internal("block_occupancy");
    size_t whole = 0, compacted = 0, empty = 0;
    std::vector<std::pair<glm::vec3, glm::vec3>> outlines;
    if (occ && !occ->levels.empty()) {
        const Image& o = occ->levels[0];
        for (int row = 0; row < o.height; ++row)
            for (int bx = 0; bx < o.width; ++bx) {
                const float f = o.at(bx, row);
                const int by = o.height - 1 - row;  // from the bottom
                if (!(f > 0.0f)) {
                    ++empty;
                    continue;
                }
                if (f <= BP_BLOCK_WHOLE) {
                    ++compacted;
                    continue;
                }
                ++whole;
                // Pixel (i, j) of the picture covers [i - 0.5, i + 0.5]; the block is cut at the frame.
                const float x0 = bx * BP_BLOCK - 0.5f, x1 = std::min((bx + 1) * BP_BLOCK, codes.width) - 0.5f;
                const float y0 = by * BP_BLOCK - 0.5f, y1 = std::min((by + 1) * BP_BLOCK, codes.height) - 0.5f;
                const glm::vec3 a(x0, y0, 0.1f), b(x1, y0, 0.1f), c(x1, y1, 0.1f), d(x0, y1, 0.1f);
                outlines.insert(outlines.end(), {{a, b}, {b, c}, {c, d}, {d, a}});
            }
    }

    auto pct = [](double f) { return formatNumber(100.0 * f, 3) + "%"; };
    std::string caption = "skipped-pixels  " + l.desc->id + ", L" + std::to_string(ctx.request.light) +
                          ": evaluated " + pct(fraction) + " of the penumbra (" + std::to_string(evaluated) + " of " +
                          std::to_string(penumbra) + " pixels: eq. 6 " + std::to_string(n[SEL_SELECTED]) +
                          ", discontinuity " + std::to_string(n[SEL_FORCED]) + ", whole block " +
                          std::to_string(n[SEL_BLOCK]) + "); skipped " + std::to_string(skipped) +
                          ", filled by pull-push; lit " + std::to_string(n[SEL_LIT]) + ", umbra " +
                          std::to_string(n[SEL_UMBRA]) + ", background " + std::to_string(n[SEL_BACKGROUND]);
    if (occ) caption += "\n16x16 blocks: " + std::to_string(whole) + " processed whole (outlined), " +
                        std::to_string(compacted) + " compacted, " + std::to_string(empty) + " with no selected pixel";
    result.caption = caption;

    nlohmann::json counts = nlohmann::json::object();
    nlohmann::json legend = nlohmann::json::array();
    std::vector<LegendEntry> entries;
    for (const SelectionClass& c : classes()) {
        counts[std::to_string(c.code)] = n[size_t(c.code)];
        entries.push_back({c.rgb, std::string(c.label) + ": " + std::to_string(n[size_t(c.code)])});
        legend.push_back({{"code", c.code}, {"label", c.label}, {"count", n[size_t(c.code)]},
                          {"rgb", {c.rgb.r, c.rgb.g, c.rgb.b}}});
    }
    result.data = {{"counts", counts},
                   {"legend", legend},
                   {"evaluated", evaluated},
                   {"skipped", skipped},
                   {"penumbra", penumbra},
                   {"evaluated_fraction", fraction},
                   {"blocks", {{"whole", whole}, {"compacted", compacted}, {"skipped", empty}}},
                   {"whole_block_rgb", {kWholeBlockRgb.r, kWholeBlockRgb.g, kWholeBlockRgb.b}}};

    const std::string legendTitle = "pixels per class";
    const int legendW = legendWidthPx(legendTitle, entries, ctx.out.height());
    const double split = std::max(0.5, 1.0 - double(legendW) / ctx.out.width());
    // Picture pixels per frame pixel. Under 1 the panel cannot show every pixel (a nearest sample
    // of the dither pattern): the caption says so, so the counts stay the truth. The strip's height
    // as addCaptionStrip lays it out (the caption wrapped to the width).
    auto stripShare = [&](const std::string& text) { return captionStripLayout(ctx.out, text).share; };
    auto magnification = [&](double strip) {
        const double w = split * ctx.out.width(), h = (1.0 - strip) * ctx.out.height();
        const double titleShare = std::min(0.4, 1.6 * textPx(ctx.out.height()) / h);
        const double fitted = 0.5 * std::max<double>(codes.height, codes.width / (w / (h * (1.0 - titleShare)))) * 1.08;
        return h / (2.0 * fitted / (1.0 - titleShare));  // fitImage's parallel scale, grown for the title
    };
    const std::string note = "\nshown at " + formatNumber(100.0 * magnification(stripShare(caption + "\nshown at 99.9%: not every "
                             "pixel is drawn; the counts are of every pixel (a larger view or a smaller --size shows each)")), 3) +
                             "%: not every pixel is drawn; the counts are of every pixel (a larger view or a smaller --size "
                             "shows each)";
    if (magnification(stripShare(caption)) < 1.0) caption += note;
    result.caption = caption;
    result.data["magnification"] = magnification(stripShare(caption));
    const double strip = addCaptionStrip(ctx.out, caption);
    vtkRenderer* panel = ctx.out.addRenderer();
    panel->SetViewport(0.0, strip, split, 1.0);
    panel->SetBackground(0.12, 0.12, 0.14);
    auto image = toImageData(codes, {"code"});
    addImagePanel(panel, image, "code", classLut());
    // Every pixel whole, the border ones too: the picture's areas are the counts.
    vtkPropCollection* props = panel->GetViewProps();
    props->InitTraversal();
    for (vtkProp* p = props->GetNextProp(); p; p = props->GetNextProp())
        if (auto* a = vtkImageActor::SafeDownCast(p)) a->GetMapper()->BorderOn();
    // Room at the top for the title: the image moves down by the title's share of the panel.
    const double panelW = split * ctx.out.width(), panelH = (1.0 - strip) * ctx.out.height();
    const double titleShare = std::min(0.4, 1.6 * textPx(ctx.out.height()) / panelH);
    fitImage(panel, codes.width, codes.height, panelW / (panelH * (1.0 - titleShare)));
    {
        vtkCamera* camera = panel->GetActiveCamera();
        const double scale = camera->GetParallelScale() / (1.0 - titleShare), shift = scale * titleShare;
        double* f = camera->GetFocalPoint();
        double* p = camera->GetPosition();
        camera->SetParallelScale(scale);
        camera->SetFocalPoint(f[0], f[1] + shift, f[2]);
        camera->SetPosition(p[0], p[1] + shift, p[2]);
        // Where the frame lands in the picture (pixels, y from the top): [x0, y0, x1, y1], for
        // checking the picture pixel by pixel against the codes.
        const double px = panelH / (2.0 * scale), fx = camera->GetFocalPoint()[0], fy = camera->GetFocalPoint()[1];
        auto sx = [&](double wx) { return (wx - fx) * px + 0.5 * panelW; };
        auto sy = [&](double wy) { return ctx.out.height() - (strip * ctx.out.height() + (wy - fy) * px + 0.5 * panelH); };
        result.data["image_rect"] = {sx(-0.5), sy(codes.height - 0.5), sx(codes.width - 0.5), sy(-0.5)};
    }
    if (!outlines.empty()) panel->AddActor(lineActor(outlines, kWholeBlockRgb, 1.5f));
    panel->AddActor2D(titleActor("selection (sec. 5.2, 6)", ctx.out.height()));
    vtkRenderer* side = ctx.out.addRenderer();
    side->SetViewport(split, strip, 1.0, 1.0);
    side->SetBackground(0.12, 0.12, 0.14);
    // A short picture (a window cell) whose legend is taller than its panel lists only the classes
    // present (the others are nowhere in the picture; every count stays in the caption and data).
    std::vector<LegendEntry> drawnEntries = entries;
    const int sideW = ctx.out.width() - int(std::lround(split * ctx.out.width()));
    if (legendHeightPx(legendTitle, entries, ctx.out.height(), sideW) > panelH) {
        drawnEntries.clear();
        for (size_t i = 0; i < entries.size(); ++i)
            if (n[size_t(classes()[i].code)] > 0) drawnEntries.push_back(entries[i]);
    }
    addLegend(side, legendTitle, drawnEntries, ctx.out.height());
    if (!ctx.request.exportPath.empty()) writeImageData(image, ctx.exportTarget(ctx.request.exportPath));
}

}  // namespace

const ViewDesc& skippedPixelsView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "skipped-pixels";
        d.aspect = [](const Renderer&, const ViewRequest&, float frame) {  // the frame and its legend
            return frame * 1.6f * (1.0f - kCaptionShare);
        };
        d.info.doc = "which pixels the screen-space multi-resolution evaluated (selected by eq. 6, forced by a "
                     "discontinuity, with their whole block) and which it skipped for pull-push to fill, each class "
                     "in its colour with its count; blocks processed whole outlined";
        d.info.appliesTo = "techniques with a 'selection' internal while screen_adaptive is on (ssm-contour, ssm-gbp06)";
        d.info.exportExtension = ".vti";
        d.refusal = skippedPixelsRefusal;
        d.build = buildSkippedPixels;
        return d;
    }();
    return desc;
}

// ---- pull-push --------------------------------------------------------------------------------


namespace {

constexpr int kMaxColumns = 5;                    // levels drawn: the first four and the top
constexpr double kGap = 0.06;                     // between tiles, in tile widths / heights
constexpr double kGroupGap = 0.12;                // between the pull and the push
constexpr double kLayoutShare = 0.80;             // of the picture's width (the bars have the rest)
const char* const kNames[] = {"visibility_sparse", "pull_push.pull", "pull_push.push"};

std::string pullPushRefusal(const LightState& l, const ViewRequest& request) {
    return screenAdaptiveRefusal(l, request, {kNames[0], kNames[1], kNames[2]});
}

// The pull-push levels drawn, of `levels` (0 .. top): all when they fit, else the first
// kMaxColumns - 1 and the top.
std::vector<int> shownLevels(int levels) {
    std::vector<int> out;
    for (int k = 0; k < levels; ++k)
        if (levels <= kMaxColumns || k < kMaxColumns - 1 || k == levels - 1) out.push_back(k);
    return out;
}

// One tile: a 1-channel image placed so that it covers [x0, x0 + w] x [y0, y0 + h] (world units,
// level-0 pixels), whatever its resolution.
vtkSmartPointer<vtkImageActor> tileActor(const Image& level, vtkLookupTable* lut, double x0, double y0, double w, double h) {
    // An image actor draws nothing of an image one texel wide or high (the 1x1 top): such a level
    // is drawn with each texel repeated 2 x 2, the same picture.
    const int rep = level.width < 2 || level.height < 2 ? 2 : 1;
    Image values(level.width * rep, level.height * rep, 1);
    for (int y = 0; y < values.height; ++y)
        for (int x = 0; x < values.width; ++x) values.at(x, y) = level.at(x / rep, y / rep);
    auto data = toImageData(values, {"value"});
    const double sx = w / values.width, sy = h / values.height;
    data->SetSpacing(sx, sy, 1.0);
    data->SetOrigin(x0 + 0.5 * sx, y0 + 0.5 * sy, 0.0);  // a point is its texel's centre
    vtkNew<vtkImageMapToColors> colours;
    colours->SetInputData(data);
    colours->SetLookupTable(lut);
    colours->SetOutputFormatToRGB();
    auto actor = vtkSmartPointer<vtkImageActor>::New();
    actor->GetMapper()->SetInputConnection(colours->GetOutputPort());
    actor->InterpolateOff();         // a coarse level's texels stay squares
    actor->GetMapper()->BorderOn();  // the outer texels whole, not cut at their centres
    return actor;
}

vtkSmartPointer<vtkTextActor> worldText(const std::string& text, glm::dvec2 at, int font) {
    auto actor = vtkSmartPointer<vtkTextActor>::New();
    actor->SetInput(text.c_str());
    vtkTextProperty* p = actor->GetTextProperty();
    p->SetFontSize(font);
    p->SetFontFamilyToArial();
    p->SetColor(0.95, 0.95, 0.95);
    p->BoldOn();
    p->SetVerticalJustificationToTop();
    actor->GetPositionCoordinate()->SetCoordinateSystemToWorld();
    actor->GetPositionCoordinate()->SetValue(at.x, at.y, 0.5);
    return actor;
}

struct Level {
    int level;
    Image v, w;  // 1 channel each, as drawn (NaN: background; above 1: weight 0, drawn orange)
};

void buildPullPush(ViewContext& ctx, ViewResult& result) {
    const LightState& l = ctx.light();
    const CollectedInternal* in[3];
    for (int i = 0; i < 3; ++i) {
        in[i] = ctx.internal(kNames[i]);
        if (!in[i] || in[i]->levels.empty())
            throw InputError("view pull-push: technique " + l.desc->id + " wrote no '" + kNames[i] + "' this frame");
    }
    const Image& sparse = in[0]->levels[0];
    const std::vector<Image>& pull = in[1]->levels;  // pull-push levels 1 .. top
    const std::vector<Image>& push = in[2]->levels;
    if (pull.size() != push.size())
        throw InternalError("view pull-push: " + std::to_string(pull.size()) + " pull levels but " +
                            std::to_string(push.size()) + " push levels");
    const CollectedInternal* finalInternal = ctx.internal("visibility");
    const Image final = finalInternal && !finalInternal->levels.empty() ? finalInternal->levels[0] : ctx.renderer.visibility();
    const Image ids = ctx.renderer.ids();
    const int w0 = sparse.width, h0 = sparse.height;
    const bool idsFit = ids.width == w0 && ids.height == h0;
    const int levelCount = 1 + int(pull.size());

    // What each tile draws, level 0 (the frame) with the background grey.
    size_t skipped = 0, backgroundPixels = 0;
    auto channel = [&](const Image& src, int c, bool frame, bool markEmpty) {
        Image out(src.width, src.height, 1);
        for (int y = 0; y < src.height; ++y)
            for (int x = 0; x < src.width; ++x) {
                float v = src.at(x, y, c);
                if (markEmpty && !(src.at(x, y, 1) > 0.0f)) v = 2.0f;  // weight 0: above the range, orange
                if (frame && idsFit && ids.at(x, y) < 0.0f) v = NAN;
                out.at(x, y) = v;
            }
        return out;
    };
    std::vector<Level> pulled, pushed;
    {
        Level l0{0, channel(sparse, 0, true, true), channel(sparse, 1, true, false)};
        for (int y = 0; y < h0; ++y)
            for (int x = 0; x < w0; ++x) {
                if (idsFit && ids.at(x, y) < 0.0f) ++backgroundPixels;
                else if (!(sparse.at(x, y, 1) > 0.0f)) ++skipped;
            }
        pulled.push_back(l0);
        Image finalV(w0, h0, 1);
        for (int y = 0; y < h0; ++y)
            for (int x = 0; x < w0; ++x)
                finalV.at(x, y) = idsFit && ids.at(x, y) < 0.0f ? NAN : final.at(x, y, 0);
        pushed.push_back({0, finalV, l0.w});
    }
    nlohmann::json levelsData = nlohmann::json::array();
    levelsData.push_back({{"level", 0}, {"size", {w0, h0}}, {"skipped", skipped}});
    for (size_t m = 0; m < pull.size(); ++m) {
        size_t empty = 0;
        for (size_t i = 0; i < pull[m].pixelCount(); ++i)
            if (!(pull[m].data[i * size_t(pull[m].channels) + 1] > 0.0f)) ++empty;
        pulled.push_back({int(m) + 1, channel(pull[m], 0, false, true), channel(pull[m], 1, false, false)});
        pushed.push_back({int(m) + 1, channel(push[m], 0, false, false), channel(push[m], 1, false, false)});
        levelsData.push_back({{"level", m + 1}, {"size", {pull[m].width, pull[m].height}}, {"weight_zero", empty}});
    }
    const std::vector<int> shown = shownLevels(levelCount);
    std::vector<int> omitted;
    for (int k = 0; k < levelCount; ++k)
        if (std::find(shown.begin(), shown.end(), k) == shown.end()) omitted.push_back(k);

    auto sizeText = [](const Image& i) { return std::to_string(i.width) + "x" + std::to_string(i.height); };
    std::string caption = "pull-push  " + l.desc->id + ", L" + std::to_string(ctx.request.light) + ": " +
                          std::to_string(levelCount) + " levels (" + sizeText(sparse) + " .. " + sizeText(pull.back()) +
                          "); level 0: " + std::to_string(skipped) + " skipped pixels (weight 0, orange) filled by the push";
    if (!omitted.empty())
        caption += "; levels " + std::to_string(omitted.front()) + ".." + std::to_string(omitted.back()) +
                   " not shown (the first " + std::to_string(kMaxColumns - 1) + " and the 1x1 top are)";
    caption += "\n'Lk WxH': level k, W x H texels, each covering 2^k x 2^k pixels; the pull's visibility above its "
               "weight; the push keeps the pull's weights";
    result.caption = caption;
    nlohmann::json shownData = nlohmann::json::array();
    for (int k : shown) shownData.push_back(k);
    result.data = {{"levels", levelCount},   {"levels_shown", shownData}, {"levels_data", levelsData},
                   {"skipped", skipped},     {"background", backgroundPixels},
                   {"skipped_rgb", {kSkippedRgb.r, kSkippedRgb.g, kSkippedRgb.b}}};

    const double strip = addCaptionStrip(ctx.out, caption);
    auto visLut = paletteLut(Palette::Visibility, 0.0, 1.0);
    visLut->SetNanColor(kBackgroundGrey.r, kBackgroundGrey.g, kBackgroundGrey.b, 1.0);
    visLut->UseAboveRangeColorOn();
    visLut->SetAboveRangeColor(kSkippedRgb.r, kSkippedRgb.g, kSkippedRgb.b, 1.0);
    auto weightLut = paletteLut(Palette::Depth, 0.0, 1.0);
    weightLut->SetNanColor(kBackgroundGrey.r, kBackgroundGrey.g, kBackgroundGrey.b, 1.0);

    // The layout, in level-0 pixels: per group (pull, push) a header line, the columns' two-line
    // labels, the visibility row and the weight row. Text bands are fixed in picture pixels, so the
    // scale (pixels per world unit) comes first.
    const std::vector<LegendEntry> legend = {{kSkippedRgb, "weight 0 (skipped)"}};
    const int font = textPx(ctx.out.height());
    const int sideW = std::max({colourBarWidthPx(visLut, "visibility", ctx.out.height()),
                                colourBarWidthPx(weightLut, "weight", ctx.out.height()),
                                legendWidthPx("", legend, ctx.out.height())});
    const double layoutShare = std::min(kLayoutShare, 1.0 - double(sideW) / ctx.out.width());
    const double vw = layoutShare * ctx.out.width(), vh = (1.0 - strip) * ctx.out.height();
    const double line = 1.3 * font + 2.0, headerPx = line + 4.0, labelPx = line + 2.0;
    const int columns = int(shown.size());
    const double worldW = columns * w0 * (1.0 + kGap);
    const double tileRowsH = h0 * (3.0 + kGap + kGroupGap);  // pull v, pull w; push v
    const double fixedPx = 2.0 * (headerPx + labelPx) + 8.0;
    const double scale = std::max(1e-3, std::min((vw - 8.0) / worldW, (vh - fixedPx) / tileRowsH));  // px per unit
    const double header = headerPx / scale, label = labelPx / scale;
    const double tilePxW = w0 * scale;

    vtkRenderer* r = ctx.out.addRenderer();
    r->SetViewport(0.0, strip, layoutShare, 1.0);
    r->SetBackground(0.12, 0.12, 0.14);
    nlohmann::json drawn = nlohmann::json::array();
    double top = -4.0 / scale;  // y up, the layout's top at 0
    auto probe = worldText("", glm::dvec2(0.0), font);
    for (int g = 0; g < 2; ++g) {
        const bool isPull = g == 0;
        // The header: the first of its forms that fits the panel's width on one line (its band is one
        // line high; a narrow window cell wrapped the long form over the level labels).
        const std::string last = std::to_string(levelCount - 1);
        const std::vector<std::string> forms =
            isPull ? std::vector<std::string>{"pull: levels 0 (sparse) .. " + last + " (1x1)", "pull: levels 0 .. " + last, "pull"}
                   : std::vector<std::string>{"push: levels " + last + " .. 0 (final visibility)", "push: levels " + last + " .. 0", "push"};
        std::string title;
        for (const std::string& form : forms) {
            int tw = 0, th = 0;
            textExtent(probe->GetTextProperty(), form, tw, th);
            title = form;
            if (tw <= vw - 12.0) break;
        }
        r->AddActor2D(worldText(title, glm::dvec2(0.0, top), font));
        drawn.push_back({{"text", title}});
        top -= header;
        const double labelTop = top, vTop = top - label, wTop = vTop - h0 * (1.0 + kGap);  // wTop: the pull's
        for (int c = 0; c < columns; ++c) {
            const int k = isPull ? shown[size_t(c)] : shown[size_t(columns - 1 - c)];
            const Level& lv = isPull ? pulled[size_t(k)] : pushed[size_t(k)];
            const double x0 = c * w0 * (1.0 + kGap);
            r->AddActor(tileActor(lv.v, visLut.GetPointer(), x0, vTop - h0, w0, h0));
            if (isPull) r->AddActor(tileActor(lv.w, weightLut.GetPointer(), x0, wTop - h0, w0, h0));
            // The label: the first that fits the column at the standard's font.
            const std::string size = sizeText(lv.v), lk = "L" + std::to_string(k);
            std::string text;
            for (const std::string& candidate : {"level " + std::to_string(k) + ", " + size, lk + " " + size, lk}) {
                int tw = 0, th = 0;
                textExtent(probe->GetTextProperty(), candidate, tw, th);
                text = candidate;
                if (tw <= tilePxW * (1.0 + kGap) - 4.0 && th <= labelPx) break;
            }
            r->AddActor2D(worldText(text, glm::dvec2(x0, labelTop), font));
            drawn.push_back({{"group", isPull ? "pull" : "push"}, {"level", k}, {"text", text}});
        }
        top = (isPull ? wTop : vTop) - h0 - h0 * kGroupGap;
    }
    result.data["labels"] = drawn;
    result.data["tile_px"] = {tilePxW, h0 * scale};

    vtkCamera* camera = r->GetActiveCamera();
    camera->ParallelProjectionOn();
    const double cx = 0.5 * vw / scale - 6.0 / scale, cy = -0.5 * vh / scale;  // the layout's top-left 6 px in
    camera->SetFocalPoint(cx, cy, 0.0);
    camera->SetPosition(cx, cy, 10.0 * std::max(w0, h0));
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(0.5 * vh / scale / ctx.request.zoom);
    r->ResetCameraClippingRange();

    // Beside it: the visibility bar, the weight bar and the orange mark's legend.
    const double legendShare = std::min(0.3, double(legendHeightPx("", legend, ctx.out.height(), sideW)) / vh);
    const double y1 = strip + (1.0 - strip) * legendShare, ym = y1 + 0.5 * (1.0 - y1);
    vtkRenderer* bars[2];
    for (int i = 0; i < 2; ++i) {
        bars[i] = ctx.out.addRenderer();
        bars[i]->SetViewport(layoutShare, i == 0 ? ym : y1, 1.0, i == 0 ? 1.0 : ym);
        bars[i]->SetBackground(0.12, 0.12, 0.14);
    }
    addColourBar(bars[0], visLut, "visibility", ctx.out.height());
    addColourBar(bars[1], weightLut, "weight", ctx.out.height());
    vtkRenderer* key = ctx.out.addRenderer();
    key->SetViewport(layoutShare, strip, 1.0, y1);
    key->SetBackground(0.12, 0.12, 0.14);
    addLegend(key, "", legend, ctx.out.height());
    // Export: level 0, the sparse input and the final visibility.
    if (!ctx.request.exportPath.empty()) {
        Image out(w0, h0, 3);
        for (int y = 0; y < h0; ++y)
            for (int x = 0; x < w0; ++x) {
                out.at(x, y, 0) = sparse.at(x, y, 0);
                out.at(x, y, 1) = sparse.at(x, y, 1);
                out.at(x, y, 2) = final.at(x, y, 0);
            }
        writeImageData(toImageData(out, {"visibility_sparse", "weight", "visibility"}), ctx.exportTarget(ctx.request.exportPath));
    }
}

}  // namespace

const ViewDesc& pullPushView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "pull-push";
        // Up to five frame-shaped columns, three rows of tiles and their text bands, bars beside.
        d.aspect = [](const Renderer& r, const ViewRequest&, float frame) {
            int levels = 1;
            for (int n = std::max(r.width(), r.height()); n > 1; n = (n + 1) / 2) ++levels;
            const int columns = std::min(levels, kMaxColumns);
            return float(columns * (1.0 + kGap) * frame / (3.0 + kGap + kGroupGap) / 1.3 / kLayoutShare *
                         (1.0 - kCaptionShare));
        };
        d.info.doc = "the pull-push reconstruction level by level: the pull from the sparse v-buffer (skipped pixels, "
                     "weight 0, orange) up to 1x1, then the push back down to the final visibility, each level's "
                     "visibility above its weight";
        d.info.appliesTo = "techniques with 'visibility_sparse' and the 'pull_push' pyramids while screen_adaptive is on "
                           "(ssm-contour, ssm-gbp06)";
        d.info.exportExtension = ".vti";
        d.refusal = pullPushRefusal;
        d.build = buildPullPush;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
