// Raster drawing for `shadowlab figure`: RGB images (Image with 3 channels, values in [0,1]),
// rectangles, outlines, text (stb_easy_font at an integer scale), resampling, the error colour
// map, and a one-page PDF holding a raster image.
#pragma once
#include <string>
#include <vector>

#include "image/image.h"

namespace shadowlab::figure {

struct Rgb {
    float r, g, b;
};

void fill(Image& image, int x0, int y0, int x1, int y1, Rgb colour);
// A rectangle outline `thickness` pixels wide, inside [x0, x1) x [y0, y1).
void outline(Image& image, int x0, int y0, int x1, int y1, int thickness, Rgb colour);
// Text with its top-left corner at (left, top); returns the width drawn.
int text(Image& image, const std::string& s, int left, int top, int scale, Rgb colour);
int textWidth(const std::string& s, int scale);
// `s` as lines at most maxWidth pixels wide: wrapped at spaces, a longer word cut after '/', ',', '=',
// '_' or '-', else between characters; never shortened. InputError naming `what` and the text when
// even one character is wider than maxWidth.
std::vector<std::string> wrapText(const std::string& s, int scale, int maxWidth, const std::string& what);
int textHeight(int scale);
// Copies `src` (1 or 3 channels; 1 channel is shown grey) into `dst` at (left, top); NaN (no data)
// becomes kBackgroundGrey.
void blit(Image& dst, const Image& src, int left, int top);
// Box-filter reduction by an integer factor (supersampling); NaN samples are skipped.
Image downsample(const Image& src, int factor);
// The region [x, x+w) x [y, y+h) of `src` scaled to outWidth x outHeight, nearest sample.
Image zoom(const Image& src, int x, int y, int w, int h, int outWidth, int outHeight);
// |test - reference| per pixel (NaN where either is not finite), 1 channel.
Image absoluteError(const Image& test, const Image& reference);
// An error image in colour: the same inferno map as `compare --heatmap`, 0 .. maxError; NaN grey.
Image colourError(const Image& error, float maxError);

// A one-page PDF showing an RGB image at `dpi` (Flate-compressed, deterministic bytes).
void writeRasterPdf(const std::string& path, const Image& rgb, double dpi, const std::string& title);

}  // namespace shadowlab::figure
