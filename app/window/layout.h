// The window's docked layout (issue 18): fixed regions computed every frame from the window's size
// and UI scale (ImGui 1.86 has no docking branch), so that no panel ever covers the technique view
// and nothing is cut off at the window's edge.
//
//   +---------+----------------------------------+------------+
//   | panel   | technique view                   | lesson     |
//   |         |                                  | narration  |
//   |---------|                                  | (only with |
//   | HUD     +----------------------------------+  a lesson) |
//   |         | views strip (each at its aspect) |            |
//   +---------+----------------------------------+------------+
//   | status line                                              |
//   +----------------------------------------------------------+
//
// The left column holds the control panel over the HUD (Tab hides the panel, the HUD stays); the
// lesson's column is on the right; the open views (and the accuracy chart) share a strip under the
// technique view, each cell at its own aspect, in as many rows as gives the largest cells. The
// technique view is what is left; the renderer renders at its size, so it keeps the render's
// aspect. In presentation mode the panel is a one-line bar over the technique view, the lesson's
// column a third of the width, the HUD one line. Pure: unit-tested without a window.
#pragma once
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace shadowlab {

struct LayoutRect {
    float x = 0, y = 0, w = 0, h = 0;  // window units, origin top-left, y down
    bool empty() const { return w <= 0.0f || h <= 0.0f; }
    float area() const { return empty() ? 0.0f : w * h; }
    float right() const { return x + w; }
    float bottom() const { return y + h; }
    bool intersects(const LayoutRect& o) const;  // interiors overlap (touching edges do not)
    bool inside(glm::vec2 window) const;         // within [0, window]
    bool contains(glm::vec2 p) const { return p.x >= x && p.y >= y && p.x < right() && p.y < bottom(); }
};

struct LayoutInput {
    glm::vec2 window{1024, 768};
    float uiScale = 1.0f;
    bool panel = true;       // the control panel is shown (Tab)
    bool hud = true;         // the HUD is shown
    bool lesson = false;     // a lesson is open
    bool present = false;    // presentation mode (--present, F5)
    std::vector<float> cellAspects;  // width / height of each open view, then the accuracy chart
};

struct WindowLayout {
    LayoutRect panel, hud, lesson, technique, strip, status;
    std::vector<LayoutRect> cells;  // one per LayoutInput::cellAspects, in order
    int stripRows = 0;
    // Every non-empty region by name ("panel", "hud", "lesson", "technique", "strip", "status",
    // "cell 0", ...) for --report and the tests.
    std::vector<std::pair<std::string, LayoutRect>> regions() const;
    nlohmann::json toJson() const;
};

WindowLayout computeWindowLayout(const LayoutInput& in);

// Presentation mode's UI scale: body text (13 px at scale 1) at least 1/40 of the window's height.
float presentationUiScale(float windowHeight);

}  // namespace shadowlab
