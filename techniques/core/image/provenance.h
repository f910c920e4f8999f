// Provenance of float buffers: every PFM the program writes gets a JSON sidecar "<file>.pfm.json"
// beside it, saying how the buffer was made (scene, lights as rendered, size, technique and
// parameters per light, frame time, program version, GL renderer, command line). `compare` reads
// both sides' sidecars and warns when the settings that decide the picture differ (scene, lights,
// size): comparing a render at --light-size 0.5 with a reference at the default size measures the
// light size, not the technique.
#pragma once
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "scene/scene.h"

namespace shadowlab {

// "<version>" from CMake's project(VERSION), with `git describe` appended when the source was a
// git checkout at configure time: "0.1.0 (334be44-dirty)".
const char* programVersion();

// A light as it was rendered: after --light-size, with the technique that ran for it (a point
// light runs `hard` whatever was asked) and that technique's parameter values.
struct RenderedLight {
    Light light;
    std::string technique;
    std::map<std::string, double> parameters;
};

// Everything a sidecar records about one render, as plain values.
struct RenderProvenance {
    std::string sceneName;
    std::string scenePath;
    std::vector<RenderedLight> lights;
    int width = 0;
    int height = 0;
    double frameMs = 0.0;           // median over the timed frames
    std::string clock;              // how frameMs was measured, e.g. "cpu-finish"
    std::string glRenderer;         // GL_RENDERER of the context
    std::vector<std::string> commandLine;
};

// The sidecar record for one buffer of a render. `meaning` says what the buffer holds:
// "visibility", "positions", "ids" or "reference".
nlohmann::json provenanceOf(const RenderProvenance& render, const std::string& meaning);

// The sidecar's path: "<pfmPath>.json".
std::string sidecarPath(const std::string& pfmPath);

// Stages the PFM and its sidecar in `outputs`: both appear on commit(), neither on failure.
void writePfmWithSidecar(OutputSet& outputs, const std::string& path, const Image& image,
                         const nlohmann::json& provenance);

// The sidecar of `pfmPath`, or nothing when there is none. A sidecar that is not valid JSON or
// not a provenance record is an InputError naming the sidecar file.
std::optional<nlohmann::json> readSidecar(const std::string& pfmPath);

// Human-readable differences between two records in what decides the picture: the scene, the
// lights (each field, with both values: "light 0 \"key\": size 0.5 vs 1") and the size. Empty when
// the two buffers show the same setting.
std::vector<std::string> provenanceDifferences(const nlohmann::json& a, const nlohmann::json& b);
// Differences in technique and parameters per light: information only, since comparing
// techniques is what `compare` is for.
std::vector<std::string> techniqueDifferences(const nlohmann::json& a, const nlohmann::json& b);

}  // namespace shadowlab
