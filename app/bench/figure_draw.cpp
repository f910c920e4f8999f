// Raster drawing for `shadowlab figure` (figure_draw.h).
#include "bench/figure_draw.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "error.h"
#include "image/metrics.h"
#include "image/palette.h"

#include <stb/stb_easy_font.h>

// stb_image_write's deflate (libstb), for the PDF's image stream; its header declares it only
// inside the implementation.
extern "C" unsigned char* stbi_zlib_compress(unsigned char* data, int data_len, int* out_len, int quality);

namespace shadowlab::figure {

void fill(Image& image, int x0, int y0, int x1, int y1, Rgb c) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, image.width);
    y1 = std::min(y1, image.height);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            image.at(x, y, 0) = c.r;
            image.at(x, y, 1) = c.g;
            image.at(x, y, 2) = c.b;
        }
}

void outline(Image& image, int x0, int y0, int x1, int y1, int t, Rgb c) {
    fill(image, x0, y0, x1, y0 + t, c);
    fill(image, x0, y1 - t, x1, y1, c);
    fill(image, x0, y0, x0 + t, y1, c);
    fill(image, x1 - t, y0, x1, y1, c);
}

int textWidth(const std::string& s, int scale) { return stb_easy_font_width(const_cast<char*>(s.c_str())) * scale; }
std::vector<std::string> wrapText(const std::string& s, int scale, int maxWidth, const std::string& what) {
    // stb_easy_font's width of one line is the sum of its characters' advances, so widths add up and
    // the wrap is linear in the text's length.
    auto width = [&](const std::string& t) { return textWidth(t, scale); };
    std::vector<std::string> lines;
    std::istringstream in(s);
    std::string paragraph;
    while (std::getline(in, paragraph)) {
        std::string current;
        int currentW = 0;
        std::istringstream words(paragraph);
        std::string word;
        bool any = false;
        while (words >> word) {
            any = true;
            const int space = current.empty() ? 0 : width(" ");
            const int w = width(word);
            if (currentW + space + w <= maxWidth) {
                current += (current.empty() ? "" : " ") + word;
                currentW += space + w;
                continue;
            }
            if (!current.empty()) lines.push_back(current);
            current.clear();
            currentW = 0;
            // A word wider than the line: pieces that fit, cut after '/', ',', '=', '_' or '-' where one
            // is in the second half of the piece, else between characters.
            size_t start = 0;
            while (start < word.size()) {
                size_t end = start;
                int pw = 0;
                while (end < word.size() && pw + width(word.substr(end, 1)) <= maxWidth) pw += width(word.substr(end++, 1));
                if (end == start)
                    throw InputError("figure: the " + what + " '" + s.substr(0, 60) + (s.size() > 60 ? "...'" : "'") +
                                     " cannot fit " + std::to_string(maxWidth) + " px at text scale " +
                                     std::to_string(scale) + " (one character is wider): give a larger width or a "
                                     "smaller text_scale");
                if (end < word.size())
                    for (size_t k = end; k > start + (end - start) / 2; --k)
                        if (std::string("/,=_-").find(word[k - 1]) != std::string::npos) {
                            end = k;
                            break;
                        }
                const std::string piece = word.substr(start, end - start);
                if (end < word.size()) lines.push_back(piece);
                else current = piece, currentW = width(piece);
                start = end;
            }
        }
        if (!current.empty() || !any) lines.push_back(current);
    }
    if (lines.empty()) lines.push_back("");
    return lines;
}

int textHeight(int scale) { return 12 * scale; }

int text(Image& image, const std::string& s, int left, int top, int scale, Rgb c) {
    struct Vertex {
        float x, y, z;
        unsigned char color[4];
    };
    std::vector<Vertex> quads(s.size() * 80 + 64);
    int n = stb_easy_font_print(0.0f, 0.0f, const_cast<char*>(s.c_str()), nullptr, quads.data(),
                                int(quads.size() * sizeof(Vertex)));
    for (int q = 0; q < n; ++q) {
        const Vertex* v = &quads[size_t(q) * 4];
        float qx0 = std::min({v[0].x, v[1].x, v[2].x, v[3].x}), qx1 = std::max({v[0].x, v[1].x, v[2].x, v[3].x});
        float qy0 = std::min({v[0].y, v[1].y, v[2].y, v[3].y}), qy1 = std::max({v[0].y, v[1].y, v[2].y, v[3].y});
        fill(image, left + int(std::lround(qx0 * scale)), top + int(std::lround(qy0 * scale)),
             left + int(std::lround(qx1 * scale)), top + int(std::lround(qy1 * scale)), c);
    }
    return textWidth(s, scale);
}

void blit(Image& dst, const Image& src, int left, int top) {
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x) {
            int dx = left + x, dy = top + y;
            if (dx < 0 || dy < 0 || dx >= dst.width || dy >= dst.height) continue;
            for (int c = 0; c < 3; ++c) {
                float v = src.at(x, y, src.channels == 1 ? 0 : c);
                dst.at(dx, dy, c) = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : kBackgroundGrey[c];  // no data
            }
        }
}

