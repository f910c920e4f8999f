// The accuracy-versus-time chart (chart_accuracy_time.h).
#include "chart_accuracy_time.h"

#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkChartLegend.h>
#include <vtkContext2D.h>
#include <vtkContextScene.h>
#include <vtkContextItem.h>
#include <vtkContextView.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPen.h>
#include <vtkPlotLine.h>
#include <vtkPlotPoints.h>
#include <vtkPoints2D.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "error.h"
#include "graph/technique.h"
#include "image/image.h"
#include "style.h"
#include "vtk_offscreen.h"

namespace shadowlab {

namespace {

// The chart's marks, drawn in scene coordinates from the axes' positions and ranges. VTK's own
// plots draw inside a scaled transform that its SVG and PDF exporters get wrong (the clip rectangle
// is transformed with the data and text is scaled with it), so the plots only feed the legend and
// this item draws the Pareto front, the points, their labels and the highlight.
class AccuracyTimeMarks : public vtkContextItem {
public:
    static AccuracyTimeMarks* New();
    vtkTypeMacro(AccuracyTimeMarks, vtkContextItem);
    struct Series {
        unsigned char colour[3];
        std::vector<AccuracyTimePoint> points;  // copies: the chart outlives the caller's panel
    };
    std::vector<Series> series;
    std::vector<AccuracyTimePoint> front;
    std::vector<std::string> names;  // the series' names, in order
    int legendFontSize = 12;
    vtkAxis* xAxis = nullptr;
    vtkAxis* yAxis = nullptr;
    bool logX = false, logY = false, labels = true;
    double errorFloor = 0.0;
    int fontSize = 14;
    // The layout record (optional): every text painted with its box, and problems found while
    // painting (tick labels of one axis overlapping); labels that found no free place are counted.
    std::vector<TextBox>* record = nullptr;
    std::string* problems = nullptr;
    int* hiddenLabels = nullptr;
    int sceneHeight = 0;  // the scene's height in pixels, to turn y up into y down

    struct Box {
        float x0, y0, x1, y1;
        bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
    };
    void note(const std::string& text, float x0, float y0, float x1, float y1, int font) {
        if (!record) return;
        TextBox b;
        b.text = text;
        b.x0 = int(std::floor(x0)), b.x1 = int(std::ceil(x1));
        b.y0 = sceneHeight - int(std::ceil(y1)), b.y1 = sceneHeight - int(std::floor(y0));
        b.fontPx = font;
        b.vx0 = 0, b.vy0 = 0, b.vx1 = 1 << 20, b.vy1 = 1 << 20;  // the chart has one panel: the picture
        record->push_back(b);
    }
    // Tick labels of an axis: measured at their tick positions; neighbours must not overlap.
    void checkTicks(vtkContext2D* painter, vtkAxis* a, bool horizontal) {
        vtkFloatArray* ticks = a->GetTickScenePositions();
        vtkStringArray* labels = a->GetTickLabels();
        if (!ticks || !labels || !problems) return;
        painter->ApplyTextProp(a->GetLabelProperties());
        float lastEnd = -1e30f;
        const float lo = horizontal ? a->GetPoint1()[0] : a->GetPoint1()[1];
        const float hi = horizontal ? a->GetPoint2()[0] : a->GetPoint2()[1];
        for (vtkIdType i = 0; i < ticks->GetNumberOfTuples() && i < labels->GetNumberOfValues(); ++i) {
            const float t = ticks->GetValue(i);
            if (t < lo - 0.5f || t > hi + 0.5f || labels->GetValue(i).empty()) continue;  // minor ticks: no label
            float b[4];
            painter->ComputeStringBounds(labels->GetValue(i), b);
            const float half = 0.5f * (horizontal ? b[2] : b[3]);
            if (t - half < lastEnd)
                *problems += "chart: tick labels of the " + std::string(horizontal ? "x" : "y") + " axis overlap at '" +
                             labels->GetValue(i) + "'\n";
            lastEnd = t + half;
        }
    }

