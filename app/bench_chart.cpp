#include "bench_chart.h"

#include "error.h"

namespace shadowlab {

void writeBenchChart(const std::vector<Measurement>&, const BenchSpec&, const std::string&, const std::string&) {
    throw InternalError("the chart needs the VTK bridge (not merged yet)");
}

}  // namespace shadowlab
