// The accuracy-versus-time chart (issue 8, DESIGN.md section 1: "show what accuracy costs in
// time"): error (RMSE, or 1 - SSIM) against shadow_ms, one series per technique with its settings as
// labelled points, the Pareto front drawn, axes with units, log scales where the values span more
// than a decade. Built with VTK's charts (vtkChartXY in a vtkContextView); `bench --plot` writes it
// as PNG, SVG or PDF, and the window's accuracy-time view can build the same chart from the same
// points (with the current setting highlighted) and show it through VtkOffscreen.
//
//   AccuracyTimePanel panel{"square-occluder", points};
//   vtkSmartPointer<vtkChartXY> chart = buildAccuracyTimeChart(panel, style);
//   VtkOffscreen out(900, 600); vtkNew<vtkContextView> view; out.attach(view);
//   view->GetScene()->AddItem(chart); Image rgba = out.render();
#pragma once
#include <string>
#include <vector>

#include <vtkChartXY.h>
#include <vtkSmartPointer.h>

#include "text_box.h"

namespace shadowlab {

struct AccuracyTimePoint {
    std::string series;  // the technique: one series (colour, legend entry) per distinct name
    std::string label;   // the setting, drawn beside the point ("n=9", "N=64")
    double timeMs = 0.0; // x: shadow_ms
    double error = 0.0;  // y: RMSE or 1 - SSIM (>= 0; zero is drawn at the axis floor)
    bool highlight = false;  // the window's current setting: a ring around the point
};

struct AccuracyTimePanel {
    std::string title;
    std::vector<AccuracyTimePoint> points;
};

struct AccuracyTimeStyle {
    std::string errorName = "RMSE";  // "RMSE" or "1 - SSIM": the y axis title
    // Text in px (tick labels, point labels, legend; titles a little larger), never under 14; 0: the
    // text standard's size for a panel `panelHeight` high (viz/style.h textPx).
    int fontSize = 0;
    int panelHeight = 480;
    bool labels = true;              // draw each point's label (one that finds no free place is left out)
    // The layout record (optional, for tests): every text with its box, in a picture `sceneHeight`
    // high; problems found while painting; point labels left out.
    std::vector<TextBox>* record = nullptr;
    std::string* problems = nullptr;
    int* hiddenLabels = nullptr;
    int sceneHeight = 0;
};

// The colour of a technique's series (8-bit RGB), fixed by its place in the registry; the two
// references (reference, raytraced) are greys.
struct Rgb8 {
    unsigned char r, g, b;
};
Rgb8 techniqueChartColour(const std::string& technique);

// Indices of the points on the Pareto front (no other point is both faster and more accurate),
// sorted by time. Ties in time keep the more accurate point.
std::vector<size_t> paretoFront(const std::vector<AccuracyTimePoint>& points);

// One chart. The series appear in the order their names first occur; a technique's colour is fixed
// by its place in the registry (the same in every chart and in the window).
vtkSmartPointer<vtkChartXY> buildAccuracyTimeChart(const AccuracyTimePanel& panel, const AccuracyTimeStyle& style);

// The panels in a grid (columns x rows chosen from their count) rendered at width x height and
// written to `path` as `extension`: ".png" (rendered), ".svg" or ".pdf" (VTK's vector exporters).
// `path` may be a staged temporary. Needs a current GL context. InputError for another extension.
void writeAccuracyTimeChart(const std::vector<AccuracyTimePanel>& panels, const AccuracyTimeStyle& style, int width,
                            int height, const std::string& path, const std::string& extension);

}  // namespace shadowlab
