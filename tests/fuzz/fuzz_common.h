// Shared by the fuzz targets: the input goes to a file (the loaders read files, and glTF resolves
// buffer URIs next to it) in a private folder, and the limits are small so that a fuzzed scene of
// 100,000 boxes is refused quickly instead of slowing the run (the limit check is what is fuzzed).
#pragma once
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "error.h"
#include "scene/scene.h"

namespace shadowlab::fuzz {

inline const std::filesystem::path& folder() {
    static const std::filesystem::path dir = [] {
        const std::filesystem::path d =
            std::filesystem::temp_directory_path() / ("shadowlab-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d / "scenes");
        std::filesystem::create_directories(d / "models");
        return d;
    }();
    return dir;
}

inline std::string writeInput(const std::string& relative, const uint8_t* data, size_t size) {
    const std::filesystem::path path = folder() / relative;
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path.string();
}

inline SceneLimits fuzzLimits() {
    SceneLimits limits;
    limits.maxTriangles = 200'000;
    return limits;
}

}  // namespace shadowlab::fuzz
