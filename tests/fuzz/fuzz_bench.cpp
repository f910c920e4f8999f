// libFuzzer target: the bench spec reader (app/bench/spec.cpp loadBenchSpec: fields, ranges, runs,
// the reference spec, paper rows; every scene it names is loaded, every technique, key and value
// checked against the registry). Bad input must be an InputError; anything else is a finding.
#include "bench/bench.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const std::string path = fuzz::writeInput("bench.json", data, size);
    try {
        const BenchSpec spec = loadBenchSpec(path);
        for (const RunSpec& run : spec.runs) (void)run.settings();
    } catch (const InputError&) {
    }
    return 0;
}