Image downsample(const Image& src, int f) {
    if (f <= 1) return src;
    Image out(src.width / f, src.height / f, src.channels);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < src.channels; ++c) {
                double sum = 0;
                int n = 0;
                for (int j = 0; j < f; ++j)
                    for (int i = 0; i < f; ++i) {
                        float v = src.at(x * f + i, y * f + j, c);
                        if (std::isfinite(v)) {
                            sum += v;
                            ++n;
                        }
                    }
                out.at(x, y, c) = n ? float(sum / n) : NAN;
            }
    return out;
}

Image zoom(const Image& src, int x0, int y0, int w, int h, int outWidth, int outHeight) {
    Image out(outWidth, outHeight, src.channels);
    for (int y = 0; y < outHeight; ++y)
        for (int x = 0; x < outWidth; ++x) {
            int sx = std::clamp(x0 + int(double(x) * w / outWidth), 0, src.width - 1);
            int sy = std::clamp(y0 + int(double(y) * h / outHeight), 0, src.height - 1);
            for (int c = 0; c < src.channels; ++c) out.at(x, y, c) = src.at(sx, sy, c);
        }
    return out;
}

Image absoluteError(const Image& test, const Image& reference) {
    Image out(test.width, test.height, 1);
    for (size_t i = 0; i < out.pixelCount(); ++i) {
        float a = test.data[i], b = reference.data[i];
        out.data[i] = std::isfinite(a) && std::isfinite(b) ? std::abs(a - b) : NAN;
    }
    return out;
}

Image colourError(const Image& error, float maxError) {
    // errorHeatmap(|e|, 0) colours |e| / maxError with the same inferno map as `compare --heatmap`;
    // its colour bar strip under the image is cut off (the figure draws one shared bar).
    Image zeros(error.width, error.height, 1, 0.0f);
    Image heat = errorHeatmap(error, zeros, maxError);
    Image out(error.width, error.height, 3);
    std::copy_n(heat.data.begin(), out.data.size(), out.data.begin());
    return out;
}

void writeRasterPdf(const std::string& path, const Image& rgb, double dpi, const std::string& title) {
    std::vector<unsigned char> pixels(size_t(rgb.width) * rgb.height * 3);
    for (size_t i = 0; i < pixels.size(); ++i) {
        float v = rgb.data[i];
        pixels[i] = (unsigned char)std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f);
    }
    int zlen = 0;
    unsigned char* z = stbi_zlib_compress(pixels.data(), int(pixels.size()), &zlen, 8);
    if (!z) throw InternalError("cannot compress the figure for " + path);
    std::string stream(reinterpret_cast<char*>(z), size_t(zlen));
    std::free(z);
    const double w = rgb.width * 72.0 / dpi, h = rgb.height * 72.0 / dpi;
    char content[128];
    std::snprintf(content, sizeof content, "q %.3f 0 0 %.3f 0 0 cm /Im0 Do Q\n", w, h);
    std::string safeTitle;
    for (char c : title)
        if (c != '(' && c != ')' && c != '\\') safeTitle += c;
    std::vector<std::string> objects = {
        "<< /Type /Catalog /Pages 2 0 R >>",
        "<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
        "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + std::to_string(w) + " " + std::to_string(h) +
            "] /Resources << /XObject << /Im0 4 0 R >> >> /Contents 5 0 R >>",
        "<< /Type /XObject /Subtype /Image /Width " + std::to_string(rgb.width) + " /Height " +
            std::to_string(rgb.height) + " /ColorSpace /DeviceRGB /BitsPerComponent 8 /Filter /FlateDecode /Length " +
            std::to_string(stream.size()) + " >>\nstream\n" + stream + "\nendstream",
        "<< /Length " + std::to_string(std::string(content).size()) + " >>\nstream\n" + content + "endstream",
        "<< /Title (" + safeTitle + ") /Producer (shadowlab figure) >>"};
    std::ostringstream pdf;
    pdf << "%PDF-1.4\n%\xE2\xE3\xCF\xD3\n";
    std::vector<size_t> offsets;
    for (size_t i = 0; i < objects.size(); ++i) {
        offsets.push_back(size_t(pdf.tellp()));
        pdf << (i + 1) << " 0 obj\n" << objects[i] << "\nendobj\n";
    }
    size_t xref = size_t(pdf.tellp());
    pdf << "xref\n0 " << objects.size() + 1 << "\n0000000000 65535 f \n";
    for (size_t o : offsets) {
        char line[32];
        std::snprintf(line, sizeof line, "%010zu 00000 n \n", o);
        pdf << line;
    }
    pdf << "trailer\n<< /Size " << objects.size() + 1 << " /Root 1 0 R /Info 6 0 R >>\nstartxref\n" << xref << "\n%%EOF\n";
    std::ofstream out(path, std::ios::binary);
    out << pdf.str();
    if (!out) throw InternalError("cannot write " + path);
}

}  // namespace shadowlab::figure
