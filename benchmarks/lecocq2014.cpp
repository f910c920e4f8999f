// Benchmark (not a test) of lecocq2014 on llvmpipe, the claims of issue 23:
//  1. point light (--light-size 0), 512x512, square-occluder, contact (its torus is a glTF model)
//     and plant: pixels misclassified against `raytraced` with rays = 1 (exact hard shadows) by
//     `hard` and by `spsm`, both at sm_size 256 (must: spsm at most a tenth of hard's), and their
//     shadow_ms side by side in one interleaved run (must: spsm at most 1.3x hard's; the paper:
//     14% overhead at 512^2);
//  2. the same at the paper's 512^2 maps;
//  1b. the floor: spsm with neighbourhood 1 and reconstruction off, the build and the look-up's
//     first step alone (every pixel against its texel's triangle, nothing after), beside them;
//  3. the Dai et al. 2008 comparison: spsm with reconstruction off and neighbourhood 3, 5, 7 beside
//     spsm's defaults (accuracy against time), and conservative rasterization off;
//  4. overlapping-occluders: the failure case the paper names (occluder fusion with one triangle
//     per texel), measured the same way.
// One process; the configurations' frames are interleaved (round r renders each once) so that a
// busy machine slows all alike; every pass runs and is timed every frame (reuse off, CPU clock
// around glFinish: llvmpipe's timer queries are wrong); the first round is warm-up, shadow_ms is the
// median of the others, with the lowest and highest round (benchmarks/spread.h).
// Usage: LP_NUM_THREADS=2 shadowlab_bench_lecocq2014 [rounds=5]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "gl/context.h"
#include "graph/renderer.h"
#include "scene/scene.h"
#include "spread.h"

using namespace shadowlab;

