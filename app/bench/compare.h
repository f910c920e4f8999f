// The settings an accuracy-time chart compares when it is asked to place "every technique" (a lesson
// step's `show accuracy-time`, the window's chart): every setting `auto` chooses among (the default
// calibration's: each registered technique at its defaults) and `auto` itself at the error budgets
// 0.005, 0.02 and 0.1; the setting being shown is marked, and added when it is none of them. Each is
// measured as the bench measures (measureSetting: every pass run and timed every frame) against one
// reference, so the lesson's chart, the window's and `bench --plot` place a setting alike.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "chart_accuracy_time.h"
#include "image/image.h"
#include "scene/scene.h"

namespace shadowlab {

class ParamValues;
struct TechniqueDesc;

struct ChartSetting {
    std::string technique;
    std::vector<std::pair<std::string, std::string>> sets;  // --set text
    std::string label;                                      // "defaults", "budget 0.02", "n=9"
    bool current = false;                                   // the setting being shown
};

// The chart's label of a setting: the parameters that differ from the paper's defaults, by symbol
// ("n=9 alpha=0.5"), or "defaults".
std::string settingLabel(const TechniqueDesc& desc, const ParamValues& values);

// `technique` and `current` (its values; null: its defaults) are the setting being shown.
std::vector<ChartSetting> comparedSettings(const std::string& technique, const ParamValues* current);

// One setting on `scene` as given (its lights and camera), width x height: shadow_ms (median of
// `frames` after one warm-up) and RMSE of v against `reference`. Needs a current GL context.
AccuracyTimePoint measureChartSetting(const Scene& scene, const std::string& sceneName, int width, int height,
                                      const ChartSetting& setting, const Image& reference, bool cpuClock,
                                      int frames = 2);

}  // namespace shadowlab
