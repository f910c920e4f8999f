// The command line's side of provenance sidecars (core/provenance.h): building the record of a
// render from the renderer's state, and checking the two sides of `compare`.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "image/provenance.h"

namespace shadowlab {

class Renderer;

// Called once with the program's arguments; sidecars record them.
void rememberCommandLine(const std::vector<std::string>& args);

// The record of a finished render: the scene, each light as rendered with its technique and
// parameters, the size, and the median of the timed frames.
RenderProvenance renderProvenance(const Scene& scene, const Renderer& renderer, int width,
                                  int height, const std::vector<double>& frameMs,
                                  const std::string& glRenderer);

// What a visibility buffer rendered with `technique` is: "reference" for the reference
// techniques (reference, raytraced), else "visibility".
std::string visibilityMeaning(const std::string& technique);

// Stages the PFM `path` and its sidecar, recording `meaning`.
void writeRenderPfm(OutputSet& outputs, const std::string& path, const Image& image,
                    const RenderProvenance& render, const std::string& meaning);

// `compare A B`: reads both sidecars. When both exist and the scene, lights or size differ, prints
// a warning listing the differences on stderr; with `strict`, throws an InputError with the same
// list instead, and also when a sidecar is missing. Returns what --json reports ("sidecars",
// "differences", "technique_differences"), or null when neither side has a sidecar.
nlohmann::json checkComparedProvenance(const std::string& a, const std::string& b, bool strict);

}  // namespace shadowlab
