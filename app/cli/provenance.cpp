// The command line's side of provenance sidecars (provenance.h).
#include "cli/provenance.h"

#include <algorithm>
#include <cstdio>

#include "error.h"
#include "graph/renderer.h"

namespace shadowlab {

namespace {
std::vector<std::string>& commandLine() {
    static std::vector<std::string> args;
    return args;
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string joinLines(const std::vector<std::string>& lines) {
    std::string out;
    for (const std::string& line : lines) out += "\n  " + line;
    return out;
}
}  // namespace

void rememberCommandLine(const std::vector<std::string>& args) {
    commandLine() = {"shadowlab"};
    commandLine().insert(commandLine().end(), args.begin(), args.end());
}

RenderProvenance renderProvenance(const Scene& scene, const Renderer& renderer, int width,
                                  int height, const std::vector<double>& frameMs,
                                  const std::string& glRenderer) {
    RenderProvenance record;
    record.sceneName = scene.name;
    record.scenePath = scene.path;
    for (const auto& state : renderer.lights()) {
        record.lights.push_back({state->light, state->desc->id, state->params.values()});
    }
    record.width = width;
    record.height = height;
    record.frameMs = median(frameMs);
    // The command times whole frames on the CPU around glFinish, whichever clock times the passes.
    record.clock = "cpu-finish";
    record.glRenderer = glRenderer;
    record.commandLine = commandLine();
    return record;
}

std::string visibilityMeaning(const std::string& technique) {
    return technique == "reference" || technique == "raytraced" ? "reference" : "visibility";
}

void writeRenderPfm(OutputSet& outputs, const std::string& path, const Image& image,
                    const RenderProvenance& render, const std::string& meaning) {
    writePfmWithSidecar(outputs, path, image, provenanceOf(render, meaning));
}

nlohmann::json checkComparedProvenance(const std::string& a, const std::string& b, bool strict) {
    const std::optional<nlohmann::json> pa = readSidecar(a);
    const std::optional<nlohmann::json> pb = readSidecar(b);
    if (strict && (!pa || !pb)) {
        const std::string missing = !pa ? a : b;
        throw InputError("compare --strict: " + missing + " has no provenance sidecar (" +
                         sidecarPath(missing) +
                         "), so its scene, lights and size cannot be checked against the other's");
    }
    if (!pa && !pb) return nullptr;
    nlohmann::json report{{"sidecars", {{"a", pa.has_value()}, {"b", pb.has_value()}}}};
    if (!pa || !pb) return report;
    const std::vector<std::string> differences = provenanceDifferences(*pa, *pb);
    report["differences"] = differences;
    report["technique_differences"] = techniqueDifferences(*pa, *pb);
    if (differences.empty()) return report;
    const std::string what = a + " and " + b +
                             " were rendered with different settings (values as A vs B):" +
                             joinLines(differences);
    if (strict) throw InputError("compare --strict: " + what);
    std::fprintf(stderr,
                 "shadowlab: warning: %s\n  The metrics measure these differences as well as the "
                 "technique's error (--strict refuses such comparisons).\n",
                 what.c_str());
    return report;
}

}  // namespace shadowlab
