// Error metrics on visibility buffers (DESIGN.md section 3) and the error heat map.
//
// Every metric compares v, never the shaded image. A pixel takes part when both values are finite
// (background pixels hold v = 1 in both, NaN marks "no data") and the mask, if any, selects it.
#include "image/metrics.h"

#include "image/palette.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "error.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_easy_font.h>  // all static functions: no implementation define needed
#pragma GCC diagnostic pop

namespace shadowlab {

namespace {

void checkPair(const Image& test, const Image& reference) {
    if (test.width != reference.width || test.height != reference.height) {
        throw InputError("images differ in size: " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                         " vs " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
    }
    if (test.channels != 1 || reference.channels != 1) {
        throw InputError("expected 1-channel visibility images, got " + std::to_string(test.channels) + " and " +
                         std::to_string(reference.channels) + " channels");
    }
}

bool bothFinite(float a, float b) { return std::isfinite(a) && std::isfinite(b); }

// SSIM constants (Wang, Bovik, Sheikh and Simoncelli 2004, "Image Quality Assessment: From Error
// Visibility to Structural Similarity", section III.B): C1 = (K1 L)^2, C2 = (K2 L)^2 with L = 1
// for visibility in [0,1]; the local statistics use an 11x11 circular-symmetric Gaussian window of
// standard deviation 1.5 (section III.C).
constexpr double kSsimK1 = 0.01;
constexpr double kSsimK2 = 0.03;
constexpr double kSsimL = 1.0;
constexpr double kSsimC1 = (kSsimK1 * kSsimL) * (kSsimK1 * kSsimL);
constexpr double kSsimC2 = (kSsimK2 * kSsimL) * (kSsimK2 * kSsimL);
constexpr int kSsimRadius = 5;  // 11 taps
constexpr double kSsimSigma = 1.5;

// Mean SSIM over the pixels that `take(i)` selects.
//
// The window is the product g(dx) g(dy) of 1-D Gaussians, and every window only uses pixels where
// both images are finite and that lie inside the image: those pixels get weight g(dx) g(dy) and
// the weights are renormalised to sum 1. (Wang et al. evaluate only windows that fit entirely
// inside the image; renormalising instead gives every pixel an SSIM value, including the border
// and pixels next to the background, and equals their definition wherever the full window fits.)
// Because the mask m of finite pixels multiplies the data pixel by pixel, the weighted sums
// S[f] = sum g(dx) g(dy) m f are separable: one horizontal and one vertical 11-tap pass over the
// six fields m, m x, m y, m x^2, m y^2, m x y. Sums are in double, so the variance formula
// sigma^2 = E[x^2] - mu^2 loses nothing that matters for values in [0,1].
template <typename Take>
double meanSsim(const Image& x, const Image& y, Take take) {
    const int w = x.width;
    const int h = x.height;
    std::array<double, 2 * kSsimRadius + 1> g{};
    for (int k = -kSsimRadius; k <= kSsimRadius; ++k) {
        g[k + kSsimRadius] = std::exp(-double(k * k) / (2.0 * kSsimSigma * kSsimSigma));
    }

    constexpr int kFields = 6;
    // Horizontal sums of one row, ring-buffered over the 11 rows the vertical pass needs.
    constexpr int kRing = 2 * kSsimRadius + 1;
    std::vector<double> ring(size_t(kRing) * w * kFields, 0.0);
    std::vector<int> ringRow(kRing, -1);
    std::vector<double> fields(size_t(w) * kFields);

    auto horizontalRow = [&](int row) -> const double* {
        int slot = row % kRing;
        double* out = ring.data() + size_t(slot) * w * kFields;
        if (ringRow[slot] == row) return out;
        ringRow[slot] = row;
        for (int i = 0; i < w; ++i) {
            float a = x.at(i, row);
            float b = y.at(i, row);
            double* f = fields.data() + size_t(i) * kFields;
            if (bothFinite(a, b)) {
                f[0] = 1.0;
                f[1] = a;
                f[2] = b;
                f[3] = double(a) * a;
                f[4] = double(b) * b;
                f[5] = double(a) * b;
            } else {
                std::fill(f, f + kFields, 0.0);
            }
        }
        for (int i = 0; i < w; ++i) {
            double sum[kFields] = {};
            int k0 = std::max(-kSsimRadius, -i);
            int k1 = std::min(kSsimRadius, w - 1 - i);
            for (int k = k0; k <= k1; ++k) {
                const double gk = g[k + kSsimRadius];
                const double* f = fields.data() + size_t(i + k) * kFields;
                for (int c = 0; c < kFields; ++c) sum[c] += gk * f[c];
            }
            std::copy(sum, sum + kFields, out + size_t(i) * kFields);
        }
        return out;
    };

    double total = 0.0;
    for (int j = 0; j < h; ++j) {
        int k0 = std::max(-kSsimRadius, -j);
        int k1 = std::min(kSsimRadius, h - 1 - j);
        // Rows j-5 .. j+5 fall in 11 distinct ring slots, so none evicts another.
        std::array<const double*, kRing> rows{};
        for (int k = k0; k <= k1; ++k) rows[k + kSsimRadius] = horizontalRow(j + k);
        for (int i = 0; i < w; ++i) {
            if (!take(size_t(j) * w + i)) continue;
            double s[kFields] = {};
            for (int k = k0; k <= k1; ++k) {
                const double gk = g[k + kSsimRadius];
                const double* f = rows[k + kSsimRadius] + size_t(i) * kFields;
                for (int c = 0; c < kFields; ++c) s[c] += gk * f[c];
            }
            // s[0] > 0 because the centre pixel itself is finite (take() only selects such pixels).
            const double muX = s[1] / s[0];
            const double muY = s[2] / s[0];
            const double varX = s[3] / s[0] - muX * muX;
            const double varY = s[4] / s[0] - muY * muY;
            const double covXY = s[5] / s[0] - muX * muY;
            // Wang et al. 2004 eq. 13.
            const double ssim = ((2.0 * muX * muY + kSsimC1) * (2.0 * covXY + kSsimC2)) /
                                ((muX * muX + muY * muY + kSsimC1) * (varX + varY + kSsimC2));
            total += ssim;
        }
    }
    return total;
}

void fillRect(Image& image, int x0, int y0, int x1, int y1, const float rgb[3]) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, image.width);
    y1 = std::min(y1, image.height);
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            for (int c = 0; c < 3; ++c) image.at(x, y, c) = rgb[c];
        }
    }
}

