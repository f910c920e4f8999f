#include "style.h"

#include <vtkActor2D.h>
#include <vtkActor2DCollection.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCoordinate.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty2D.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "error.h"
#include "vtk_offscreen.h"

namespace shadowlab {

int textPx(int frameHeight) { return std::max(kMinTextPx, int(std::lround(double(frameHeight) / 30.0))); }

void textExtent(vtkTextProperty* property, const std::string& text, int& width, int& height) {
    width = height = 0;
    if (text.empty()) return;
    int bbox[4] = {0, 0, 0, 0};
    vtkTextRenderer* tr = vtkTextRenderer::GetInstance();
    if (!tr || !tr->GetBoundingBox(property, text, bbox, 72)) throw InternalError("cannot measure text '" + text + "'");
    width = bbox[1] - bbox[0] + 1;
    height = bbox[3] - bbox[2] + 1;
}

static int lineWidth(vtkTextProperty* p, const std::string& line) {
    int w, h;
    textExtent(p, line.empty() ? std::string(" ") : line, w, h);
    return w;
}

// Splits one over-long word into pieces that fit: after '/', ',', '_' or '-' where it can, else
// anywhere.
static std::vector<std::string> splitWord(vtkTextProperty* p, const std::string& word, int maxWidth) {
    std::vector<std::string> pieces;
    std::string rest = word;
    while (!rest.empty() && lineWidth(p, rest) > maxWidth) {
        size_t fit = 1;
        while (fit < rest.size() && lineWidth(p, rest.substr(0, fit + 1)) <= maxWidth) ++fit;
        size_t cut = fit;
        for (size_t i = fit; i > fit / 2 && i > 0; --i)
            if (std::string("/,_-").find(rest[i - 1]) != std::string::npos) {
                cut = i;
                break;
            }
        pieces.push_back(rest.substr(0, cut));
        rest = rest.substr(cut);
    }
    if (!rest.empty()) pieces.push_back(rest);
    return pieces;
}

std::string wrapText(vtkTextProperty* p, const std::string& text, int maxWidth) {
    maxWidth = std::max(maxWidth, 8);
    std::string out;
    std::istringstream lines(text);
    std::string line;
    bool firstLine = true;
    while (std::getline(lines, line)) {
        if (!firstLine) out += '\n';
        firstLine = false;
        if (lineWidth(p, line) <= maxWidth) {
            out += line;
            continue;
        }
        // Greedy word wrap; leading spaces of the line (indentation) are kept on its first piece.
        std::string current;
        size_t i = 0;
        while (i < line.size() && line[i] == ' ') current += line[i++];
        std::vector<std::string> words;
        std::string word;
        for (; i <= line.size(); ++i) {
            if (i == line.size() || line[i] == ' ') {
                if (!word.empty()) words.push_back(word);
                word.clear();
            } else {
                word += line[i];
            }
        }
        bool lineStart = true;
        for (const std::string& w : words) {
            std::string trial = lineStart ? current + w : current + " " + w;
            if (lineWidth(p, trial) <= maxWidth) {
                current = trial;
                lineStart = false;
                continue;
            }
            if (!lineStart) {
                out += current + '\n';
                current.clear();
            }
            std::vector<std::string> pieces = splitWord(p, w, maxWidth);
            for (size_t k = 0; k + 1 < pieces.size(); ++k) out += pieces[k] + '\n';
            current = pieces.empty() ? "" : pieces.back();
            lineStart = false;
        }
        out += current;
    }
    return out;
}

vtkSmartPointer<vtkLookupTable> paletteLut(Palette palette, double lo, double hi) {
    if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) lo = 0.0, hi = 1.0;
    if (palette == Palette::SignedError) {
        const double m = std::max(std::abs(lo), std::abs(hi));
        lo = -m, hi = m;
    }
    const double minWidth = 1e-2 * std::max(1.0, std::max(std::abs(lo), std::abs(hi)));
    if (hi - lo < minWidth) {
        const double mid = 0.5 * (lo + hi);
        lo = mid - 0.5 * minWidth;
        hi = mid + 0.5 * minWidth;
    }
    auto lut = vtkSmartPointer<vtkLookupTable>::New();
    lut->SetNumberOfTableValues(256);
    lut->SetTableRange(lo, hi);
    for (int i = 0; i < 256; ++i) {
        glm::vec3 c = paletteColour(palette, float(i) / 255.0f);
        lut->SetTableValue(i, c.r, c.g, c.b, 1.0);
    }
    lut->SetNanColor(kBackgroundGrey.r, kBackgroundGrey.g, kBackgroundGrey.b, 1.0);
    lut->SetUseBelowRangeColor(false);
    lut->SetUseAboveRangeColor(false);
    return lut;
}

