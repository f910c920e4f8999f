// libFuzzer target: what `figure --remake` reads (app/bench/figure_spec.cpp readFigureSidecar: every
// field typed and ranged, then the recorded spec read with the spec's own rules and the cells
// counted against its rows x columns, as commandFigure does). Bad input must be an InputError;
// anything else (a missing key read through nlohmann's unchecked operator[], a type error, a
// crash) is a finding.
#include "bench/figure_spec.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const std::string path = fuzz::writeInput("figure.png.json", data, size);
    try {
        const JsonDocument doc = JsonDocument::fromFile(path, "figure sidecar");
        const FigureSidecar side = readFigureSidecar(doc);
        const JsonDocument specDoc = JsonDocument::fromString(path + " (field spec)", side.spec);
        const FigureSpec spec = parseFigureSpec(specDoc);
        if (side.cells.size() != spec.rows.size() * spec.columns.size())
            JsonReader(doc).fail("cells", "the spec's rows x columns", "another count");
    } catch (const InputError&) {
    }
    return 0;
}
