// Limits that keep heavy input from exhausting the machine (docs/robustness.md): the scene's
// triangles (--max-triangles) and a render's memory (--max-memory-mb), both estimated before
// anything is allocated, and checks that outputs do not collide.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "cli/cli.h"
#include "graph/renderer.h"
#include "scene/scene.h"

namespace shadowlab {

// Default of --max-memory-mb: a render estimated above this many MB is refused (exit 2).
constexpr int kDefaultMaxMemoryMB = 4096;

// SceneLimits from --max-triangles (default SceneLimits{}).
SceneLimits sceneLimitsFrom(const Options& opts);
// Estimated bytes a render needs: frame textures on the GPU and read-backs on the CPU per pixel,
// every resource each light's technique declares at its parameters (techniqueResourceBytes: shadow
// maps, pyramids, light-space buffers), and the scene's geometry (kBytesPerTriangle).
double estimateRenderBytes(const Scene& scene, const RenderOptions& options);
// Throws InputError when estimateRenderBytes exceeds --max-memory-mb (default above).
void checkRenderMemory(const Scene& scene, const RenderOptions& options, const Options& opts);
// Throws InputError when two of the (flag, path) outputs name the same file.
void checkDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& outputs);

// A command's output plan (issue 24): every final path it will write, sidecars and implicit
// outputs included, checked before any work starts. check() refuses (InputError, exit 2, naming
// the flag and the user's path) two outputs that are the same file after normalisation
// (`p.png` and `./p.png`, `--stats v.pfm.json` and `--visibility v.pfm`'s sidecar), an output
// inside a folder another output fills (`--internals I --visibility I/shadow_map.pfm`), an output
// path that is a folder (the output's or its sidecar's), a missing folder and a folder that cannot
// take the file. The files are then written through one OutputSet, committed all at once.
class OutputPlan {
public:
    // A file; `what` names it in messages ("--visibility").
    void file(const std::string& what, const std::string& path);
    // A PFM and its provenance sidecar "<path>.json" (named "<what>'s sidecar").
    void fileWithSidecar(const std::string& what, const std::string& path);
    // A folder the command creates or fills (--internals): no other output may lie inside it.
    void folder(const std::string& what, const std::string& path);
    void check() const;

private:
    struct Entry {
        std::string what, path;
        bool folder = false;
    };
    std::vector<Entry> entries_;
};
// Prints the scene's warnings to stderr ("shadowlab: warning: ...").
void printSceneWarnings(const Scene& scene);

}  // namespace shadowlab