// ---- colour bars -------------------------------------------------------------------------------------
std::vector<std::string> colourBarTickLabels(double lo, double hi, int n) {
    const double range = hi - lo;
    auto label = [range](double v, int digits) {
        if (std::abs(v) < 1e-9 * std::max(1.0, std::abs(range))) v = 0.0;
        char s[40];
        std::snprintf(s, sizeof s, "%.*g", digits, v);
        return std::string(s);
    };
    std::vector<std::string> labels;
    for (int digits = 3; digits <= 9; ++digits) {
        labels.clear();
        for (int i = 0; i < n; ++i) labels.push_back(label(n > 1 ? lo + range * i / (n - 1) : lo, digits));
        bool distinct = true;
        for (int i = 1; i < n; ++i) distinct = distinct && labels[size_t(i)] != labels[size_t(i) - 1];
        if (distinct) break;
    }
    return labels;
}

namespace {

constexpr const char* kNoData = "no data";

vtkSmartPointer<vtkTextActor> barText(const std::string& text, int px, bool bold) {
    auto a = vtkSmartPointer<vtkTextActor>::New();
    a->SetInput(text.c_str());
    vtkTextProperty* p = a->GetTextProperty();
    p->SetFontSize(px);
    p->SetFontFamilyToArial();
    p->SetBold(bold);
    p->ItalicOff();
    p->ShadowOff();
    p->SetColor(0.95, 0.95, 0.95);
    a->GetPositionCoordinate()->SetCoordinateSystemToViewport();
    return a;
}

std::vector<std::string> tickLabels(vtkLookupTable* lut, int n) {
    double* r = lut->GetTableRange();
    return colourBarTickLabels(r[0], r[1], n);
}

bool showsNoData(vtkLookupTable* lut) {
    const double* c = lut->GetNanColor();
    return std::abs(c[0] - kBackgroundGrey.r) < 1e-3 && std::abs(c[1] - kBackgroundGrey.g) < 1e-3 &&
           std::abs(c[2] - kBackgroundGrey.b) < 1e-3;
}

struct BarMetrics {
    int px, margin, strip, labelW, labelH, swatch, swatchRowW;
};

BarMetrics barMetrics(vtkLookupTable* lut, int frameHeight) {
    BarMetrics m{};
    m.px = textPx(frameHeight);
    m.margin = std::max(4, m.px / 3);
    m.strip = std::max(10, int(m.px * 0.9));
    auto probe = barText("0", m.px, false);
    for (int n = 2; n <= 5; ++n)
        for (const std::string& l : tickLabels(lut, n)) {
            int w, h;
            textExtent(probe->GetTextProperty(), l, w, h);
            m.labelW = std::max(m.labelW, w);
            m.labelH = std::max(m.labelH, h);
        }
    int w = 0, h = 0;
    textExtent(probe->GetTextProperty(), kNoData, w, h);
    m.swatch = showsNoData(lut) ? m.px : 0;
    m.swatchRowW = m.swatch ? m.swatch + m.margin / 2 + w : 0;
    m.labelH = std::max(m.labelH, h);
    return m;
}

void addStrip(vtkRenderer* r, vtkLookupTable* lut, int x0, int y0, int x1, int y1, bool horizontal) {
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> cells;
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetNumberOfComponents(3);
    const int n = 128;
    double* range = lut->GetTableRange();
    for (int i = 0; i < n; ++i) {
        double a = double(i) / n, b = double(i + 1) / n;
        double q[4][2];
        if (horizontal) {
            double xa = x0 + (x1 - x0) * a, xb = x0 + (x1 - x0) * b;
            double qq[4][2] = {{xa, double(y0)}, {xb, double(y0)}, {xb, double(y1)}, {xa, double(y1)}};
            std::copy(&qq[0][0], &qq[0][0] + 8, &q[0][0]);
        } else {
            double ya = y0 + (y1 - y0) * a, yb = y0 + (y1 - y0) * b;
            double qq[4][2] = {{double(x0), ya}, {double(x1), ya}, {double(x1), yb}, {double(x0), yb}};
            std::copy(&qq[0][0], &qq[0][0] + 8, &q[0][0]);
        }
        vtkIdType ids[4];
        for (int k = 0; k < 4; ++k) ids[k] = points->InsertNextPoint(q[k][0], q[k][1], 0.0);
        cells->InsertNextCell(4, ids);
        double rgb[3];
        lut->GetColor(range[0] + (range[1] - range[0]) * (i + 0.5) / n, rgb);
        colours->InsertNextTuple3(rgb[0] * 255.0, rgb[1] * 255.0, rgb[2] * 255.0);
    }
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(points);
    poly->SetPolys(cells);
    poly->GetCellData()->SetScalars(colours);
    vtkNew<vtkCoordinate> coordinate;
    coordinate->SetCoordinateSystemToViewport();
    vtkNew<vtkPolyDataMapper2D> mapper;
    mapper->SetInputData(poly);
    mapper->SetTransformCoordinate(coordinate);
    mapper->SetScalarModeToUseCellData();
    mapper->SetColorModeToDirectScalars();
    vtkNew<vtkActor2D> actor;
    actor->SetMapper(mapper);
    r->AddActor2D(actor);
}

void addSwatch(vtkRenderer* r, int x, int y, int size, glm::vec3 rgb = kBackgroundGrey) {
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> cells;
    vtkIdType ids[4] = {points->InsertNextPoint(x, y, 0), points->InsertNextPoint(x + size, y, 0),
                        points->InsertNextPoint(x + size, y + size, 0), points->InsertNextPoint(x, y + size, 0)};
    cells->InsertNextCell(4, ids);
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(points);
    poly->SetPolys(cells);
    vtkNew<vtkCoordinate> coordinate;
    coordinate->SetCoordinateSystemToViewport();
    vtkNew<vtkPolyDataMapper2D> mapper;
    mapper->SetInputData(poly);
    mapper->SetTransformCoordinate(coordinate);
    vtkNew<vtkActor2D> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(rgb.r, rgb.g, rgb.b);
    r->AddActor2D(actor);
}

void viewportPixels(vtkRenderer* r, int& x0, int& y0, int& w, int& h) {
    const int* size = r->GetRenderWindow()->GetSize();
    const double* vp = r->GetViewport();
    x0 = int(std::lround(vp[0] * size[0]));
    y0 = int(std::lround(vp[1] * size[1]));
    w = int(std::lround(vp[2] * size[0])) - x0;
    h = int(std::lround(vp[3] * size[1])) - y0;
}

}  // namespace