    bool Paint(vtkContext2D* painter) override {
        // Axis value -> scene position (log10 on log axes), clipped to the plot area.
        auto map = [](vtkAxis* a, bool log, double v, int i) {
            double lo = a->GetUnscaledMinimum(), hi = a->GetUnscaledMaximum();
            if (log) v = std::log10(v), lo = std::log10(lo), hi = std::log10(hi);
            const float* p1 = a->GetPoint1();
            const float* p2 = a->GetPoint2();
            return float(p1[i] + (v - lo) / (hi - lo) * (p2[i] - p1[i]));
        };
        auto at = [&](const AccuracyTimePoint& q, float& x, float& y) {
            const AccuracyTimePoint* p = &q;
            double e = logY ? std::max(p->error, errorFloor) : p->error;
            x = map(xAxis, logX, p->timeMs, 0);
            y = map(yAxis, logY, e, 1);
            const float* x1 = xAxis->GetPoint1();
            const float* x2 = xAxis->GetPoint2();
            const float* y1 = yAxis->GetPoint1();
            const float* y2 = yAxis->GetPoint2();
            return std::isfinite(x) && std::isfinite(y) && x >= x1[0] - 0.5f && x <= x2[0] + 0.5f && y >= y1[1] - 0.5f &&
                   y <= y2[1] + 0.5f;
        };
        // The grid at the axes' ticks, inside the plot area only (VTK's own grid is off: its SVG
        // export draws lines past the plot area).
        {
            const float x0 = xAxis->GetPoint1()[0], x1 = xAxis->GetPoint2()[0];
            const float y0 = yAxis->GetPoint1()[1], y1 = yAxis->GetPoint2()[1];
            painter->GetPen()->SetColor(232, 232, 232, 255);
            painter->GetPen()->SetWidth(1.0f);
            painter->GetPen()->SetLineType(vtkPen::SOLID_LINE);
            if (vtkFloatArray* ticks = xAxis->GetTickScenePositions())
                for (vtkIdType i = 0; i < ticks->GetNumberOfTuples(); ++i) {
                    float x = ticks->GetValue(i);
                    if (x > x0 + 0.5f && x < x1 - 0.5f) painter->DrawLine(x, y0, x, y1);
                }
            if (vtkFloatArray* ticks = yAxis->GetTickScenePositions())
                for (vtkIdType i = 0; i < ticks->GetNumberOfTuples(); ++i) {
                    float y = ticks->GetValue(i);
                    if (y > y0 + 0.5f && y < y1 - 0.5f) painter->DrawLine(x0, y, x1, y);
                }
        }
        if (front.size() >= 2) {
            std::vector<float> xy;
            for (const AccuracyTimePoint& p : front) {
                float x, y;
                if (at(p, x, y)) xy.insert(xy.end(), {x, y});
            }
            painter->GetPen()->SetColor(90, 90, 90, 255);
            painter->GetPen()->SetWidth(1.5f);
            painter->GetPen()->SetLineType(vtkPen::DASH_LINE);
            if (xy.size() >= 4) painter->DrawPoly(xy.data(), int(xy.size() / 2));
            painter->GetPen()->SetLineType(vtkPen::SOLID_LINE);
        }
        vtkTextProperty* text = painter->GetTextProp();
        text->SetFontSize(fontSize);
        text->SetColor(0.15, 0.15, 0.15);
        text->SetOpacity(1.0);
        text->SetJustificationToLeft();
        text->SetVerticalJustificationToBottom();
        text->SetBold(false);
        text->SetItalic(false);
        text->SetOrientation(0.0);
        const float radius = 5.0f;
        // Points first, then labels placed where they overlap no point and no earlier label: right
        // and above the point, else right-below, left-above, left-below (the first that fits).
        std::vector<Box> taken;
        for (const Series& s : series) {
            painter->GetPen()->SetColor(255, 255, 255, 255);
            painter->GetPen()->SetWidth(1.0f);
            painter->GetBrush()->SetColor(s.colour[0], s.colour[1], s.colour[2], 255);
            for (const AccuracyTimePoint& p : s.points) {
                float x, y;
                if (!at(p, x, y)) continue;
                painter->DrawEllipse(x, y, radius, radius);
                const float r = p.highlight ? 2.2f * radius + 1.5f : radius;  // the ring drawn below
                taken.push_back({x - r, y - r, x + r, y + r});
            }
        }
        if (labels)
            for (const Series& s : series)
                for (const AccuracyTimePoint& p : s.points) {
                    float x, y;
                    if (p.label.empty() || !at(p, x, y)) continue;
                    // An error of 0 cannot sit on a log axis: such a point is drawn at the floor and says so.
                    const std::string label = p.error <= 0.0 && logY ? p.label + " (error 0)" : p.label;
                    float b[4];
                    painter->ComputeStringBounds(label, b);
                    const float w = b[2], h = b[3], gap = (p.highlight ? 2.2f * radius + 1.5f : radius) + 1.0f;
                    const Box candidates[] = {{x + gap, y + 1.0f, x + gap + w, y + 1.0f + h},
                                              {x + gap, y - 1.0f - h, x + gap + w, y - 1.0f},
                                              {x - gap - w, y + 1.0f, x - gap, y + 1.0f + h},
                                              {x - gap - w, y - 1.0f - h, x - gap, y - 1.0f}};
                    // Inside the plot area and over nothing painted before; a label with no such place
                    // is left out (counted: the legend and the point still say which it is).
                    const float px0 = xAxis->GetPoint1()[0], px1 = xAxis->GetPoint2()[0];
                    const float py0 = yAxis->GetPoint1()[1], py1 = yAxis->GetPoint2()[1];
                    const Box* chosen = nullptr;
                    for (const Box& c : candidates) {
                        bool inside = c.x0 >= px0 && c.x1 <= px1 && c.y0 >= py0 && c.y1 <= py1;
                        bool free = std::none_of(taken.begin(), taken.end(), [&](const Box& t) { return t.overlaps(c); });
                        if (inside && free) {
                            chosen = &c;
                            break;
                        }
                    }
                    if (!chosen) {
                        if (hiddenLabels) ++*hiddenLabels;
                        continue;
                    }
                    taken.push_back(*chosen);
                    painter->DrawString(chosen->x0, chosen->y0, label);
                    note(label, chosen->x0, chosen->y0, chosen->x1, chosen->y1, fontSize);
                }
        for (const Series& s : series)
            for (const AccuracyTimePoint& p : s.points) {
                float x, y;
                if (!p.highlight || !at(p, x, y)) continue;
                painter->GetPen()->SetColor(220, 0, 0, 255);
                painter->GetPen()->SetWidth(2.5f);
                painter->GetBrush()->SetColor(0, 0, 0, 0);
                painter->DrawEllipse(x, y, 2.2f * radius, 2.2f * radius);
            }
        paintLegend(painter, radius, taken);
        if (record) {
            // The axes' texts: tick labels measured at their tick positions, in the label band of the
            // axis' bounding rectangle; titles at its outer edge (the y title rotated).
            for (vtkAxis* a : {xAxis, yAxis}) {
                const bool horizontal = a == xAxis;
                const vtkRectf r = a->GetBoundingRect(painter);
                vtkFloatArray* ticks = a->GetTickScenePositions();
                vtkStringArray* tickLabels = a->GetTickLabels();
                painter->ApplyTextProp(a->GetLabelProperties());
                const float lo = horizontal ? a->GetPoint1()[0] : a->GetPoint1()[1];
                const float hi = horizontal ? a->GetPoint2()[0] : a->GetPoint2()[1];
                for (vtkIdType i = 0; ticks && tickLabels && i < ticks->GetNumberOfTuples() && i < tickLabels->GetNumberOfValues(); ++i) {
                    const float t = ticks->GetValue(i);
                    if (t < lo - 0.5f || t > hi + 0.5f || tickLabels->GetValue(i).empty()) continue;
                    float b[4];
                    painter->ComputeStringBounds(tickLabels->GetValue(i), b);
                    if (horizontal)
                        note(tickLabels->GetValue(i), t - 0.5f * b[2], r.GetY() + r.GetHeight() - b[3] - 1.0f,
                             t + 0.5f * b[2], r.GetY() + r.GetHeight() - 1.0f, a->GetLabelProperties()->GetFontSize());
                    else
                        note(tickLabels->GetValue(i), r.GetX() + r.GetWidth() - b[2] - 1.0f, t - 0.5f * b[3],
                             r.GetX() + r.GetWidth() - 1.0f, t + 0.5f * b[3], a->GetLabelProperties()->GetFontSize());
                }
                painter->ApplyTextProp(a->GetTitleProperties());
                float b[4];
                painter->ComputeStringBounds(a->GetTitle(), b);
                const float mid = 0.5f * (lo + hi);
                if (horizontal)
                    note(a->GetTitle(), mid - 0.5f * b[2], r.GetY(), mid + 0.5f * b[2], r.GetY() + b[3],
                         a->GetTitleProperties()->GetFontSize());
                else
                    note(a->GetTitle(), r.GetX(), mid - 0.5f * b[3], r.GetX() + b[2], mid + 0.5f * b[3],
                         a->GetTitleProperties()->GetFontSize());  // the bounds of the rotated text
            }
            checkTicks(painter, xAxis, true);
            checkTicks(painter, yAxis, false);
        }
        return true;
    }

