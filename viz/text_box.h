// One text drawn in a view or chart, with its box in pixels: the layout record the text standard's
// tests check (style.h: textLayout, layoutProblems). No VTK here, so app code can hold it.
#pragma once
#include <string>

namespace shadowlab {

// x right, y down from the picture's top left; the renderer's viewport in the same convention.
struct TextBox {
    std::string text;
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;      // [x0, x1) x [y0, y1)
    int fontPx = 0;
    int vx0 = 0, vy0 = 0, vx1 = 0, vy1 = 0;  // the renderer's viewport
};

}  // namespace shadowlab
