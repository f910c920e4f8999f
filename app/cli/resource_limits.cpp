#include "cli/resource_limits.h"

#include <cstdio>
#include <filesystem>

#include "error.h"

namespace shadowlab {

namespace fs = std::filesystem;

SceneLimits sceneLimitsFrom(const Options& opts) {
    SceneLimits limits;
    if (opts.has("--max-triangles")) {
        const std::string text = opts.get("--max-triangles");
        char* end = nullptr;
        const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
        if (text.empty() || text[0] == '-' || *end != '\0' || v < 1 || v > 4'000'000'000ull)
            throw InputError("--max-triangles: expected a whole number in 1..4000000000, got '" + text + "'");
        limits.maxTriangles = v;
    }
    return limits;
}

double estimateRenderBytes(const Scene& scene, const RenderOptions& options) {
    // Per pixel on the GPU: G-buffer position, normal, material (RGBA32F, 16 B each), depth-stencil
    // (8 B), visibility (4 B), image (16 B), and one R32F visibility per light; on the CPU, the
    // read-backs (image, visibility, positions, ids as floats) and their staging: about 48 B.
    size_t lights = scene.lights.size();
    const double perPixel = 48.0 + 8.0 + 4.0 + 16.0 + 4.0 * double(lights) + 48.0;
    double bytes = perPixel * double(options.width) * double(options.height);
    // Shadow maps: sm_size^2 depths (and a copy) per light; 1024 unless --set sm_size says.
    double smSize = 1024.0;
    for (const auto& [key, value] : options.sets)
        if (key == "sm_size") smSize = std::atof(value.c_str());
    bytes += double(lights) * smSize * smSize * 8.0;
    uint64_t triangles = 0;
    for (const Object& o : scene.objects) triangles += o.mesh.triangleCount();
    bytes += double(triangles) * double(kBytesPerTriangle);
    return bytes;
}

void checkRenderMemory(const Scene& scene, const RenderOptions& options, const Options& opts) {
    const int limitMB = opts.getInt("--max-memory-mb", kDefaultMaxMemoryMB, 16, 1 << 20);
    const double bytes = estimateRenderBytes(scene, options);
    if (bytes > double(limitMB) * 1e6) {
        throw InputError("this render would need about " + describeBytes(bytes) + " of memory (" +
                         std::to_string(options.width) + "x" + std::to_string(options.height) + " frame buffers, " +
                         std::to_string(scene.lights.size()) + " shadow map(s), the scene's geometry), over the limit of " +
                         std::to_string(limitMB) + " MB (--max-memory-mb N raises it)");
    }
}

void checkDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
    std::vector<std::pair<std::string, fs::path>> seen;
    for (const auto& [flag, path] : outputs) {
        if (path.empty()) continue;
        std::error_code ec;
        fs::path canonical = fs::weakly_canonical(fs::absolute(path), ec);
        if (ec) canonical = fs::absolute(path).lexically_normal();
        for (const auto& [otherFlag, otherPath] : seen)
            if (otherPath == canonical)
                throw InputError(otherFlag + " and " + flag + " name the same file '" + path +
                                 "': each output needs its own file");
        seen.push_back({flag, canonical});
    }
}

void printSceneWarnings(const Scene& scene) {
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "shadowlab: warning: %s\n", w.c_str());
}

}  // namespace shadowlab
