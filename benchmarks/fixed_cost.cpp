// Benchmark (not a test): the fixed cost of a frame (G-buffer, combine, shade) before and after core
// stage two, as ratios of a trivial full-screen pass timed in the same run, on `plant` at 512x512.
//   before: combine.frag and shade.frag, each looping over MAX_LIGHTS = 8 (shaders/bench/legacy_*)
//   after:  one shade pass writing visibility and image, LIGHT_COUNT injected as a define
// Every pass is timed on the CPU around glFinish (llvmpipe's timer queries are wrong), interleaved,
// median over the runs. Usage: LP_NUM_THREADS=2 shadowlab_bench_fixed_cost [scene] [size] [runs]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "gl/context.h"
#include "graph/renderer.h"
#include "scene/scene.h"
#include "spread.h"

using namespace shadowlab;

namespace {
double timeMs(const std::function<void()>& run) {
    glFinish();
    auto t0 = std::chrono::steady_clock::now();
    run();
    glFinish();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
}  // namespace

int main(int argc, char** argv) {
    std::string sceneName = argc > 1 ? argv[1] : "plant";
    int size = argc > 2 ? std::atoi(argv[2]) : 512;
    int runs = argc > 3 ? std::atoi(argv[3]) : 15;
    auto context = createHeadlessContext(GLBackend::Egl);
    Scene scene = loadScene(sceneName);
    RenderOptions options;
    options.width = options.height = size;
    options.technique = "hard";
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"image", "visibility"});
    const ResourcePool& pool = renderer.pool();
    const Texture& position = pool.find("frame/gbuffer.position")->texture;
    const Texture& normal = pool.find("frame/gbuffer.normal")->texture;
    const Texture& material = pool.find("frame/gbuffer.material")->texture;
    int lights = int(renderer.lights().size());

    Texture scalar(size, size, GL_R32F), color(size, size, GL_RGBA32F), scalar2(size, size, GL_R32F);
    Framebuffer scalarFbo({&scalar}, nullptr), colorFbo({&color}, nullptr), bothFbo({&scalar2, &color}, nullptr);
    ShaderProgram trivial("common/fullscreen.vert", "bench/trivial.frag");
    trivial.set("gPosition", 0);
    ShaderProgram oldCombine("common/fullscreen.vert", "bench/legacy_combine.frag");
    ShaderProgram oldShade("common/fullscreen.vert", "bench/legacy_shade.frag");
    ShaderProgram newShade("common/fullscreen.vert", "common/shade.frag", {"LIGHT_COUNT " + std::to_string(lights)});
    auto bindInputs = [&](const ShaderProgram& p, bool legacy) {
        p.use();
        if (legacy) p.set("lightCount", lights);
        for (int i = 0; i < lights; ++i) {
            const LightState& l = *renderer.lights()[size_t(i)];
            std::string idx = "[" + std::to_string(i) + "]";
            p.set(("lightPositions" + idx).c_str(), l.light.position);
            p.set(("lightRadiance" + idx).c_str(), l.light.color * l.light.intensity);
            glBindTextureUnit(GLuint(3 + i), pool.find(l.group + "/visibility")->texture.id());
            p.set(("lightVisibility" + idx).c_str(), 3 + i);
        }
        glBindTextureUnit(0, position.id());
        glBindTextureUnit(1, normal.id());
        glBindTextureUnit(2, material.id());
        p.set("gPosition", 0);
        p.set("gNormal", 1);
        p.set("gMaterial", 2);
        p.set("ambient", scene.ambient);
    };
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    std::vector<double> tTrivial, tOldCombine, tOldShade, tNewShade, tGBuffer;
    for (int r = 0; r < runs + 2; ++r) {  // two warm-up rounds
        auto trivialPass = [&] { glBindTextureUnit(0, position.id()); trivial.use(); scalarFbo.bind(size, size); drawFullscreenTriangle(); };
        // The G-buffer first; then one untimed read of it, so that the first timed reader does not pay
        // for the driver making the freshly rendered textures readable.
        renderer.invalidate();
        double g = timeMs([&] { renderer.renderFrame(0, {"gbuffer"}); });
        glDisable(GL_DEPTH_TEST);
        trivialPass();
        double a = timeMs(trivialPass);
        double b = timeMs([&] { bindInputs(oldCombine, true); scalarFbo.bind(size, size); drawFullscreenTriangle(); });
        double c = timeMs([&] { bindInputs(oldShade, true); colorFbo.bind(size, size); drawFullscreenTriangle(); });
        double d = timeMs([&] { bindInputs(newShade, false); bothFbo.bind(size, size); drawFullscreenTriangle(); });
        if (r < 2) continue;
        tTrivial.push_back(a);
        tOldCombine.push_back(b);
        tOldShade.push_back(c);
        tNewShade.push_back(d);
        tGBuffer.push_back(g);
    }
    double trivialMs = median(tTrivial), gbufferMs = median(tGBuffer);
    double oldFixed = gbufferMs + median(tOldCombine) + median(tOldShade);
    double newFixed = gbufferMs + median(tNewShade);
    std::printf("fixed cost on %s at %dx%d, %d light(s), %d runs, clock cpu-finish, LP_NUM_THREADS=%s\n",
                sceneName.c_str(), size, size, lights, runs, getenv("LP_NUM_THREADS") ? getenv("LP_NUM_THREADS") : "unset");
    std::printf("  trivial full-screen pass     %8.3f ms   1.00x\n", trivialMs);
    std::printf("  gbuffer                      %8.3f ms  %5.2fx\n", gbufferMs, gbufferMs / trivialMs);
    std::printf("  before: combine (8-slot loop) %7.3f ms  %5.2fx\n", median(tOldCombine), median(tOldCombine) / trivialMs);
    std::printf("  before: shade (8-slot loop)   %7.3f ms  %5.2fx\n", median(tOldShade), median(tOldShade) / trivialMs);
    std::printf("  after:  shade (merged, LIGHT_COUNT=%d) %6.3f ms  %5.2fx\n", lights, median(tNewShade),
                median(tNewShade) / trivialMs);
    std::printf("  fixed before (gbuffer + combine + shade) %8.3f ms  %5.2fx trivial\n", oldFixed, oldFixed / trivialMs);
    std::printf("  fixed after  (gbuffer + shade)           %8.3f ms  %5.2fx trivial\n", newFixed, newFixed / trivialMs);
    std::printf("  combine+shade before %.2fx -> after %.2fx trivial (%.1fx less)\n",
                (median(tOldCombine) + median(tOldShade)) / trivialMs, median(tNewShade) / trivialMs,
                (median(tOldCombine) + median(tOldShade)) / median(tNewShade));
    // The spread over the rounds: each round's own before / after ratio.
    std::vector<double> ratios;
    for (size_t i = 0; i < tNewShade.size(); ++i) ratios.push_back((tOldCombine[i] + tOldShade[i]) / tNewShade[i]);
    const bench::Spread spread = bench::spreadOf(ratios);
    std::printf("  per round: combine+shade before / after %.1fx median, %.1fx-%.1fx over %zu rounds\n", spread.median,
                spread.lowest, spread.highest, ratios.size());
    return 0;
}
