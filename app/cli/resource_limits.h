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
// shadow maps per light, and the scene's geometry (kBytesPerTriangle).
double estimateRenderBytes(const Scene& scene, const RenderOptions& options);
// Throws InputError when estimateRenderBytes exceeds --max-memory-mb (default above).
void checkRenderMemory(const Scene& scene, const RenderOptions& options, const Options& opts);
// Throws InputError when two of the (flag, path) outputs name the same file.
void checkDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& outputs);
// Prints the scene's warnings to stderr ("shadowlab: warning: ...").
void printSceneWarnings(const Scene& scene);

}  // namespace shadowlab
