// The settings an accuracy-time chart compares (compare.h).
#include "bench/compare.h"

#include <cstdio>

#include "auto/auto.h"
#include "bench/bench.h"
#include "graph/technique.h"

namespace shadowlab {

namespace {

ParamValues valuesOf(const TechniqueDesc& desc, const std::vector<std::pair<std::string, std::string>>& sets) {
    ParamValues v(desc);
    for (const auto& [k, text] : sets) v.set(desc, k, text, "chart");
    return v;
}

}  // namespace

// The setting as the chart labels it: the parameters whose value differs from the paper's default
// (by the paper's symbol where it has one: "n=9", "alpha=0.5"; enums by name), or "defaults". Read
// from the values the renderer runs, so a slider moved back to its default reads "defaults" again.
std::string settingLabel(const TechniqueDesc& desc, const ParamValues& values) {
    std::string label;
    for (const ParamDesc& p : desc.params) {
        const double v = values.get(p.key);
        if (v == p.defaultValue) continue;
        char text[64];
        if (p.type == ParamDesc::Type::Enum) std::snprintf(text, sizeof text, "%s", values.getChoice(p.key).c_str());
        else std::snprintf(text, sizeof text, "%g", v);
        label += (label.empty() ? "" : " ") + (p.symbol.empty() ? p.key : p.symbol) + "=" + text;
    }
    return label.empty() ? "defaults" : label;
}

std::vector<ChartSetting> comparedSettings(const std::string& technique, const ParamValues* current) {
    std::vector<ChartSetting> out;
    for (const CalibrationSetting& s : defaultCalibration().settings) {
        const TechniqueDesc& desc = requireTechnique(s.technique, "calibration");
        out.push_back({s.technique, s.sets, settingLabel(desc, valuesOf(desc, s.sets)), false});
    }
    for (const char* budget : {"0.005", "0.02", "0.1"})
        out.push_back({"auto", {{"error_budget", budget}}, std::string("budget ") + budget, false});
    const TechniqueDesc* desc = findTechnique(technique);
    if (!desc) return out;
    const ParamValues shown = current ? *current : ParamValues(*desc);
    for (ChartSetting& s : out)
        if (s.technique == technique && valuesOf(*desc, s.sets).values() == shown.values()) {
            s.current = true;
            return out;
        }
    ChartSetting own{technique, {}, settingLabel(*desc, shown), true};
    for (const ParamDesc& p : desc->params) {
        char text[64];
        if (p.type == ParamDesc::Type::Enum) std::snprintf(text, sizeof text, "%s", shown.getChoice(p.key).c_str());
        else std::snprintf(text, sizeof text, "%.9g", shown.get(p.key));
        own.sets.push_back({p.key, text});
    }
    out.push_back(own);
    return out;
}

AccuracyTimePoint measureChartSetting(const Scene& scene, const std::string& sceneName, int width, int height,
                                      const ChartSetting& setting, const Image& reference, bool cpuClock, int frames) {
    const Measurement m = measureSetting(scene, sceneName, width, height, std::nullopt, Setting{setting.technique, setting.sets},
                                         frames, 1, &reference, cpuClock);
    return {setting.technique, setting.label, m.shadowMs, m.all.rmse, setting.current};
}

}  // namespace shadowlab