// ---- legends --------------------------------------------------------------------------------------
namespace {
struct LegendMetrics {
    int px, margin, swatch, rowGap;
};
LegendMetrics legendMetrics(int frameHeight) {
    const int px = textPx(frameHeight);
    return {px, std::max(4, px / 3), px, std::max(3, px / 4)};
}
}  // namespace

int legendWidthPx(const std::string& title, const std::vector<LegendEntry>& entries, int frameHeight) {
    const LegendMetrics m = legendMetrics(frameHeight);
    int need = 0, w = 0, h = 0;
    auto t = barText("", m.px, false);
    for (const LegendEntry& e : entries) {
        textExtent(t->GetTextProperty(), e.text, w, h);
        need = std::max(need, m.margin + m.swatch + m.margin / 2 + w + m.margin);
    }
    auto b = barText("", m.px, true);
    for (size_t i = 0, j; i <= title.size(); i = j + 1) {  // the title wraps: its longest word must fit
        j = title.find(' ', i);
        if (j == std::string::npos) j = title.size();
        textExtent(b->GetTextProperty(), title.substr(i, j - i), w, h);
        need = std::max(need, w + 2 * m.margin);
    }
    return need;
}

int legendHeightPx(const std::string& title, const std::vector<LegendEntry>& entries, int frameHeight, int widthPx) {
    const LegendMetrics m = legendMetrics(frameHeight);
    int w = 0, h = 0, total = m.margin;
    if (!title.empty()) {
        auto b = barText("", m.px, true);
        textExtent(b->GetTextProperty(), wrapText(b->GetTextProperty(), title, widthPx - 2 * m.margin), w, h);
        total += h + m.rowGap;
    }
    auto t = barText("", m.px, false);
    for (const LegendEntry& e : entries) {
        textExtent(t->GetTextProperty(), wrapText(t->GetTextProperty(), e.text, widthPx - 2 * m.margin - m.swatch - m.margin / 2), w, h);
        total += std::max(m.swatch, h) + m.rowGap;
    }
    return total + m.margin;
}