    // A legend box in the plot area's top-right corner: the front, each series, the highlight.
    void paintLegend(vtkContext2D* painter, float radius, const std::vector<Box>& taken) {
        struct Entry {
            std::string name;
            int kind;  // 0 front (dashed line), 1 series (disc), 2 highlight (ring)
            const unsigned char* colour;
        };
        static const unsigned char grey[3] = {90, 90, 90}, red[3] = {220, 0, 0};
        std::vector<Entry> entries;
        if (front.size() >= 2) entries.push_back({"Pareto front", 0, grey});
        for (size_t s = 0; s < names.size(); ++s) entries.push_back({names[s], 1, series[s].colour});
        bool highlighted = false;
        for (const Series& s : series)
            for (const AccuracyTimePoint& p : s.points) highlighted = highlighted || p.highlight;
        if (highlighted) entries.push_back({"current setting", 2, red});
        if (entries.empty()) return;
        vtkTextProperty* text = painter->GetTextProp();
        text->SetFontSize(legendFontSize);
        text->SetColor(0.1, 0.1, 0.1);
        text->SetJustificationToLeft();
        text->SetVerticalJustificationToCentered();
        float widest = 0.0f, bounds[4];
        for (const Entry& e : entries) {
            painter->ComputeStringBounds(e.name, bounds);
            widest = std::max(widest, bounds[2]);
        }
        const float line = float(legendFontSize) * 1.5f, pad = 0.4f * float(legendFontSize), swatch = 1.8f * float(legendFontSize);
        const float w = pad * 3 + swatch + widest, h = pad * 2 + line * float(entries.size());
        const float right = xAxis->GetPoint2()[0] - 4.0f, top = yAxis->GetPoint2()[1] - 4.0f;
        const float left = right - w, bottom = top - h;
        painter->GetPen()->SetColor(60, 60, 60, 255);
        painter->GetPen()->SetWidth(1.0f);
        painter->GetPen()->SetLineType(vtkPen::SOLID_LINE);
        painter->GetBrush()->SetColor(255, 255, 255, 235);
        painter->DrawRect(left, bottom, w, h);
        for (size_t i = 0; i < entries.size(); ++i) {
            const Entry& e = entries[i];
            const float y = top - pad - line * (float(i) + 0.5f), x = left + pad;
            if (e.kind == 0) {
                painter->GetPen()->SetColor(e.colour[0], e.colour[1], e.colour[2], 255);
                painter->GetPen()->SetWidth(1.5f);
                painter->GetPen()->SetLineType(vtkPen::DASH_LINE);
                painter->DrawLine(x, y, x + swatch, y);
                painter->GetPen()->SetLineType(vtkPen::SOLID_LINE);
            } else if (e.kind == 1) {
                painter->GetPen()->SetColor(255, 255, 255, 255);
                painter->GetPen()->SetWidth(1.0f);
                painter->GetBrush()->SetColor(e.colour[0], e.colour[1], e.colour[2], 255);
                painter->DrawEllipse(x + swatch / 2, y, radius, radius);
            } else {
                painter->GetPen()->SetColor(e.colour[0], e.colour[1], e.colour[2], 255);
                painter->GetPen()->SetWidth(2.5f);
                painter->GetBrush()->SetColor(0, 0, 0, 0);
                painter->DrawEllipse(x + swatch / 2, y, 2.2f * radius, 2.2f * radius);
            }
            painter->DrawString(x + swatch + pad, y, e.name);
            painter->ComputeStringBounds(e.name, bounds);
            note(e.name, x + swatch + pad, y - 0.5f * bounds[3], x + swatch + pad + bounds[2], y + 0.5f * bounds[3],
                 legendFontSize);
        }
        // The legend's box over a point label is a problem the record reports.
        const Box legend{left, bottom, left + w, top};
        if (problems)
            for (const Box& t : taken)
                if (t.overlaps(legend)) {
                    *problems += "chart: the legend covers a point or its label\n";
                    break;
                }
    }
};
vtkStandardNewMacro(AccuracyTimeMarks);

// Colours of the techniques' series: Okabe-Ito (readable by colour-blind readers and in print)
// and four darker hues, in registry order (the eleventh, violet, is `auto`'s); the two references
// are greys (ground truth, not a contender), so they never take a colour from a technique.
constexpr int kColourCount = 11;
const unsigned char kColours[kColourCount][3] = {{0, 114, 178},  {213, 94, 0},   {0, 158, 115},  {204, 121, 167},
                                                 {230, 159, 0},  {86, 180, 233}, {240, 228, 66}, {0, 60, 130},
                                                 {140, 80, 20},  {110, 130, 0},  {120, 0, 160}};
const unsigned char kReferenceGrey[3] = {70, 70, 70};
const unsigned char kRaytracedGrey[3] = {150, 150, 150};

// A technique keeps its colour in every chart: its place among the registry's non-reference
// techniques (the order of `shadowlab list`); names the registry does not know take the colours
// after, in the order they appear.
const unsigned char* seriesColour(const std::string& name, const std::vector<std::string>& series) {
    if (name == "reference") return kReferenceGrey;
    if (name == "raytraced") return kRaytracedGrey;
    size_t index = 0;
    for (const TechniqueDesc* d : allTechniques()) {
        if (d->id == "reference" || d->id == "raytraced") continue;
        if (d->id == name) return kColours[index % kColourCount];
        ++index;
    }
    for (const std::string& s : series) {
        if (s == name) break;
        if (!findTechnique(s)) ++index;
    }
    return kColours[index % kColourCount];
}

bool spansDecades(double lo, double hi) { return lo > 0.0 && hi / lo > 10.0; }

}  // namespace

Rgb8 techniqueChartColour(const std::string& technique) {
    const unsigned char* c = seriesColour(technique, {technique});
    return {c[0], c[1], c[2]};
}

std::vector<size_t> paretoFront(const std::vector<AccuracyTimePoint>& points) {
    std::vector<size_t> order(points.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        if (points[a].timeMs != points[b].timeMs) return points[a].timeMs < points[b].timeMs;
        return points[a].error < points[b].error;
    });
    std::vector<size_t> front;
    double best = INFINITY;
    for (size_t i : order) {
        if (!std::isfinite(points[i].timeMs) || !std::isfinite(points[i].error)) continue;
        if (points[i].error < best) {
            front.push_back(i);
            best = points[i].error;
        }
    }
    return front;
}

