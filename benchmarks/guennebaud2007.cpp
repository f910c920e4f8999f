// Benchmark (not a test) of guennebaud2007 sections 3-4 on llvmpipe:
//  1. the HSM build's share of shadow_ms (the technique's passes) on `plant` at 768x768 with a 1024^2
//     map (the paper: under 1 ms for a 1k x 1k HSM on its GeForce 8800, sec. 7.1);
//  2. ssm-contour against ssm-gbp06 at three light sizes (the paper: contour up to 1.5x faster on its
//     GPU, 4-10x on the CPU, sec. 7.1).
// Every pass runs every frame (no reuse) and is timed on the CPU around glFinish (llvmpipe's timer
// queries are wrong); medians over the timed frames after one warm-up frame. In part 2 the two
// techniques' frames are interleaved (round r renders contour, then gbp06) and each round's
// shadow_ms ratio is kept, so the speed-up comes with its spread over the rounds.
// Usage: LP_NUM_THREADS=2 shadowlab_bench_guennebaud2007 [scene] [size1] [size2] [frames]
#include <chrono>
#include <memory>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gl/context.h"
#include "graph/renderer.h"
#include "scene/scene.h"
#include "spread.h"

using namespace shadowlab;

namespace {

struct PassTimes {
    double shadowMs = 0.0, hsmMs = 0.0, kernelMs = 0.0, visibilityMs = 0.0, mapMs = 0.0;
};

PassTimes run(const Scene& scene, const std::string& technique, int size, int frames, std::optional<float> lightSize) {
    RenderOptions options;
    options.width = options.height = size;
    options.technique = technique;
    options.reuse = false;
    options.cpuClock = true;
    options.lightSize = lightSize;
    Renderer renderer(scene, options);
    std::vector<double> frameMs;
    for (int f = 0; f < frames + 1; ++f) {
        glFinish();
        auto t0 = std::chrono::steady_clock::now();
        renderer.renderFrame(f, {"image", "visibility"});
        glFinish();
        frameMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    nlohmann::json stats = renderer.stats(frameMs, 1);
    PassTimes t;
    t.shadowMs = stats["shadow_ms"].get<double>();
    for (const auto& p : stats["passes"]) {
        std::string name = p["name"];
        double ms = p["median_ms"].get<double>();
        auto ends = [&](const std::string& s) { return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0; };
        if (ends("/hsm")) t.hsmMs = ms;
        if (ends("/kernel")) t.kernelMs = ms;
        if (ends("/visibility")) t.visibilityMs = ms;
        if (ends("/shadow_map")) t.mapMs = ms;
    }
    return t;
}

}  // namespace

int main(int argc, char** argv) {
    std::string sceneName = argc > 1 ? argv[1] : "plant";
    int size1 = argc > 2 ? std::atoi(argv[2]) : 768;
    int size2 = argc > 3 ? std::atoi(argv[3]) : 384;
    int frames = argc > 4 ? std::atoi(argv[4]) : 3;
    auto context = createHeadlessContext(GLBackend::Egl);
    Scene scene = loadScene(sceneName);
    const char* threads = std::getenv("LP_NUM_THREADS");
    std::printf("guennebaud2007 on %s, clock cpu-finish, LP_NUM_THREADS=%s, median of %d frames after 1 warm-up, "
                "sm_size 1024\n",
                sceneName.c_str(), threads ? threads : "unset", frames);

    std::printf("\n1. HSM build share of shadow_ms at %dx%d\n", size1, size1);
    std::printf("  %-12s %10s %10s %10s %10s %10s %8s\n", "technique", "shadow_ms", "map", "hsm", "kernel", "visibility",
                "hsm %");
    for (const char* technique : {"ssm-contour", "ssm-gbp06"}) {
        PassTimes t = run(scene, technique, size1, frames, {});
        std::printf("  %-12s %10.1f %10.1f %10.1f %10.1f %10.1f %7.1f%%\n", technique, t.shadowMs, t.mapMs, t.hsmMs,
                    t.kernelMs, t.visibilityMs, 100.0 * t.hsmMs / t.shadowMs);
    }

    std::printf("\n2. ssm-contour vs ssm-gbp06 at %dx%d by light size (world units; the scene's is %.2f)\n", size2, size2,
                scene.lights.empty() ? 0.0 : double(scene.lights[0].size));
    std::printf("  %-10s %14s %14s %14s %14s %10s\n", "light", "contour vis", "gbp06 vis", "contour shadow",
                "gbp06 shadow", "speed-up");
    for (float lightSize : {0.5f, 1.0f, 2.0f}) {
        std::unique_ptr<Renderer> sides[2];
        const char* names[2] = {"ssm-contour", "ssm-gbp06"};
        for (int k = 0; k < 2; ++k) {
            RenderOptions options;
            options.width = options.height = size2;
            options.technique = names[k];
            options.reuse = false;
            options.cpuClock = true;
            options.lightSize = lightSize;
            sides[k] = std::make_unique<Renderer>(scene, options);
        }
        std::vector<double> shadow[2], ratios;
        for (int f = 0; f < frames + 1; ++f) {
            for (int k = 0; k < 2; ++k) {
                sides[k]->renderFrame(f, {"image", "visibility"});
                if (f > 0) shadow[k].push_back(bench::shadowMsOfFrame(*sides[k], f));
            }
            if (f > 0) ratios.push_back(shadow[1].back() / shadow[0].back());
        }
        auto visibilityMs = [](Renderer& r) {
            const nlohmann::json stats = r.stats({}, 1);  // kept: a loop over a temporary's member dangles
            for (const auto& p : stats["passes"]) {
                const std::string name = p["name"];
                if (name.size() >= 11 && name.compare(name.size() - 11, 11, "/visibility") == 0) return p["median_ms"].get<double>();
            }
            return 0.0;
        };
        const bench::Spread c = bench::spreadOf(shadow[0]), g = bench::spreadOf(shadow[1]), q = bench::spreadOf(ratios);
        std::printf("  %-10.2f %11.1f ms %11.1f ms %11.1f ms %11.1f ms %9.2fx   rounds: contour %.1f-%.1f, gbp06 %.1f-%.1f ms, "
                    "ratio %.2f-%.2f\n",
                    lightSize, visibilityMs(*sides[0]), visibilityMs(*sides[1]), c.median, g.median, q.median, c.lowest,
                    c.highest, g.lowest, g.highest, q.lowest, q.highest);
    }
    return 0;
}