namespace {

using Sets = std::vector<std::pair<std::string, std::string>>;

struct Config {
    std::string label, technique;
    Sets sets;
    std::unique_ptr<Renderer> renderer;
    std::vector<double> rounds;
    bench::Spread shadowMs;
    size_t misclassified = 0, pixels = 0;
};

// Pixels whose hard visibility (v > 0.5) differs from the reference's, over the pixels both cover.
void countMisclassified(const Image& test, const Image& reference, size_t& bad, size_t& pixels) {
    bad = pixels = 0;
    for (size_t i = 0; i < test.data.size(); ++i) {
        float a = test.data[i], b = reference.data[i];
        if (!std::isfinite(a) || !std::isfinite(b)) continue;
        ++pixels;
        bad += (a > 0.5f) != (b > 0.5f);
    }
}

void run(const std::string& sceneName, std::vector<Config>& configs, int size, int rounds) {
    Scene scene = loadScene(sceneName);
    RenderOptions ro;
    ro.width = ro.height = size;
    ro.technique = "raytraced";
    ro.sets = {{"rays", "1"}};
    ro.lightSize = 0.0f;
    Renderer exact(scene, ro);
    exact.renderFrame(0, {"visibility"});
    Image reference = exact.visibility();
    for (Config& c : configs) {
        RenderOptions options;
        options.width = options.height = size;
        options.technique = c.technique;
        options.sets = c.sets;
        options.reuse = false;
        options.cpuClock = true;
        options.lightSize = 0.0f;
        c.renderer = std::make_unique<Renderer>(scene, options);
    }
    for (int r = 0; r < rounds + 1; ++r)
        for (Config& c : configs) {
            c.renderer->renderFrame(r, {"visibility"});
            if (r > 0) c.rounds.push_back(bench::shadowMsOfFrame(*c.renderer, r));
        }
    std::printf("\n%s, %dx%d, point light; misclassified against raytraced rays=1 (%s)\n", sceneName.c_str(), size, size,
                "pixels whose v > 0.5 differs");
    std::printf("  %-34s %10s %8s %22s %9s  %s\n", "setting", "misclass.", "of hard", "shadow_ms med [lo, hi]", "x hard",
                "passes (median ms)");
    const Config* hard = nullptr;
    for (Config& c : configs) {
        c.shadowMs = bench::spreadOf(c.rounds);
        countMisclassified(c.renderer->visibility(), reference, c.misclassified, c.pixels);
        if (c.technique == "hard" && !hard) hard = &c;
    }
    for (Config& c : configs) {
        const Config* base = hard;
        for (Config& h : configs)  // the hard shadow map of the same size
            if (h.technique == "hard" && h.sets == Sets{{"sm_size", c.sets.empty() ? "512" : c.sets[0].second}}) base = &h;
        std::printf("  %-34s %10zu %8.3f %8.2f [%6.2f, %6.2f] %9.2f\n", c.label.c_str(), c.misclassified,
                    base ? double(c.misclassified) / double(std::max<size_t>(base->misclassified, 1)) : 0.0,
                    c.shadowMs.median, c.shadowMs.lowest, c.shadowMs.highest,
                    base ? c.shadowMs.median / base->shadowMs.median : 0.0);
        nlohmann::json stats = c.renderer->stats({}, 1, 1);
        std::string passes;
        for (const auto& p : stats["passes"])
            if (p["cost"] == "shadow" && p["runs"].get<int>() > 0) {
                char buf[96];
                std::snprintf(buf, sizeof buf, " %s %.2f", p["name"].get<std::string>().c_str(), p["median_ms"].get<double>());
                passes += buf;
            }
        std::printf("      %s\n", passes.c_str());
    }
    configs.clear();
}

std::vector<Config> configsFor(int smSize, bool dai) {
    std::string s = std::to_string(smSize);
    std::vector<Config> c;
    c.push_back({"hard sm " + s, "hard", {{"sm_size", s}}, {}, {}, {}, 0, 0});
    c.push_back({"spsm sm " + s, "spsm", {{"sm_size", s}}, {}, {}, {}, 0, 0});
    // The floor: the build and the look-up's first step alone (neighbourhood 1, no reconstruction:
    // a ray the texel's own triangle does not decide is lit). What the paper's method costs here
    // before any neighbour or reconstruction: if this row is over 1.3x hard, no work on the later
    // steps can bring spsm under it.
    c.push_back({"spsm sm " + s + " floor: step 1 alone", "spsm",
                 {{"sm_size", s}, {"neighbourhood", "1"}, {"reconstruction", "false"}}, {}, {}, {}, 0, 0});
    if (dai) {
        c.push_back({"spsm sm " + s + " conservative off", "spsm", {{"sm_size", s}, {"conservative", "false"}}, {}, {}, {}, 0, 0});
        for (int k : {3, 5, 7})
            c.push_back({"Dai 2008: k " + std::to_string(k) + ", no reconstruction", "spsm",
                         {{"sm_size", s}, {"neighbourhood", std::to_string(k)}, {"reconstruction", "false"}}, {}, {}, {}, 0, 0});
    }
    return c;
}

}  // namespace

int main(int argc, char** argv) {
    int rounds = argc > 1 ? std::atoi(argv[1]) : 5;
    auto context = createHeadlessContext(GLBackend::Egl);
    std::printf("lecocq2014 benchmark: %d timed rounds after one warm-up, LP_NUM_THREADS=%s\n", rounds,
                std::getenv("LP_NUM_THREADS") ? std::getenv("LP_NUM_THREADS") : "(unset)");
    for (const char* scene : {"square-occluder", "contact", "plant"}) {
        std::vector<Config> c = configsFor(256, std::string(scene) == "contact");
        run(scene, c, 512, rounds);
    }
    for (const char* scene : {"square-occluder", "contact"}) {
        std::vector<Config> c = configsFor(512, false);
        run(scene, c, 512, rounds);
    }
    std::vector<Config> c = configsFor(256, false);
    run("overlapping-occluders", c, 512, rounds);
    return 0;
}
