#include "window/layout.h"

#include <algorithm>
#include <cmath>

namespace shadowlab {

bool LayoutRect::intersects(const LayoutRect& o) const {
    if (empty() || o.empty()) return false;
    return x < o.right() && o.x < right() && y < o.bottom() && o.y < bottom();
}

bool LayoutRect::inside(glm::vec2 window) const {
    const float eps = 1e-3f;
    return x >= -eps && y >= -eps && right() <= window.x + eps && bottom() <= window.y + eps;
}

float presentationUiScale(float windowHeight) {
    // ImGui's default font is 13 px at scale 1: 13 s >= h / 40.
    return std::clamp(std::ceil(windowHeight / 40.0f / 13.0f * 4.0f) / 4.0f, 1.0f, 8.0f);
}

namespace {

// The views strip: n cells of the given aspects (image width / height, plus a caption band of
// `caption` under each image) in the width `width`, at most `maxHeight` tall. Tries every number of
// rows and keeps the one with the tallest images; rows are filled left to right and centred.
struct Strip {
    std::vector<LayoutRect> cells;  // relative to the strip's top-left
    float height = 0.0f;
    int rows = 0;
};

Strip layoutStrip(const std::vector<float>& aspects, float width, float maxHeight, float gap, float caption) {
    Strip best;
    const int n = int(aspects.size());
    if (n == 0 || width <= 0.0f || maxHeight <= caption) return best;
    float bestImage = -1.0f;
    for (int rows = 1; rows <= n; ++rows) {
        const int perRow = (n + rows - 1) / rows;
        // The image height every row fits: its aspects' sum times h plus the gaps within the width.
        float image = (maxHeight - gap * float(rows - 1)) / float(rows) - caption;
        for (int r = 0; r < rows; ++r) {
            float sum = 0.0f;
            int count = 0;
            for (int i = r * perRow; i < std::min(n, (r + 1) * perRow); ++i) sum += std::max(aspects[size_t(i)], 0.05f), ++count;
            if (count > 0) image = std::min(image, (width - gap * float(count - 1)) / sum);
        }
        if (image > bestImage + 0.5f) {
            bestImage = image;
            best.rows = rows;
        }
    }
    if (bestImage <= 1.0f) return Strip{};
    const int perRow = (n + best.rows - 1) / best.rows;
    const float cellH = bestImage + caption;
    for (int r = 0; r < best.rows; ++r) {
        float rowWidth = 0.0f;
        const int first = r * perRow, last = std::min(n, (r + 1) * perRow);
        for (int i = first; i < last; ++i) rowWidth += std::max(aspects[size_t(i)], 0.05f) * bestImage + (i > first ? gap : 0.0f);
        float x = std::max(0.0f, 0.5f * (width - rowWidth));
        for (int i = first; i < last; ++i) {
            const float w = std::max(aspects[size_t(i)], 0.05f) * bestImage;
            best.cells.push_back({x, float(r) * (cellH + gap), w, cellH});
            x += w + gap;
        }
    }
    best.height = float(best.rows) * cellH + gap * float(best.rows - 1);
    return best;
}

}  // namespace

WindowLayout computeWindowLayout(const LayoutInput& in) {
    WindowLayout out;
    const float W = std::max(in.window.x, 1.0f), H = std::max(in.window.y, 1.0f);
    const float s = std::max(in.uiScale, 0.25f);
    const float gap = std::round(4.0f * s);
    const float line = 17.0f * s;  // one line of 13 px text with ImGui's spacing, scaled

    // The status line along the bottom.
    const float statusH = std::min(std::round(line + 4.0f * s), 0.06f * H);
    out.status = {0.0f, H - statusH, W, statusH};
    const float top = 0.0f, bottom = out.status.y - gap;

    // The right column: the lesson's narration.
    float right = W;
    if (in.lesson) {
        const float w = in.present ? std::round(W / 3.0f) : std::round(std::min(std::max(440.0f * s, 240.0f), 0.28f * W));
        out.lesson = {W - w, top, w, bottom - top};
        right = out.lesson.x - gap;
    }

    // The left column: the control panel over the HUD (normal mode).
    float left = 0.0f;
    float techniqueTop = top;
    // With the panel hidden (Tab) the HUD leaves the column: it sits at the left of the bottom row,
    // beside the views, and the technique view takes the whole width above.
    const bool hudInRow = !in.present && !in.panel && in.hud;
    if (!in.present && in.panel) {
        const float w = std::round(std::min(std::max(340.0f * s, 200.0f), 0.24f * W));
        const float hudH = in.hud ? std::round(std::min(10.0f * line + 12.0f * s, 0.4f * (bottom - top))) : 0.0f;
        if (in.hud) out.hud = {0.0f, bottom - hudH, w, hudH};
        if (in.panel) out.panel = {0.0f, top, w, (in.hud ? out.hud.y - gap : bottom) - top};
        left = w + gap;
    }
    // Presentation: the panel is one line over the technique view, the HUD one line under it.
    if (in.present) {
        const float bar = std::round(line + 10.0f * s);
        if (in.panel) {
            out.panel = {left, top, right - left, bar};
            techniqueTop = out.panel.bottom() + gap;
        }
        if (in.hud) {
            out.hud = {left, techniqueTop, right - left, bar};
            techniqueTop = out.hud.bottom() + gap;
        }
    }

    // The views strip under the technique view, at most 36% of the height (the view keeps more).
    float techniqueBottom = bottom;
    float rowLeft = left;
    if (hudInRow) {
        const float w = std::round(std::min(std::max(340.0f * s, 200.0f), 0.24f * W));
        const float hudH = std::round(std::min(7.0f * line + 12.0f * s, 0.25f * (bottom - top)));
        out.hud = {0.0f, bottom - hudH, w, hudH};
        rowLeft = w + gap;
    }
    if (!in.cellAspects.empty()) {
        const float width = right - rowLeft;
        const float maxHeight = std::min(0.36f * H, std::max(0.0f, techniqueBottom - techniqueTop - 0.3f * H));
        // Under each image only its title line (the view draws its caption inside the picture) and
        // the first view's pick hint.
        Strip strip = layoutStrip(in.cellAspects, width, maxHeight, gap, std::round(2.0f * line + 6.0f * s));
        if (!strip.cells.empty()) {
            out.strip = {rowLeft, techniqueBottom - strip.height, width, strip.height};
            out.stripRows = strip.rows;
            for (LayoutRect c : strip.cells) {
                c.x += out.strip.x;
                c.y += out.strip.y;
                out.cells.push_back(c);
            }
            techniqueBottom = out.strip.y - gap;
        }
        out.cells.resize(in.cellAspects.size());  // a view that does not fit gets an empty cell
    }
    // The bottom row is as tall as the taller of the HUD and the strip.
    if (hudInRow) techniqueBottom = std::min(techniqueBottom, out.hud.y - gap);
    out.technique = {left, techniqueTop, std::max(0.0f, right - left), std::max(0.0f, techniqueBottom - techniqueTop)};
    return out;
}

std::vector<std::pair<std::string, LayoutRect>> WindowLayout::regions() const {
    std::vector<std::pair<std::string, LayoutRect>> out;
    for (const auto& [name, r] : std::vector<std::pair<std::string, LayoutRect>>{
             {"panel", panel}, {"hud", hud}, {"lesson", lesson}, {"technique", technique}, {"status", status}})
        if (!r.empty()) out.push_back({name, r});
    for (size_t i = 0; i < cells.size(); ++i)
        if (!cells[i].empty()) out.push_back({"cell " + std::to_string(i), cells[i]});
    return out;
}

nlohmann::json WindowLayout::toJson() const {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [name, r] : regions()) j[name] = {r.x, r.y, r.w, r.h};
    j["strip_rows"] = stripRows;
    return j;
}

}  // namespace shadowlab