vtkSmartPointer<vtkChartXY> buildAccuracyTimeChart(const AccuracyTimePanel& panel, const AccuracyTimeStyle& style) {
    auto chart = vtkSmartPointer<vtkChartXY>::New();
    chart->SetTitle(panel.title.c_str());
    const int font = style.fontSize > 0 ? std::max(kMinTextPx, style.fontSize) : textPx(style.panelHeight);
    chart->GetTitleProperties()->SetFontSize(font + 3);
    chart->GetTitleProperties()->SetBold(true);
    chart->SetShowLegend(false);  // AccuracyTimeMarks draws the legend

    // Ranges decide the scales: log where the values span more than a decade. An error of 0 (a
    // setting equal to the reference) cannot sit on a log axis: it is drawn at the axis floor.
    double tLo = INFINITY, tHi = 0, eLo = INFINITY, eHi = 0;
    for (const AccuracyTimePoint& p : panel.points) {
        if (p.timeMs > 0) tLo = std::min(tLo, p.timeMs), tHi = std::max(tHi, p.timeMs);
        if (p.error > 0) eLo = std::min(eLo, p.error), eHi = std::max(eHi, p.error);
    }
    if (!std::isfinite(tLo)) tLo = 0.01, tHi = 1.0;
    if (!std::isfinite(eLo)) eLo = 1e-4, eHi = 1.0;
    const bool logX = spansDecades(tLo, tHi), logY = spansDecades(eLo, eHi);
    const double eFloor = logY ? eLo / 2.0 : 0.0;

    std::vector<std::string> series;
    for (const AccuracyTimePoint& p : panel.points)
        if (std::find(series.begin(), series.end(), p.series) == series.end()) series.push_back(p.series);

    {
        // vtkChartXY paints nothing (not even its axes) without a visible plot: one invisible point.
        vtkNew<vtkTable> table;
        vtkNew<vtkFloatArray> x, y;
        x->SetName("shadow_ms");
        y->SetName("error");
        table->AddColumn(x);
        table->AddColumn(y);
        table->SetNumberOfRows(1);
        table->SetValue(0, 0, tLo);
        table->SetValue(0, 1, eLo);
        vtkPlot* anchor = chart->AddPlot(vtkChart::POINTS);
        anchor->SetInputData(table, 0, 1);
        anchor->SetColor(255, 255, 255, 0);
        vtkPlotPoints::SafeDownCast(anchor)->SetMarkerStyle(vtkPlotPoints::NONE);
    }
    vtkNew<AccuracyTimeMarks> marks;
    std::vector<size_t> front = paretoFront(panel.points);
    for (size_t i : front) marks->front.push_back(panel.points[i]);
    for (size_t s = 0; s < series.size(); ++s) {
        AccuracyTimeMarks::Series entry;
        std::copy_n(seriesColour(series[s], series), 3, entry.colour);
        for (const AccuracyTimePoint& p : panel.points)
            if (p.series == series[s]) entry.points.push_back(p);
        marks->series.push_back(entry);
        marks->names.push_back(series[s]);
    }

    vtkAxis* xAxis = chart->GetAxis(vtkAxis::BOTTOM);
    vtkAxis* yAxis = chart->GetAxis(vtkAxis::LEFT);
    // Short titles: they must fit the axis at the text standard's size (the README and --help say
    // that the time is the technique's passes only, the median over the frames).
    xAxis->SetTitle(std::string("shadow_ms per frame (median)") + (logX ? ", log scale" : ""));
    yAxis->SetTitle(style.errorName + " against the reference" + (logY ? ", log scale" : ""));
    for (vtkAxis* a : {xAxis, yAxis}) {
        a->GetTitleProperties()->SetFontSize(font + 1);
        a->GetTitleProperties()->SetBold(false);
        a->GetLabelProperties()->SetFontSize(font);
        a->SetNotation(vtkAxis::PRINTF_NOTATION);
        a->SetLabelFormat("%g");
        a->SetBehavior(vtkAxis::FIXED);
        a->SetGridVisible(false);  // AccuracyTimeMarks draws the grid
    }
    xAxis->SetLogScale(logX);
    yAxis->SetLogScale(logY);
    // Room around the points (and for the labels to the right of the last one). With many series the
    // legend (top right, about a third of the plot's width) would cover the slowest points: the axis
    // then runs on until the points fill at most the left 68% of it.
    const double legendRoom = series.size() > 4 ? 1.0 / 0.68 : 1.0;
    if (logX) xAxis->SetUnscaledRange(tLo / 1.6, std::max(tHi * 3.0, tLo / 1.6 * std::pow(1.6 * tHi / tLo, legendRoom)));
    else
        xAxis->SetUnscaledRange(std::max(0.0, tLo - 0.1 * (tHi - tLo) - 1e-3),
                                tHi + std::max(0.35, legendRoom - 1.0) * (tHi - tLo) + 1e-3);
    if (logY) yAxis->SetUnscaledRange(eFloor / 1.5, eHi * 2.0);
    else yAxis->SetUnscaledRange(0.0, eHi * 1.15 + 1e-6);
    marks->xAxis = xAxis;
    marks->yAxis = yAxis;
    marks->logX = logX;
    marks->logY = logY;
    marks->errorFloor = eFloor;
    marks->labels = style.labels;
    marks->fontSize = font;
    marks->legendFontSize = font;
    marks->record = style.record;
    marks->problems = style.problems;
    marks->hiddenLabels = style.hiddenLabels;
    marks->sceneHeight = style.sceneHeight;
    chart->AddItem(marks);  // painted after the axes and the (empty) plots
    return chart;
}

