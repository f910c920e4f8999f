// Every soft technique on the real-mesh test set (assets/models/README.md: scanned and modelled
// meshes nobody here made, with holes, non-manifold edges, duplicated faces and inconsistent
// winding), against `raytraced` (256 rays a pixel) at 128x128 and the techniques' defaults:
//  - each soft technique's RMSE is below `hard`'s on every mesh (a soft shadow worth its cost);
//  - no technique draws shadow where the reference has none: pixels darker than the reference by
//    over 0.5 where the reference is lit (v >= 0.99), the signature of pvm's shards and ssv's
//    over-sized shadows, stay within the bound below.
// A mesh whose glTF scripts/fetch-meshes.sh has not made (SHADOWLAB_FETCH_MESHES=OFF) is skipped.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>

#include "graph/renderer.h"
#include "scene/scene.h"
#include "support/gl_fixture.h"
#include "support/real_meshes.h"
#include "support/volume_tests.h"

namespace shadowlab {
namespace {

using volume_tests::renderVisibility;
using volume_tests::rmse;

class RealMeshes : public testing::GLTest, public ::testing::WithParamInterface<std::string> {};
class RealMeshStats : public testing::GLTest {};
// PcssUnderATiltedLightDrawsNoGrid's bound: measured 3.07e-5 with the box centred on the receiver's
// position, 1.47e-4 with it centred on the receiver's texel (the grid); 3x the measured value.
constexpr double kPcssGridBound = 9e-5;

// Darker than the reference by over 0.5 where the reference is lit.
size_t shadowWhereLit(const Image& v, const Image& reference) {
    size_t n = 0;
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x)
            n += reference.at(x, y) >= 0.99f && v.at(x, y) < reference.at(x, y) - 0.5f;
    return n;
}

TEST_P(RealMeshes, SoftTechniquesBeatHardAndDrawNoShadowWhereTheReferenceIsLit) {
    const std::string scene = "mesh-" + GetParam();
    if (!testing::sceneCanLoad(scene)) GTEST_SKIP() << scene << ": the mesh was not fetched";
    const Scene s = loadScene(scene);
    const int size = 128;
    const Image reference = renderVisibility(s, "raytraced", size, {{"rays", "256"}});
    const double hard = rmse(renderVisibility(s, "hard", size), reference);
    std::printf("[ real mesh %-16s] hard RMSE %.4f\n", GetParam().c_str(), hard);
    // Measured on all seven meshes at 128x128 (the printout): at most 2 such pixels (pvmf on
    // elephant-holes, 128^2 = 16,384 pixels); 3x that is the bound.
    const size_t maxShadowWhereLit = 6;
    for (const char* technique : {"pcf", "pcss", "sssm", "ssm-gbp06", "ssm-contour", "ssv", "pvm", "pvmf"}) {
        SCOPED_TRACE(std::string(technique) + " on " + scene);
        const Image v = renderVisibility(s, technique, size);
        const double e = rmse(v, reference);
        const size_t wrong = shadowWhereLit(v, reference);
        std::printf("[ real mesh %-16s] %-12s RMSE %.4f (%.2f x hard), %zu pixels of shadow where the reference is lit\n",
                    GetParam().c_str(), technique, e, e / hard, wrong);
        EXPECT_LT(e, hard);
        EXPECT_LE(wrong, maxShadowWhereLit);
    }
}

// What ssv's topology repaired and closed is in `--stats` (counter `topology`): boeing's triangles
// wound against their neighbours turned round (1,432 of 2,564: the patch's majority by area wins),
// the Stanford dragon's duplicates left out, chinese-dragon's two tiny holes closed by fans.
TEST_F(RealMeshStats, SsvSaysWhatTheTopologyRepaired) {
    for (const auto& [name, key] : {std::pair<std::string, std::string>{"boeing", "turned_round"},
                                    {"stanford-dragon", "duplicates_left_out"},
                                    {"chinese-dragon", "openings_closed"}}) {
        SCOPED_TRACE(name);
        if (!testing::sceneCanLoad("mesh-" + name)) GTEST_SKIP() << name << ": the mesh was not fetched";
        RenderOptions options;
        options.width = options.height = 32;
        options.technique = "ssv";
        const Scene scene = loadScene("mesh-" + name);  // the renderer keeps a reference
        Renderer renderer(scene, options);
        renderer.renderFrame(0, {"visibility"});
        const nlohmann::json stats = renderer.stats({1.0}, 0);
        const nlohmann::json& objects = stats["lights"][0]["counters"]["topology"]["objects"];
        ASSERT_EQ(objects.size(), 1u) << stats["lights"][0]["counters"].dump();
        std::printf("[ real mesh %-16s] ssv topology: %s\n", name.c_str(), objects[0].dump().c_str());
        EXPECT_GT(objects[0][key].get<size_t>(), 0u);
    }
}

// PCSS under a tilted light (mesh-bunny's light faces (0.5, -0.85, 0.2)) at sm_size 512: the filter's
// box was centred on the receiver's texel, so every pixel within one texel read the same taps with
// the same weights, and where the tilt spreads the map's texels over many pixels of the floor the
// penumbra and the lit floor around it showed a grid of texel-sized squares (shaders/pcss/
// filter.frag now centres it on the receiver's own position). The grid's signature is energy at the
// pixel scale in the error v - v_ref: the mean square of the error minus its 3x3 mean, over the
// floor where the reference is not umbra (and not at the image border).
TEST_F(RealMeshStats, PcssUnderATiltedLightDrawsNoGrid) {
    if (!testing::sceneCanLoad("mesh-bunny")) GTEST_SKIP() << "the mesh was not fetched";
    const Scene s = loadScene("mesh-bunny");
    const int size = 192;
    const Image reference = renderVisibility(s, "raytraced", size, {{"rays", "256"}});
    RenderOptions options;
    options.width = options.height = size;
    options.technique = "pcss";
    options.sets = {{"sm_size", "512"}};
    Renderer renderer(s, options);
    renderer.renderFrame(0, {"visibility", "gbuffer"});
    const Image v = renderer.visibility(), ids = renderer.ids();
    auto error = [&](int x, int y) { return double(v.at(x, y)) - reference.at(x, y); };
    double energy = 0.0;
    size_t n = 0;
    for (int y = 1; y + 1 < size; ++y)
        for (int x = 1; x + 1 < size; ++x) {
            if (ids.at(x, y) != 0.0f || reference.at(x, y) < 0.02f) continue;  // the floor (id 0), not umbra
            double mean = 0.0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) mean += error(x + dx, y + dy) / 9.0;
            const double d = error(x, y) - mean;
            energy += d * d;
            ++n;
        }
    ASSERT_GT(n, 10000u);
    energy /= double(n);
    std::printf("[ pcss     ] mesh-bunny, sm_size 512: pixel-scale error energy %.3g over %zu floor pixels\n", energy, n);
    EXPECT_LT(energy, kPcssGridBound);
}

INSTANTIATE_TEST_SUITE_P(Set, RealMeshes,
                         ::testing::Values("bunny", "teapot", "snowden", "stanford-dragon", "elephant-holes", "boeing",
                                           "chinese-dragon"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = info.param;
                             for (char& c : name)
                                 if (c == '-') c = '_';
                             return name;
                         });

}  // namespace
}  // namespace shadowlab