void addLegend(vtkRenderer* r, const std::string& title, const std::vector<LegendEntry>& entries, int frameHeight) {
    if (!r->GetRenderWindow()) throw InternalError("addLegend: the renderer is not in a window yet");
    int vx, vy, W, H;
    viewportPixels(r, vx, vy, W, H);
    const LegendMetrics m = legendMetrics(frameHeight);
    int top = H - m.margin, w = 0, h = 0;  // viewport pixels, y up
    if (!title.empty()) {
        auto b = barText("", m.px, true);
        const std::string wrapped = wrapText(b->GetTextProperty(), title, W - 2 * m.margin);
        b->SetInput(wrapped.c_str());
        b->GetTextProperty()->SetVerticalJustificationToTop();
        b->SetPosition(m.margin, top);
        textExtent(b->GetTextProperty(), wrapped, w, h);
        r->AddActor2D(b);
        top -= h + m.rowGap;
    }
    for (const LegendEntry& e : entries) {
        // An entry wider than the panel wraps (never shrinks) and its row grows.
        auto t = barText("", m.px, false);
        const std::string text = wrapText(t->GetTextProperty(), e.text, W - 2 * m.margin - m.swatch - m.margin / 2);
        t->SetInput(text.c_str());
        textExtent(t->GetTextProperty(), text, w, h);
        const int row = std::max(m.swatch, h);
        const int y = top - row;
        addSwatch(r, m.margin, y + (row - m.swatch) / 2, m.swatch, e.rgb);
        t->GetTextProperty()->SetVerticalJustificationToCentered();
        t->SetPosition(m.margin + m.swatch + m.margin / 2, y + row / 2);
        r->AddActor2D(t);
        top = y - m.rowGap;
    }
}


int colourBarWidthPx(vtkLookupTable* lut, const std::string& title, int frameHeight) {
    const BarMetrics m = barMetrics(lut, frameHeight);
    int need = m.margin + m.strip + m.margin / 2 + m.labelW + m.margin;
    need = std::max(need, 2 * m.margin + m.swatchRowW);
    auto t = barText("", m.px, true);
    std::istringstream words(title);
    std::string word;
    while (words >> word) need = std::max(need, lineWidth(t->GetTextProperty(), word) + 2 * m.margin);
    return need;
}

