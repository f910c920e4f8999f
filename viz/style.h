// The text and layout standard of every view and chart (issue 19; viz/README.md "Text and
// colour"): text sizes from the picture's height, word wrapping measured with VTK's own text
// renderer, colour bars laid out from their labels' measured boxes (a title that never overlaps
// its ticks, ticks never clipped, the background's grey stated), one palette per quantity, and the
// record of every text drawn (textLayout) that the tests check.
//
//   const int px = textPx(out.height());                        // >= 14, >= height / 30
//   auto lut = paletteLut(Palette::Depth, lo, hi);              // NaN: kBackgroundGrey
//   int w = colourBarWidthPx(lut, "light-view depth z", out.height());
//   addColourBar(sideRenderer, lut, "light-view depth z", out.height());
//   std::vector<TextBox> boxes = textLayout(out);               // after out.render()
#pragma once
#include <vtkLookupTable.h>
#include <vtkSmartPointer.h>

#include <string>
#include <vector>

#include "image/palette.h"
#include "text_box.h"

class vtkRenderer;
class vtkTextProperty;

namespace shadowlab {

class VtkOffscreen;

// The standard's smallest text: never under 14 px, and at least 1/30 of the picture's height
// (16 px at the default 640x480, 32 px at 1280x960).
constexpr int kMinTextPx = 14;
int textPx(int frameHeight);

// The width and height in pixels `text` takes with `property` (lines split at '\n').
void textExtent(vtkTextProperty* property, const std::string& text, int& width, int& height);
// `text` with its lines wrapped at spaces (then after '/', ',', '_', '-', then anywhere) so that every
// line is at most maxWidth pixels wide with `property`.
std::string wrapText(vtkTextProperty* property, const std::string& text, int maxWidth);

// A lookup table of 256 colours of `palette` over [lo, hi] (SignedError: [-maxAbs, maxAbs]), NaN
// kBackgroundGrey. A range of zero width is widened a little so the bar still reads its value.
vtkSmartPointer<vtkLookupTable> paletteLut(Palette palette, double lo, double hi);

// A colour bar drawn into `renderer` (its whole viewport, which must already be placed in the
// window): title on top (wrapped to the width), the colour strip with tick labels beside it
// (vertical) or under it (horizontal), and a grey swatch "no data" when the table's NaN colour is
// the background grey. Tick count and positions come from the labels' measured boxes: never
// overlapping one another, the title or the swatch, never outside the viewport.
void addColourBar(vtkRenderer* renderer, vtkLookupTable* lut, const std::string& title, int frameHeight,
                  bool horizontal = false);
// The labels of n ticks evenly over [lo, hi]: three significant digits, more (up to nine) where
// three would print two neighbouring ticks alike (a depth range of 1.99 .. 2.01 reads 1.99, 1.995,
// 2, 2.005, 2.01, not 1.99, 1.99, 2, 2, 2.01).
std::vector<std::string> colourBarTickLabels(double lo, double hi, int n);
// The width a vertical colour bar needs so that its labels and the title's longest word fit.
int colourBarWidthPx(vtkLookupTable* lut, const std::string& title, int frameHeight);

// A legend of categories (the skipped-pixels classes, the pull-push view's marks): drawn into
// `renderer`'s whole viewport (already placed in the window): the title on top, wrapped to the
// width, then one row per entry, a swatch of its colour and its text, at the standard's size
// (textPx), wrapped to the width when it is wider (its row grows). legendWidthPx / legendHeightPx: what the legend needs for its widest row and its rows.
struct LegendEntry {
    glm::vec3 rgb;
    std::string text;
};
void addLegend(vtkRenderer* renderer, const std::string& title, const std::vector<LegendEntry>& entries, int frameHeight);
int legendWidthPx(const std::string& title, const std::vector<LegendEntry>& entries, int frameHeight);
int legendHeightPx(const std::string& title, const std::vector<LegendEntry>& entries, int frameHeight, int widthPx);
// Every text actor of the frame with its box (text_box.h). Valid after a render.
std::vector<TextBox> textLayout(VtkOffscreen& out);
// Problems of a layout against the standard, one line each ("" when none): two boxes overlapping, a
// box outside the picture or its viewport, a font under textPx(height).
std::string layoutProblems(const std::vector<TextBox>& boxes, int width, int height);

// Wraps every text actor of the frame wider than its viewport to the viewport's width (titles made
// before the viewport's size was known). renderView calls it before rendering.
void wrapTextsToViewports(VtkOffscreen& out);

}  // namespace shadowlab
