// libFuzzer target: the figure spec reader (app/bench/figure_spec.cpp parseFigureSpec: size and
// supersample bounds, columns checked against the registry, rows' scenes loaded, row sets checked
// against the columns' techniques, cameras, insets within the cell). Bad input must be an
// InputError; anything else is a finding. A spec that is accepted must also survive its own
// sidecar: `figure --remake` reads specJson(spec) with the same rules, so that text must parse to
// the same spec (a difference aborts, and libFuzzer keeps the input).
#include <cstdio>
#include <cstdlib>

#include "bench/figure_spec.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const std::string path = fuzz::writeInput("figure.json", data, size);
    FigureSpec spec;
    try {
        spec = parseFigureSpec(JsonDocument::fromFile(path, "figure spec"));
    } catch (const InputError&) {
        return 0;
    }
    const std::string written = specJson(spec).dump();
    try {
        const FigureSpec again = parseFigureSpec(JsonDocument::fromString("sidecar spec", written));
        if (specJson(again).dump() != written) {
            std::fprintf(stderr, "fuzz_figure: the sidecar's spec reads back differently:\n%s\n%s\n", written.c_str(),
                         specJson(again).dump().c_str());
            std::abort();
        }
    } catch (const InputError& e) {
        std::fprintf(stderr, "fuzz_figure: the sidecar's spec is refused: %s\n%s\n", e.what(), written.c_str());
        std::abort();
    }
    return 0;
}