void addColourBar(vtkRenderer* r, vtkLookupTable* lut, const std::string& title, int frameHeight, bool horizontal) {
    if (!r->GetRenderWindow()) throw InternalError("addColourBar: the renderer is not in a window yet");
    int vx, vy, W, H;
    viewportPixels(r, vx, vy, W, H);
    const BarMetrics m = barMetrics(lut, frameHeight);
    // Title on top, wrapped to the width.
    auto titleText = barText("", m.px, true);
    const std::string wrapped = wrapText(titleText->GetTextProperty(), title, W - 2 * m.margin);
    titleText->SetInput(wrapped.c_str());
    int tw = 0, th = 0;
    textExtent(titleText->GetTextProperty(), wrapped, tw, th);
    titleText->GetTextProperty()->SetVerticalJustificationToTop();
    titleText->SetPosition(m.margin, H - m.margin);
    r->AddActor2D(titleText);
    const int titleBottom = H - m.margin - th;
    const int half = m.labelH / 2 + 1;

    auto placeLabels = [&](int n, auto position) {
        std::vector<std::string> labels = tickLabels(lut, n);
        for (int i = 0; i < n; ++i) {
            auto a = barText(labels[size_t(i)], m.px, false);
            position(a, i, n);
            r->AddActor2D(a);
        }
    };

    if (!horizontal) {
        int rowTop = m.margin;
        if (m.swatch) {
            addSwatch(r, m.margin, m.margin, m.swatch);
            // "no data" wrapped to what the swatch leaves of a narrow panel; its row as tall as it.
            const int textX = m.margin + m.swatch + m.margin / 2;
            auto t = barText(kNoData, m.px, false);
            // (the width wrapTextsToViewports allows a left-aligned text)
            const std::string noData = wrapText(t->GetTextProperty(), kNoData, std::max(1, W - textX - 4));
            t->SetInput(noData.c_str());
            int nw = 0, nh = 0;
            textExtent(t->GetTextProperty(), noData, nw, nh);
            const int rowH = std::max({m.swatch, m.labelH, nh});
            t->GetTextProperty()->SetVerticalJustificationToCentered();
            t->SetPosition(textX, m.margin + rowH / 2);
            r->AddActor2D(t);
            rowTop = m.margin + rowH;
        }
        const int y0 = rowTop + m.margin + half, y1 = titleBottom - m.margin / 2 - half;
        addStrip(r, lut, m.margin, y0, m.margin + m.strip, std::max(y1, y0 + 1), false);
        const double span = std::max(0, y1 - y0);
        int n = 2;
        for (int k = 5; k >= 2; --k)
            if (span / (k - 1) >= 1.3 * m.labelH) {
                n = k;
                break;
            }
        placeLabels(n, [&](vtkTextActor* a, int i, int count) {
            a->GetTextProperty()->SetVerticalJustificationToCentered();
            a->SetPosition(m.margin + m.strip + m.margin / 2, y0 + span * i / (count - 1));
        });
        return;
    }
    // Horizontal: the strip under the title with the swatch at its right, the labels under it.
    const int stripTop = titleBottom - m.margin / 2, stripBottom = stripTop - m.strip;
    int stripRight = W - m.margin;
    if (m.swatch) {
        const int sx = W - m.margin - m.swatchRowW;
        addSwatch(r, sx, stripBottom, m.swatch);
        auto t = barText(kNoData, m.px, false);
        t->GetTextProperty()->SetVerticalJustificationToCentered();
        t->SetPosition(sx + m.swatch + m.margin / 2, stripBottom + m.swatch / 2);
        r->AddActor2D(t);
        stripRight = sx - m.margin;
    }
    const int x0 = m.margin + m.labelW / 2, x1 = std::max(stripRight - m.labelW / 2, x0 + 1);
    addStrip(r, lut, x0, stripBottom, x1, stripTop, true);
    const double span = x1 - x0;
    int n = 2;
    for (int k = 5; k >= 2; --k)
        if (span / (k - 1) >= m.labelW + m.margin) {
            n = k;
            break;
        }
    placeLabels(n, [&](vtkTextActor* a, int i, int count) {
        a->GetTextProperty()->SetJustificationToCentered();
        a->GetTextProperty()->SetVerticalJustificationToTop();
        a->SetPosition(x0 + span * i / (count - 1), stripBottom - m.margin / 2);
    });
}