void writeAccuracyTimeChart(const std::vector<AccuracyTimePanel>& panels, const AccuracyTimeStyle& style, int width,
                            int height, const std::string& path, const std::string& extension) {
    if (extension != ".png" && extension != ".svg" && extension != ".pdf")
        throw InputError("chart: expected a .png, .svg or .pdf file, got '" + path + "'");
    if (panels.empty()) throw InputError("chart: nothing to plot (no rows)");
    VtkOffscreen out(width, height);
    vtkNew<vtkContextView> view;
    out.attach(view);
    view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    const int n = int(panels.size());
    const int columns = n <= 1 ? 1 : n <= 4 ? 2 : 3;
    const int rows = (n + columns - 1) / columns;
    const float cw = float(width) / float(columns), ch = float(height) / float(rows);
    std::vector<vtkSmartPointer<vtkChartXY>> charts;
    for (int i = 0; i < n; ++i) {
        AccuracyTimeStyle panelStyle = style;
        panelStyle.panelHeight = int(ch);
        panelStyle.sceneHeight = height;
        vtkSmartPointer<vtkChartXY> chart = buildAccuracyTimeChart(panels[size_t(i)], panelStyle);
        chart->SetAutoSize(false);
        const int col = i % columns, row = i / columns;
        // VTK's scene has y up: the first panel at the top left. The axes' corners are placed with
        // fixed margins (AXES_TO_RECT) rather than from the labels' measured bounds: the PDF device
        // measures the rotated y title as if it were horizontal, which would squeeze the plot.
        // Margins in units of the text size: the y axis' labels and rotated title at the left, the x
        // axis' labels and title under the plot, the chart's title above it.
        const float f = float(style.fontSize > 0 ? std::max(kMinTextPx, style.fontSize) : textPx(int(ch)));
        const float left = 6.0f * f, bottom = 4.0f * f, right = 1.5f * f, top = 2.6f * f;
        chart->SetLayoutStrategy(vtkChart::AXES_TO_RECT);
        chart->SetSize(vtkRectf(float(col) * cw + left, float(rows - 1 - row) * ch + bottom, cw - left - right,
                                ch - bottom - top));
        view->GetScene()->AddItem(chart);
        charts.push_back(chart);
    }
    Image rgba = out.render();
    if (extension == ".png") {
        Image rgb(rgba.width, rgba.height, 3);
        for (size_t i = 0; i < rgb.pixelCount(); ++i)
            for (int c = 0; c < 3; ++c) rgb.data[i * 3 + c] = rgba.data[i * 4 + c];
        writePNG(path, rgb);
        return;
    }
    // The exporter chooses the format by the file's extension: write beside, then move into place.
    const std::string named = path + extension;
    out.exportVector(named);
    std::error_code ec;
    std::filesystem::rename(named, path, ec);
    if (ec) throw InternalError("chart: cannot move " + named + " to " + path + ": " + ec.message());
}

}  // namespace shadowlab
