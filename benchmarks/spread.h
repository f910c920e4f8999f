// The spread of a benchmark's per-round times: median, lowest and highest, so a speed claim says
// how much the rounds disagreed (the machine is shared and noisy). Rounds are interleaved: round r
// runs every side once, so a busy moment slows all sides alike.
#pragma once

#include <algorithm>
#include <vector>

#include "graph/renderer.h"

namespace shadowlab::bench {

struct Spread {
    double median = 0.0, lowest = 0.0, highest = 0.0;
};

inline Spread spreadOf(std::vector<double> v) {
    Spread s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    s.lowest = v.front();
    s.highest = v.back();
    return s;
}

// shadow_ms of the frame just rendered as frame `frame` (every pass of it timed: reuse off).
inline double shadowMsOfFrame(Renderer& renderer, int frame) {
    return renderer.stats({}, 0, frame)["shadow_ms"].get<double>();
}

}  // namespace shadowlab::bench