// ---- the layout record ------------------------------------------------------------------------------
std::vector<TextBox> textLayout(VtkOffscreen& out) {
    std::vector<TextBox> boxes;
    const int H = out.height();
    vtkRendererCollection* renderers = out.window()->GetRenderers();
    renderers->InitTraversal();
    while (vtkRenderer* r = renderers->GetNextItem()) {
        int vx, vy, vw, vh;
        viewportPixels(r, vx, vy, vw, vh);
        vtkActor2DCollection* actors = r->GetActors2D();
        actors->InitTraversal();
        while (vtkActor2D* a = actors->GetNextActor2D()) {
            if (a->IsA("vtkScalarBarActor")) {
                // VTK's own bar places its texts where it likes: the standard cannot measure them.
                TextBox b;
                b.text = "[a vtkScalarBarActor: use addColourBar, whose texts are measured]";
                b.x1 = b.y1 = 1;
                b.vx1 = b.vy1 = 1;
                boxes.push_back(b);
                continue;
            }
            auto* t = vtkTextActor::SafeDownCast(a);
            if (!t || !t->GetVisibility() || !t->GetInput() || !*t->GetInput()) continue;
            double bb[4];
            t->GetBoundingBox(r, bb);  // xmin, xmax, ymin, ymax about the actor's position
            const double* at = t->GetPositionCoordinate()->GetComputedDoubleViewportValue(r);
            bb[0] += at[0], bb[1] += at[0], bb[2] += at[1], bb[3] += at[1];
            TextBox b;
            b.text = t->GetInput();
            b.fontPx = t->GetTextProperty()->GetFontSize();
            b.x0 = vx + int(std::floor(bb[0]));
            b.x1 = vx + int(std::ceil(bb[1])) + 1;
            b.y0 = H - (vy + int(std::ceil(bb[3])) + 1);
            b.y1 = H - (vy + int(std::floor(bb[2])));
            b.vx0 = vx, b.vx1 = vx + vw, b.vy0 = H - (vy + vh), b.vy1 = H - vy;
            boxes.push_back(b);
        }
    }
    return boxes;
}

std::string layoutProblems(const std::vector<TextBox>& boxes, int width, int height) {
    std::string problems;
    auto name = [](const TextBox& b) {
        std::string t = b.text.substr(0, 40);
        std::replace(t.begin(), t.end(), '\n', ' ');
        return "'" + t + "' [" + std::to_string(b.x0) + "," + std::to_string(b.y0) + " - " + std::to_string(b.x1) +
               "," + std::to_string(b.y1) + "]";
    };
    const int minPx = textPx(height);
    for (size_t i = 0; i < boxes.size(); ++i) {
        const TextBox& a = boxes[i];
        if (a.fontPx < minPx)
            problems += name(a) + ": font " + std::to_string(a.fontPx) + " px, the standard needs " +
                        std::to_string(minPx) + "\n";
        if (a.x0 < 0 || a.y0 < 0 || a.x1 > width || a.y1 > height) problems += name(a) + ": outside the picture\n";
        else if (a.x0 < a.vx0 || a.y0 < a.vy0 || a.x1 > a.vx1 || a.y1 > a.vy1)
            problems += name(a) + ": outside its panel [" + std::to_string(a.vx0) + "," + std::to_string(a.vy0) + " - " +
                        std::to_string(a.vx1) + "," + std::to_string(a.vy1) + "]\n";
        for (size_t j = i + 1; j < boxes.size(); ++j) {
            const TextBox& b = boxes[j];
            if (a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1)
                problems += name(a) + " overlaps " + name(b) + "\n";
        }
    }
    return problems;
}

void wrapTextsToViewports(VtkOffscreen& out) {
    vtkRendererCollection* renderers = out.window()->GetRenderers();
    renderers->InitTraversal();
    while (vtkRenderer* r = renderers->GetNextItem()) {
        int vx, vy, vw, vh;
        viewportPixels(r, vx, vy, vw, vh);
        vtkActor2DCollection* actors = r->GetActors2D();
        actors->InitTraversal();
        while (vtkActor2D* a = actors->GetNextActor2D()) {
            auto* t = vtkTextActor::SafeDownCast(a);
            if (!t || !t->GetInput() || !*t->GetInput()) continue;
            double* p = t->GetPositionCoordinate()->GetComputedDoubleViewportValue(r);
            vtkTextProperty* prop = t->GetTextProperty();
            int available = vw - 4;
            if (prop->GetJustification() == VTK_TEXT_LEFT) available = vw - int(std::ceil(p[0])) - 4;
            int w, h;
            textExtent(prop, t->GetInput(), w, h);
            if (w > available) t->SetInput(wrapText(prop, t->GetInput(), available).c_str());
        }
    }
}

}  // namespace shadowlab
