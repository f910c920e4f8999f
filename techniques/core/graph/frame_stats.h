// What a frame costs (DESIGN.md section 3, "Show what accuracy costs in time"): the time of every
// pass the last request needed, split into shadow cost (a technique's passes, all lights: what every
// speed claim compares) and fixed cost (G-buffer and shading: the same for every technique).
#pragma once
#include <string>
#include <vector>

#include "graph/pass_graph.h"

namespace shadowlab {

struct PassCost {
    std::string name;
    std::string group;
    std::string technique;  // "" for the frame's own passes (fixed cost)
    bool needed = false;    // needed by the last request: only these count
    double medianMs = 0.0;  // median of the pass's runs at frames >= costFrom (0 when none)
    bool isShadow() const { return !technique.empty(); }
};

struct FrameCost {
    double shadowMs = 0.0;  // the technique passes that were needed, all lights
    double fixedMs = 0.0;   // the frame passes that were needed
    std::vector<PassCost> passes;  // every pass of the graph, in graph order
    double costMs() const { return shadowMs + fixedMs; }
    // The median of one pass by name (0 when the pass does not exist or never ran).
    double passMs(const std::string& name) const;
};

// The cost of a frame where every needed pass runs: each needed pass's median time over its runs
// at frame numbers >= costFrom.
FrameCost frameCost(const PassGraph& graph, const std::vector<std::string>& needed, int costFrom);

// Median of a list of times (0 for an empty list; the mean of the two middle values for an even one).
double medianMs(std::vector<double> times);

}  // namespace shadowlab
