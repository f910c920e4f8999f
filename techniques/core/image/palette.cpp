#include "image/palette.h"

#include <algorithm>
#include <cmath>

namespace shadowlab {

namespace {

// Piecewise-linear interpolation through `n` evenly spaced stops.
template <size_t N>
glm::vec3 stops(const float (&table)[N][3], float t) {
    const float x = t * float(N - 1);
    const int i = std::clamp(int(std::floor(x)), 0, int(N) - 2);
    const float f = std::clamp(x - float(i), 0.0f, 1.0f);
    return glm::mix(glm::vec3(table[i][0], table[i][1], table[i][2]),
                    glm::vec3(table[i + 1][0], table[i + 1][1], table[i + 1][2]), f);
}

// matplotlib's viridis and plasma at 8 stops (sRGB), ordered in lightness.
const float kViridis[8][3] = {{0.267f, 0.005f, 0.329f}, {0.275f, 0.194f, 0.496f}, {0.213f, 0.359f, 0.552f},
                              {0.153f, 0.498f, 0.558f}, {0.122f, 0.632f, 0.531f}, {0.290f, 0.762f, 0.428f},
                              {0.622f, 0.854f, 0.223f}, {0.993f, 0.906f, 0.144f}};
const float kPlasma[8][3] = {{0.050f, 0.030f, 0.528f}, {0.327f, 0.007f, 0.640f}, {0.546f, 0.039f, 0.647f},
                             {0.723f, 0.196f, 0.538f}, {0.859f, 0.360f, 0.408f}, {0.955f, 0.533f, 0.285f},
                             {0.994f, 0.737f, 0.160f}, {0.940f, 0.975f, 0.131f}};
// Black -> brown -> cream: the lightness of a grey visibility image, with enough chroma in the
// middle that no value looks like the neutral background grey.
const float kVisibility[5][3] = {{0.0f, 0.0f, 0.0f}, {0.30f, 0.13f, 0.04f}, {0.62f, 0.36f, 0.12f},
                                 {0.88f, 0.68f, 0.38f}, {1.0f, 0.97f, 0.88f}};

// Inferno, the CC0 polynomial fit by Matt Zucker of matplotlib's table.
glm::vec3 inferno(float t) {
    static const double c[7][3] = {
        {0.0002189403691192265, 0.001651004631001012, -0.01948089843709184},
        {0.1065134194856116, 0.5639564367884091, 3.932712388889277},
        {11.60249308247187, -3.972853965665698, -15.9423941062914},
        {-41.70399613139459, 17.43639888205313, 44.35414519872813},
        {77.162935699427, -33.40235894210092, -81.80730925738993},
        {-71.31942824499214, 32.62606426397723, 73.20951985803202},
        {25.13112622477341, -12.24266895238567, -23.07032500287172},
    };
    glm::vec3 rgb;
    for (int k = 0; k < 3; ++k) {
        double v = c[6][k];
        for (int p = 5; p >= 0; --p) v = c[p][k] + t * v;
        rgb[k] = float(std::clamp(v, 0.0, 1.0));
    }
    return rgb;
}

}  // namespace

glm::vec3 paletteColour(Palette palette, float t) {
    if (!std::isfinite(t)) return kBackgroundGrey;
    t = std::clamp(t, 0.0f, 1.0f);
    switch (palette) {
        case Palette::Visibility: return stops(kVisibility, t);
        case Palette::SignedError: {
            // Moreland's cool-warm end points through a white centre.
            const glm::vec3 blue(0.230f, 0.299f, 0.754f), white(0.97f), red(0.706f, 0.016f, 0.150f);
            const float s = t * 2.0f - 1.0f;
            return s < 0.0f ? glm::mix(white, blue, -s) : glm::mix(white, red, s);
        }
        case Palette::AbsoluteError: return inferno(t);
        case Palette::Depth: return stops(kViridis, t);
        case Palette::KernelSize: return stops(kPlasma, t);
    }
    return kBackgroundGrey;
}

const char* paletteName(Palette palette) {
    switch (palette) {
        case Palette::Visibility: return "visibility (black - brown - cream)";
        case Palette::SignedError: return "signed error (blue - white - red)";
        case Palette::AbsoluteError: return "absolute error (inferno)";
        case Palette::Depth: return "depth and other quantities (viridis)";
        case Palette::KernelSize: return "kernel size (plasma)";
    }
    return "";
}

}  // namespace shadowlab
