// The bench's rows as accuracy-versus-time charts (bench_chart.h).
#include "bench/chart.h"

#include <algorithm>
#include <cstdio>

#include "chart_accuracy_time.h"

namespace shadowlab {

namespace {

// A setting's label on the chart: its swept values without the keys when there is one key
// ("9"), else "key=value" pairs; "default" for a technique at its defaults.
std::string pointLabel(const Setting& s) {
    if (s.sets.empty()) return "default";
    if (s.sets.size() == 1) {
        const auto& [k, v] = s.sets[0];
        if (k == "pcf_kernel") return "n=" + v;
        if (k == "samples") return "N=" + v;
        if (k == "rays") return "M=" + v;
    }
    return s.describe();
}

}  // namespace

std::vector<AccuracyTimePanel> benchChartPanels(const std::vector<Measurement>& rows, const std::string& errorMetric) {
    std::vector<AccuracyTimePanel> panels;
    bool severalSizes = false;
    for (const Measurement& a : rows)
        for (const Measurement& b : rows)
            if (a.scene == b.scene && a.lightSize != b.lightSize) severalSizes = true;
    for (const Measurement& m : rows) {
        char title[256];
        if (severalSizes)
            std::snprintf(title, sizeof title, "%s, light size %g", m.scene.c_str(), m.lightSize);
        else
            std::snprintf(title, sizeof title, "%s", m.scene.c_str());
        auto it = std::find_if(panels.begin(), panels.end(), [&](const AccuracyTimePanel& p) { return p.title == title; });
        if (it == panels.end()) {
            panels.push_back({title, {}});
            it = panels.end() - 1;
        }
        it->points.push_back({m.setting.technique, pointLabel(m.setting), m.shadowMs, errorOf(m, errorMetric), false});
    }
    return panels;
}

void writeBenchChart(const std::vector<Measurement>& rows, const BenchSpec& spec, const std::string& path,
                     const std::string& extension) {
    std::vector<AccuracyTimePanel> panels = benchChartPanels(rows, spec.errorMetric);
    AccuracyTimeStyle style;
    style.errorName = spec.errorMetric == "1-ssim" ? "1 - SSIM" : "RMSE";
    const int columns = panels.size() <= 1 ? 1 : panels.size() <= 4 ? 2 : 3;
    const int panelRows = int((panels.size() + size_t(columns) - 1) / size_t(columns));
    writeAccuracyTimeChart(panels, style, 720 * columns, 500 * panelRows, path, extension);
}

}  // namespace shadowlab
