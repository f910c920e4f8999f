// libFuzzer target: the scene-file loader (JSON parse, schema, limits, primitives, generators).
// Bad input must be an InputError; any other exception or a crash is a finding (scripts/fuzz.sh).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const std::string path = fuzz::writeInput("scenes/scene.json", data, size);
    try {
        const Scene scene = loadScene(path, fuzz::fuzzLimits());
        (void)scene.bounds(0.0);
    } catch (const InputError&) {
    }
    return 0;
}