int textWidth(const std::string& text) { return stb_easy_font_width(const_cast<char*>(text.c_str())); }
int textHeight(const std::string& text) { return stb_easy_font_height(const_cast<char*>(text.c_str())); }

// Rasterises text with stb_easy_font (which emits axis-aligned quads in font units, y down) at an
// integer scale, its top-left corner at (left, top); clipped to the image.
void drawText(Image& image, const std::string& text, int left, int top, int scale, const float rgb[3]) {
    struct Vertex {
        float x, y, z;
        unsigned char color[4];
    };
    std::vector<Vertex> quads(text.size() * 80 + 64);  // stb_easy_font needs ~270 bytes per character
    int n = stb_easy_font_print(0.0f, 0.0f, const_cast<char*>(text.c_str()), nullptr, quads.data(),
                                int(quads.size() * sizeof(Vertex)));
    for (int q = 0; q < n; ++q) {
        const Vertex* v = &quads[size_t(q) * 4];
        float qx0 = std::min({v[0].x, v[1].x, v[2].x, v[3].x});
        float qx1 = std::max({v[0].x, v[1].x, v[2].x, v[3].x});
        float qy0 = std::min({v[0].y, v[1].y, v[2].y, v[3].y});
        float qy1 = std::max({v[0].y, v[1].y, v[2].y, v[3].y});
        fillRect(image, left + int(std::lround(qx0 * scale)), top + int(std::lround(qy0 * scale)),
                 left + int(std::lround(qx1 * scale)), top + int(std::lround(qy1 * scale)), rgb);
    }
}

}  // namespace

std::vector<uint8_t> penumbraMask(const Image& reference) {
    std::vector<uint8_t> mask(reference.pixelCount(), 0);
    for (size_t i = 0; i < mask.size(); ++i) {
        float v = reference.data[i * reference.channels];
        // NaN fails both comparisons, so "no data" is never penumbra.
        mask[i] = (v > kPenumbraEpsilon && v < 1.0f - kPenumbraEpsilon) ? 1 : 0;
    }
    return mask;
}

Metrics computeMetrics(const Image& test, const Image& reference, const std::vector<uint8_t>* mask) {
    checkPair(test, reference);
    const size_t count = test.pixelCount();
    if (mask && mask->size() != count) {
        throw InputError("mask has " + std::to_string(mask->size()) + " entries, expected " + std::to_string(count) +
                         " (" + std::to_string(test.width) + "x" + std::to_string(test.height) + ")");
    }
    auto take = [&](size_t i) {
        return (!mask || (*mask)[i] != 0) && bothFinite(test.data[i], reference.data[i]);
    };

    Metrics m;
    double sumSquared = 0.0;
    for (size_t i = 0; i < count; ++i) {
        if (!take(i)) continue;
        double e = std::abs(double(test.data[i]) - double(reference.data[i]));
        sumSquared += e * e;
        m.maxAbs = std::max(m.maxAbs, e);
        ++m.pixels;
    }
    if (m.pixels == 0) {
        // Nothing to compare (an empty penumbra, say): report "no difference" and pixels = 0, which
        // callers show so that the numbers are not mistaken for a measurement.
        m.rmse = 0.0;
        m.psnr = std::numeric_limits<double>::infinity();
        m.ssim = 1.0;
        return m;
    }
    m.rmse = std::sqrt(sumSquared / double(m.pixels));
    // PSNR with peak 1: 10 log10(1 / MSE).
    m.psnr = m.rmse == 0.0 ? std::numeric_limits<double>::infinity() : -20.0 * std::log10(m.rmse);
    m.ssim = meanSsim(test, reference, take) / double(m.pixels);
    return m;
}

