// The bench's rows as the accuracy-versus-time chart (viz/chart_accuracy_time.h): one panel per
// scene and light size, one series per technique, its settings as labelled points.
#pragma once
#include <string>
#include <vector>

#include "bench/bench.h"
#include "chart_accuracy_time.h"

namespace shadowlab {

// The panels of the chart: one per scene (and light size when the rows have several), one series
// per technique, the y value RMSE or 1 - SSIM (`errorMetric`). The window's accuracy-time view can
// build its chart from these with buildAccuracyTimeChart.
std::vector<AccuracyTimePanel> benchChartPanels(const std::vector<Measurement>& rows, const std::string& errorMetric);

// Writes the chart of `rows` to `path` as `extension` (".png", ".svg" or ".pdf"; `path` may be a
// staged temporary name). Needs a current GL context.
void writeBenchChart(const std::vector<Measurement>& rows, const BenchSpec& spec, const std::string& path,
                     const std::string& extension);

}  // namespace shadowlab
