// libFuzzer target: the glTF path (tinygltf parse, extensions, node tree, accessors, limits). The
// input is written as .glb when it starts with the binary magic "glTF", else as .gltf. Bad input
// must be an InputError; any other exception or a crash is a finding (scripts/fuzz.sh).
#include <cstring>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const std::string path = fuzz::writeInput(binary ? "models/model.glb" : "models/model.gltf", data, size);
    try {
        std::vector<std::string> warnings;
        const Mesh mesh = loadGltfMesh(path, fuzz::fuzzLimits(), &warnings);
        (void)mesh;
    } catch (const InputError&) {
    }
    return 0;
}