Image errorHeatmap(const Image& test, const Image& reference, float maxError) {
    checkPair(test, reference);
    const int w = test.width;
    const int h = test.height;

    if (!(maxError > 0.0f) || !std::isfinite(maxError)) {
        maxError = 0.0f;
        for (size_t i = 0; i < test.pixelCount(); ++i) {
            if (bothFinite(test.data[i], reference.data[i])) {
                maxError = std::max(maxError, std::abs(test.data[i] - reference.data[i]));
            }
        }
        if (!(maxError > 0.0f)) maxError = 1.0f;  // identical images: a scale of 1 shows all black
    }

    // The colour bar under the image: its text at least 1/30 of the picture's height and never under
    // 14 px (issue 19's text standard, viz/README.md: stb_easy_font's em is about 10 units, its
    // capitals 7, so a scale of 2 at least), a title, the two end labels and the background's grey
    // swatch, laid out left to right without overlap.
    const int em = std::max(14, int(std::lround((h + 64) / 30.0)));
    const int scale = std::max(2, (em + 9) / 10);
    char maxLabel[32];
    std::snprintf(maxLabel, sizeof maxLabel, "%.3g", double(maxError));
    const std::string zeroLabel = "0";
    const std::string title = "|v - v_ref|";
    const std::string noData = "no data";
    const int margin = 3 * scale;
    const int barHeight = 10 * scale;
    const int textHeightPx = std::max(textHeight(zeroLabel), textHeight(maxLabel)) * scale;
    const int stripHeight = margin + barHeight + margin + textHeightPx + margin;

    Image out(w, h + stripHeight, 3, 0.0f);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            float a = test.at(x, y);
            float b = reference.at(x, y);
            glm::vec3 rgb = bothFinite(a, b) ? paletteColour(Palette::AbsoluteError, std::min(std::abs(a - b) / maxError, 1.0f))
                                             : kBackgroundGrey;
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = rgb[c];
        }
    }

    const float background[3] = {0.12f, 0.12f, 0.12f};
    const float white[3] = {1.0f, 1.0f, 1.0f};
    const float grey[3] = {kBackgroundGrey.r, kBackgroundGrey.g, kBackgroundGrey.b};
    fillRect(out, 0, h, w, h + stripHeight, background);
    // Title at the left, the bar in the middle with 0 and the maximum under its ends, the grey
    // swatch and "no data" at the right. A picture too narrow for all of it keeps the bar and its
    // two labels (the title and swatch need their own width, never drawn over the bar).
    const int titleWidth = textWidth(title) * scale + 2 * margin;
    const int swatchWidth = barHeight + margin + textWidth(noData) * scale + 2 * margin;
    const int minBar = (textWidth(zeroLabel) + textWidth(maxLabel)) * scale + 4 * margin;
    const bool sides = w - titleWidth - swatchWidth >= minBar;
    const int barLeft = sides ? titleWidth : std::min(margin, w / 4);
    const int barRight = std::max(sides ? w - swatchWidth : w - barLeft, barLeft + 1);
    const int barTop = h + margin;
    for (int x = barLeft; x < barRight && x < w; ++x) {
        float t = barRight - barLeft > 1 ? float(x - barLeft) / float(barRight - barLeft - 1) : 1.0f;
        glm::vec3 c = paletteColour(Palette::AbsoluteError, t);
        const float rgb[3] = {c.r, c.g, c.b};
        fillRect(out, x, barTop, x + 1, barTop + barHeight, rgb);
    }
    const int textTop = barTop + barHeight + margin;
    drawText(out, zeroLabel, barLeft, textTop, scale, white);
    drawText(out, maxLabel, barRight - textWidth(maxLabel) * scale, textTop, scale, white);
    if (sides) {
        drawText(out, title, margin, barTop + (barHeight - 7 * scale) / 2, scale, white);
        const int sx = barRight + 2 * margin;
        fillRect(out, sx, barTop, sx + barHeight, barTop + barHeight, grey);
        drawText(out, noData, sx + barHeight + margin, barTop + (barHeight - 7 * scale) / 2, scale, white);
    }
    return out;
}

}  // namespace shadowlab
