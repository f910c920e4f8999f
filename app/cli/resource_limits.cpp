#include "scene/input_file.h"
#include "cli/resource_limits.h"
#include "image/image.h"

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
    // Each light's technique: the resources its passes declare at these parameters (shadow maps,
    // pyramids, light-space buffers, per-pixel textures), as the pool will allocate them.
    // Resolved as the renderer resolves them (--light-size, a point light's `hard`, `auto`'s choice).
    for (const LightState& l : Renderer::resolveLights(scene, options))
        if (l.runs()) bytes += techniqueResourceBytes(*l.desc, l.params, {options.width, options.height});
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
                         std::to_string(scene.lights.size()) + " light(s)' technique resources, the scene's geometry), over the limit of " +
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

namespace {

fs::path normalised(const std::string& path) {
    std::error_code ec;
    fs::path canonical = fs::weakly_canonical(fs::absolute(path), ec);
    if (ec) canonical = fs::absolute(path).lexically_normal();
    // "dir/" and "dir" are one folder.
    if (!canonical.has_filename() && canonical.has_parent_path()) canonical = canonical.parent_path();
    return canonical;
}

bool inside(const fs::path& path, const fs::path& folder) {
    auto p = path.begin();
    for (auto f = folder.begin(); f != folder.end(); ++f, ++p)
        if (p == path.end() || *p != *f) return false;
    return p != path.end();
}

}  // namespace

void OutputPlan::file(const std::string& what, const std::string& path) {
    if (!path.empty()) entries_.push_back({what, path, false});
}

void OutputPlan::fileWithSidecar(const std::string& what, const std::string& path) {
    if (path.empty()) return;
    file(what, path);
    file(what + "'s sidecar", path + ".json");
}

void OutputPlan::folder(const std::string& what, const std::string& path) {
    if (!path.empty()) entries_.push_back({what, path, true});
}

void OutputPlan::check() const {
    for (const Entry& e : entries_) checkPathName(e.what, e.path);  // before any file system call
    std::vector<fs::path> paths;
    for (const Entry& e : entries_) paths.push_back(normalised(e.path));
    for (size_t i = 0; i < entries_.size(); ++i) {
        const Entry& e = entries_[i];
        for (size_t j = 0; j < i; ++j) {
            const Entry& o = entries_[j];
            if (paths[i] == paths[j])
                throw InputError(o.what + " and " + e.what + " name the same " + (e.folder || o.folder ? "path" : "file") +
                                 " '" + (e.path == o.path ? e.path : o.path + "' and '" + e.path) +
                                 "': each output needs its own file");
            if (o.folder && inside(paths[i], paths[j]))
                throw InputError(e.what + " '" + e.path + "' is inside the folder '" + o.path + "' that " + o.what +
                                 " fills: give it a path outside that folder");
            if (e.folder && inside(paths[j], paths[i]))
                throw InputError(o.what + " '" + o.path + "' is inside the folder '" + e.path + "' that " + e.what +
                                 " fills: give it a path outside that folder");
        }
    }
    for (const Entry& e : entries_) {
        std::error_code ec;
        const fs::path parent = fs::path(e.path).parent_path();
        if (!parent.empty() && !fs::is_directory(parent, ec))
            throw InputError(e.what + ": folder '" + parent.string() + "' does not exist");
        const fs::file_status status = fs::status(e.path, ec);
        if (e.folder) {
            if (fs::exists(status) && !fs::is_directory(status))
                throw InputError(e.what + ": '" + e.path + "' exists and is not a folder");
            if (!fs::exists(status)) checkOutputWritable((fs::path(e.path).lexically_normal() / "").parent_path().string());
            continue;
        }
        if (fs::is_directory(status)) throw InputError(e.what + ": '" + e.path + "' is a folder, expected a file path");
        if (fs::exists(status) && !fs::is_regular_file(status))
            throw InputError(e.what + ": '" + e.path + "' is not a regular file (a FIFO, a device or a socket), expected a file path");
        checkOutputWritable(e.path);
    }
}

void printSceneWarnings(const Scene& scene) {
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "shadowlab: warning: %s\n", w.c_str());
}

}  // namespace shadowlab
