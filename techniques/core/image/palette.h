// One palette per kind of quantity (issue 19, viz/README.md "Colours"): every view, chart, figure
// and heat map colours a quantity by its kind through this file, so a picture's colours mean the
// same thing everywhere, and pixels with no data (background: no geometry, NaN) take the one
// colour no palette reaches, kBackgroundGrey, which every colour bar states.
//
//   glm::vec3 c = paletteColour(Palette::AbsoluteError, e / maxError);   // t in [0, 1]
//   glm::vec3 g = kBackgroundGrey;                                       // NaN / no geometry
#pragma once
#include <glm/glm.hpp>
#include <string>

namespace shadowlab {

enum class Palette {
    Visibility,     // black -> brown -> cream (0 = umbra, 1 = lit): never neutral grey
    SignedError,    // diverging blue (v < v_ref) -> white (0) -> red (v > v_ref), Moreland's cool-warm
    AbsoluteError,  // inferno (black at 0 -> pale yellow at the largest error)
    Depth,          // viridis (dark blue near -> yellow far); also any other internal quantity
    KernelSize,     // plasma (blue small -> yellow large)
};

// The neutral mid grey of "no data" (sRGB 0.5, 128/255 in 8 bits). No palette comes within 0.08 of
// it in any channel-sum distance (tested: tests/core/test_metrics.cpp, PalettesNeverReachTheBackgroundGrey).
inline constexpr glm::vec3 kBackgroundGrey{0.5f, 0.5f, 0.5f};

// The palette's colour at t (clamped to [0, 1]; SignedError: 0 is the blue end, 0.5 white, 1 red).
// NaN gives kBackgroundGrey.
glm::vec3 paletteColour(Palette palette, float t);
// "visibility", "signed error", ... and the map's name ("inferno"), for captions and the README.
const char* paletteName(Palette palette);

}  // namespace shadowlab
