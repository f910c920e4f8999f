// `pvmf` (cournia2005 chapter 5): the shared mask, filter-width and jitter math and its hard cases
// (an edge through the light centre, radius 0, a receiver no farther than the edges), the GPU
// against the same source as C++, and renders: sphere-light against `raytraced`, the overlap
// artifact of pvm gone on overlapping-occluders, the per-pixel record against the image, the
// exported mask volumes ray-cast against the mask, and the masked fraction falling as the camera
// moves away.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gl/buffer.h"
#include "gl/util.h"
#include "graph/internals.h"
#include "graph/renderer.h"
#include "pvm/pvm.h"
#include "scene/light_view.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"
#include "support/mesh_scenes.h"
#include "support/volume_tests.h"

namespace shadowlab {
namespace {

using namespace shared;
using testing::Collected;
using testing::GLTest;

// ---- the shared math -------------------------------------------------------------------------------

// Sec. 5.1: both end points move towards the light centre along their rays by the same distance
// s_e d_e, d_e the nearer end's distance; s_e = 0 leaves them, a point at the light stays.
TEST(PvmfMath, MovedPointsMoveEquallyAlongTheirRays) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 500; ++i) {
        const glm::vec3 l(u(rng), 3.0f + u(rng), u(rng));
        const glm::vec3 e0(u(rng), u(rng), u(rng)), e1(u(rng), u(rng), u(rng));
        const float se = 0.5f * (1.0f + u(rng));
        const float de = pvmfEdgeDistance(e0, e1, l);
        EXPECT_FLOAT_EQ(de, std::min(glm::length(e0 - l), glm::length(e1 - l)));
        for (const glm::vec3& e : {e0, e1}) {
            const glm::vec3 m = pvmfMovedPoint(e, de, l, se);
            EXPECT_NEAR(glm::length(e - m), se * de, 1e-5f);
            EXPECT_NEAR(glm::length(glm::cross(glm::normalize(e - l), glm::normalize(m - l))), 0.0f, 1e-4f);
            EXPECT_LT(glm::length(m - l), glm::length(e - l));
            EXPECT_LT(glm::length(pvmfMovedPoint(e, de, l, 0.0f) - e), 1e-6f);  // s_e = 0: stays (l + (e - l) rounds)
        }
        // s_e = 1: the nearer end lands exactly on the light centre, the farther end stays on its ray.
        const glm::vec3 nearer = glm::length(e0 - l) <= glm::length(e1 - l) ? e0 : e1;
        EXPECT_EQ(pvmfMovedPoint(nearer, de, l, 1.0f), l);
    }
    EXPECT_EQ(pvmfMovedPoint(glm::vec3(1, 2, 3), 1.0f, glm::vec3(1, 2, 3), 0.5f), glm::vec3(1, 2, 3));
}

// The extrusion vectors (README.md: the printed vectors with e and n scaled by r, the ends leaning
// outwards): unit; their component along the hard shadow plane's normal is -side r / |v| exactly
// (the outer volume leans away from the occluder, the inner towards it, by the penumbra's half
// angle); along the edge -r at e^0 and +r at e^1; radius 0 gives the hard shadow plane's rays; an
// edge whose line passes through the light (n = 0) extrudes along the ray and the edge alone.
TEST(PvmfMath, ExtrusionOpensLikeThePenumbra) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 500; ++i) {
        const glm::vec3 l(u(rng), 3.0f + u(rng), u(rng));
        const glm::vec3 a(u(rng), u(rng), u(rng)), b = a + glm::vec3(u(rng), 0.2f * u(rng), u(rng));
        const float r = 0.05f + 0.5f * std::abs(u(rng));
        const glm::vec3 n = pvmPlaneNormal(a, b, l), e = glm::normalize(b - a);
        for (float side : {PVM_OUTER, PVM_INNER}) {
            for (float end : {PVMF_START, PVMF_END}) {
                const glm::vec3 p = end == PVMF_START ? a : b;
                const glm::vec3 v = pvmfExtrusion(p, a, b, n, l, r, end, side);
                const float len = glm::length(p - l + r * (end * e - side * n));
                EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f);
                EXPECT_NEAR(glm::dot(v, n), -side * r / len, 1e-5f);
                EXPECT_NEAR(glm::dot(v, e) - glm::dot(p - l, e) / len, end * r / len, 1e-4f);
                EXPECT_GT(glm::dot(v, p - l), 0.0f);  // away from the light
                const glm::vec3 hard = pvmfExtrusion(p, a, b, n, l, 0.0f, end, side);
                EXPECT_NEAR(glm::dot(hard, glm::normalize(p - l)), 1.0f, 1e-6f);
            }
        }
    }
    // The edge's line through the light centre: no hard shadow plane.
    const glm::vec3 l(0.0f), a(0.0f, -1.0f, 0.0f), b(0.0f, -2.0f, 0.0f);
    EXPECT_EQ(pvmPlaneNormal(a, b, l), glm::vec3(0.0f));
    const glm::vec3 v = pvmfExtrusion(a, a, b, pvmPlaneNormal(a, b, l), l, 0.3f, PVMF_START, PVM_OUTER);
    EXPECT_NEAR(glm::length(v), 1.0f, 1e-6f);
    EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
}

// Sec. 5.2's width against the penumbra it estimates: with s_p = 2 the filter spans exactly the
// penumbra an edge at d_o casts on a receiver at d_r from a disk of radius r (2 r (d_r - d_o) / d_o
// in world units over the map's width 2 d_r tan(alpha / 2) there); 0 for a point light, a receiver
// no farther than the edges, an unknown d_o; growing with d_r.
TEST(PvmfMath, FilterWidthIsTheProjectedPenumbra) {
    const float r = 0.4f, t = std::tan(0.5f);
    for (float dO = 0.5f; dO < 4.0f; dO += 0.5f)
        for (float dr = dO + 0.25f; dr < 8.0f; dr += 0.5f) {
            const float penumbra = 2.0f * r * (dr - dO) / dO, map = 2.0f * dr * t;
            EXPECT_NEAR(pvmfFilterWidth(2.0f, dr, dO, r, t), penumbra / map, 1e-5f);
            EXPECT_LT(pvmfFilterWidth(1.0f, dr, dO, r, t), pvmfFilterWidth(1.0f, dr + 0.5f, dO, r, t));
        }
    EXPECT_EQ(pvmfFilterWidth(1.77f, 3.0f, 1.0f, 0.0f, t), 0.0f);
    EXPECT_EQ(pvmfFilterWidth(1.77f, 1.0f, 1.0f, r, t), 0.0f);
    EXPECT_EQ(pvmfFilterWidth(1.77f, 0.5f, 1.0f, r, t), 0.0f);
    EXPECT_EQ(pvmfFilterWidth(1.77f, 3.0f, 0.0f, r, t), 0.0f);
    EXPECT_EQ(pvmfFilterWidth(1.77f, 3.0f, -1.0f, r, t), 0.0f);
}

// The n_pcf x n_pcf jitter: every cell of the grid holds exactly one sample, in [-1/2, 1/2); the
// same seed and pixel give the same samples, another seed or pixel others. The blur weight B: same
// object only, the background matches nothing.
TEST(PvmfMath, JitterStratifiesTheFilterAndBlurWeights) {
    for (uint32_t npcf : {1u, 3u, 7u}) {
        const uint32_t seed = pvmfPixelSeed(1u, 10u, 20u);
        std::vector<int> cells(npcf * npcf, 0);
        for (uint32_t i = 0; i < npcf * npcf; ++i) {
            const glm::vec2 o = pvmfSampleOffset(i, npcf, seed);
            ASSERT_GE(o.x, -0.5f);
            ASSERT_LT(o.x, 0.5f);
            ASSERT_GE(o.y, -0.5f);
            ASSERT_LT(o.y, 0.5f);
            const int cx = int((o.x + 0.5f) * float(npcf)), cy = int((o.y + 0.5f) * float(npcf));
            ++cells[size_t(cy) * npcf + size_t(cx)];
        }
        for (int c : cells) EXPECT_EQ(c, 1);
    }
    EXPECT_EQ(pvmfPixelSeed(1u, 3u, 4u), pvmfPixelSeed(1u, 3u, 4u));
    EXPECT_NE(pvmfPixelSeed(1u, 3u, 4u), pvmfPixelSeed(2u, 3u, 4u));
    EXPECT_NE(pvmfPixelSeed(1u, 3u, 4u), pvmfPixelSeed(1u, 4u, 3u));
    EXPECT_EQ(pvmfBlurWeight(2.0f, 2.0f, 0.5f), 1.0f);
    EXPECT_EQ(pvmfBlurWeight(2.0f, 3.0f, 1.0f), 0.0f);
    EXPECT_EQ(pvmfBlurWeight(-1.0f, -1.0f, 1.0f), 0.0f);
    EXPECT_EQ(pvmfBlurWeight(2.0f, 2.0f, 0.0f), 0.0f);  // a tap turned away from the light
    // n_blur counts taps on sec. 5.5's 512-pixel visibility buffer.
    EXPECT_EQ(pvmfBlurTaps(12, 512), 12);
    EXPECT_EQ(pvmfBlurTaps(12, 128), 3);
    EXPECT_EQ(pvmfBlurTaps(12, 1080), 25);
    EXPECT_EQ(pvmfBlurTaps(0, 2160), 0);
}

// The quads of pvmfQuad: independent of the edge's neighbours, starting at the moved end points,
// the outer one on the lit side of the hard shadow plane and the inner one on the occluder's.
TEST(PvmfMath, QuadsStraddleTheHardShadowPlane) {
    PvmEdge e;
    e.a = glm::vec3(1.0f, 1.0f, -1.0f);
    e.b = glm::vec3(1.0f, -1.0f, -1.0f);
    const glm::vec3 l(0.0f);
    const glm::vec3 n = pvmPlaneNormal(e.a, e.b, l);
    const auto outer = pvmfQuad(e, l, 0.3f, 0.1f, PVM_OUTER, 10.0f);
    const auto inner = pvmfQuad(e, l, 0.3f, 0.1f, PVM_INNER, 10.0f);
    const float de = std::sqrt(3.0f);
    EXPECT_NEAR(glm::length(outer[0] - e.a), 0.1f * de, 1e-5f);
    EXPECT_EQ(outer[0], inner[0]);
    EXPECT_EQ(outer[3], inner[3]);
    for (int k : {1, 2}) {
        EXPECT_GT(glm::dot(outer[k] - l, n), 0.0f);
        EXPECT_LT(glm::dot(inner[k] - l, n), 0.0f);
    }
}

struct GpuCase {
    glm::vec4 e0, e1, light, filt, ids;
    glm::uvec4 seeds, npcf;
};
struct GpuResult {
    glm::vec4 moved0, moved1, ext0, ext1, sample;
    glm::uvec4 seed;
};

class PvmfMathGpu : public GLTest {};

// Random edges, lights, filter inputs and ids, with the hard cases mixed in: an edge through the
// light centre, radius 0, s_e 0 and 1, d_r <= d_o, d_o 0, the background id. The GPU runs the same
// source as C++.
TEST_F(PvmfMathGpu, AgreesWithCpuOnAGrid) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<GpuCase> cases;
    for (uint32_t i = 0; i < 2048; ++i) {
        const glm::vec3 l(u(rng), 3.0f + u(rng), u(rng));
        glm::vec3 e0(u(rng), u(rng), u(rng));
        glm::vec3 e1 = e0 + glm::vec3(u(rng), 0.2f * u(rng), u(rng));
        float r = 0.05f + 0.5f * std::abs(u(rng)), se = 0.5f * (1.0f + u(rng));
        float dO = 1.0f + std::abs(u(rng)), dr = dO + 2.0f * u(rng);
        const int hard = int(i % 8);
        if (hard == 1) e1 = l + 0.5f * (e0 - l);  // the edge's line through the light centre
        if (hard == 2) r = 0.0f;
        if (hard == 3) se = (i & 8) ? 1.0f : 0.0f;
        if (hard == 4) dO = 0.0f;
        if (hard == 5) dr = dO;
        const float idC = (hard == 6) ? -1.0f : float(i % 3), idT = float((i / 3) % 3);
        const uint32_t npcf = 1u + i % 9u;
        cases.push_back({glm::vec4(e0, r), glm::vec4(e1, se), glm::vec4(l, (i & 1) ? PVM_OUTER : PVM_INNER),
                         glm::vec4(1.0f + std::abs(u(rng)), dr, dO, 0.2f + std::abs(u(rng))),
                         glm::vec4(idC, idT, (i % 5 == 0) ? 0.0f : 0.25f * float(i % 4), 0.0f), glm::uvec4(i * 7u, i % 61u, i / 61u, i % (npcf * npcf)),
                         glm::uvec4(npcf, i % 65u, 1u + (i * 37u) % 2160u, 0u)});
    }
    Buffer in(cases.size() * sizeof(GpuCase), cases.data());
    Buffer out(cases.size() * sizeof(GpuResult));
    const ShaderProgram& program = programCache().compute("tests/volumes/pvmf_math.comp");
    program.set("count", unsigned(cases.size()));
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.dispatch(GLuint((cases.size() + 63) / 64));
    memoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const std::vector<GpuResult> gpu = out.read<GpuResult>();
    ASSERT_EQ(gpu.size(), cases.size());
    for (size_t i = 0; i < cases.size(); ++i) {
        SCOPED_TRACE("case " + std::to_string(i));
        const GpuCase& c = cases[i];
        const float r = c.e0.w, se = c.e1.w, side = c.light.w;
        const glm::vec3 l(c.light);
        const float de = pvmfEdgeDistance(glm::vec3(c.e0), glm::vec3(c.e1), l);
        const glm::vec3 a = pvmfMovedPoint(glm::vec3(c.e0), de, l, se), b = pvmfMovedPoint(glm::vec3(c.e1), de, l, se);
        EXPECT_NEAR(gpu[i].moved0.w, de, 1e-5f);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(gpu[i].moved0[k], a[k], 1e-5f);
            EXPECT_NEAR(gpu[i].moved1[k], b[k], 1e-5f);
        }
        const float w = pvmfFilterWidth(c.filt.x, c.filt.y, c.filt.z, r, c.filt.w);
        EXPECT_NEAR(gpu[i].moved1.w, w, 1e-5f * std::max(1.0f, w));
        const glm::vec3 n = pvmPlaneNormal(glm::vec3(c.e0), glm::vec3(c.e1), l);
        const glm::vec3 v0 = pvmfExtrusion(a, a, b, n, l, r, PVMF_START, side);
        const glm::vec3 v1 = pvmfExtrusion(b, a, b, n, l, r, PVMF_END, side);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(gpu[i].ext0[k], v0[k], 2e-5f);
            EXPECT_NEAR(gpu[i].ext1[k], v1[k], 2e-5f);
        }
        EXPECT_EQ(gpu[i].ext0.w, pvmfBlurWeight(c.ids.x, c.ids.y, c.ids.z));
        const uint32_t seed = pvmfPixelSeed(c.seeds.x, c.seeds.y, c.seeds.z);
        EXPECT_EQ(gpu[i].seed.x, seed);
        EXPECT_EQ(int(gpu[i].seed.y), pvmfBlurTaps(int(c.npcf.y), int(c.npcf.z)));
        const glm::vec2 o = pvmfSampleOffset(c.seeds.w, c.npcf.x, seed);
        EXPECT_NEAR(gpu[i].sample.x, o.x, 1e-6f);
        EXPECT_NEAR(gpu[i].sample.y, o.y, 1e-6f);
    }
}

// ---- renders -----------------------------------------------------------------------------------------

using volume_tests::renderVisibility;
using volume_tests::rmse;

class PvmfRender : public GLTest {};

// sphere-light against `raytraced`: RMSE <= 0.06 (the bound; measured: see the printout).
TEST_F(PvmfRender, SphereLightAgainstRaytraced) {
    Scene scene = loadScene("sphere-light");
    const Image rt = renderVisibility(scene, "raytraced", 128);
    const double e = rmse(renderVisibility(scene, "pvmf", 128), rt);
    std::printf("[ pvmf     ] sphere-light vs raytraced: RMSE %.5f\n", e);
    EXPECT_LE(e, 0.06);
}

// A point light runs `hard` (the renderer's rule for soft passes): the same image.
TEST_F(PvmfRender, PointLightIsTheHardShadow) {
    Scene scene = loadScene("sphere-light");
    const Image pvmf = renderVisibility(scene, "pvmf", 96, {}, 0.0f);
    const Image hard = renderVisibility(scene, "hard", 96, {{"sm_size", "512"}}, 0.0f);
    EXPECT_EQ(rmse(pvmf, hard), 0.0);
}

// Chapter 5's claim: the mask's volumes only select pixels, the filter reads every occluder in the
// shadow map, so there is no overlap artifact: on overlapping-occluders pvmf's error in the overlap
// region (floor pixels both plates shadow, each alone, in `raytraced`) is lower than chapter 4's
// pvm's (one volume map for both sides: split_sides 0), and so is its error over the whole image.
TEST_F(PvmfRender, NoOverlapArtifact) {
    const Scene scene = loadScene("overlapping-occluders");
    const int size = 128;
    const Image rt = renderVisibility(scene, "raytraced", size);
    const Image pvm = renderVisibility(scene, "pvm", size, {{"split_sides", "0"}});
    const Image pvmf = renderVisibility(scene, "pvmf", size);
    auto alone = [&](const std::string& plate) {
        Scene s = scene;
        for (Object& o : s.objects)
            if (o.name != plate && o.name != "floor") o.castsShadows = false;
        return renderVisibility(s, "raytraced", size);
    };
    const Image low = alone("low plate"), high = alone("high plate");
    auto overlap = [&](int x, int y) { return low.at(x, y) < 0.95f && high.at(x, y) < 0.95f; };
    const double pvmOverlap = rmse(pvm, rt, overlap), pvmfOverlap = rmse(pvmf, rt, overlap);
    const double pvmAll = rmse(pvm, rt), pvmfAll = rmse(pvmf, rt);
    std::printf("[ pvmf     ] overlapping-occluders: RMSE in the overlap pvm %.4f pvmf %.4f; whole image pvm %.4f "
                "pvmf %.4f\n", pvmOverlap, pvmfOverlap, pvmAll, pvmfAll);
    EXPECT_LT(pvmfOverlap, 0.5 * pvmOverlap);
    EXPECT_LT(pvmfAll, pvmAll);
}

// Keeps the records as well.
struct Records : Collected {
    std::map<std::string, nlohmann::json> records;
    void json(const std::string& name, const nlohmann::json& value, const std::string&, const std::string&) override {
        records[name] = value;
    }
};

// The per-pixel record recomputes the filter on the CPU from the mask and shadow-map texels the
// shader read (the shared math, the same jitter): its visibility is the filter's output
// (visibility_before_blur) within 1e-4 on listed pixels and unlisted ones, and its samples are
// n_pcf^2 within w_pcf of the receiver's projection.
TEST_F(PvmfRender, PixelRecordsAgreeWithTheFilter) {
    Scene scene = loadScene("sphere-light");
    RenderOptions options;
    options.width = options.height = 96;
    options.technique = "pvmf";
    Renderer renderer(scene, options);
    renderer.renderFrame(0, renderer.internalRequests(true));
    int listed = 0, filtered = 0, unlisted = 0;
    for (int y = 4; y < 96; y += 7)
        for (int x = 3; x < 96; x += 7) {
            Records r;
            renderer.writeInternals(r, glm::ivec2(x, y));
            ASSERT_TRUE(r.records.count("pixel"));
            if (!r.records["pixel"].contains("lights")) continue;
            const nlohmann::json& j = r.records["pixel"]["lights"][0];
            if (j.contains("background")) continue;
            EXPECT_NEAR(j["visibility_from_record"].get<float>(), j["visibility_before_blur"].get<float>(), 1e-4f)
                << x << "," << y << " " << j.dump();
            if (!j["listed"].get<bool>()) {
                ++unlisted;
                EXPECT_NEAR(j["visibility"].get<float>(), j["visibility_before_blur"].get<float>(), 1e-6f);
                continue;
            }
            ++listed;
            if (j["samples"].is_null()) continue;
            ++filtered;
            const float w = j["w_pcf_texels"].get<float>();
            EXPECT_EQ(j["samples"].size(), 49u);
            for (const auto& s : j["samples"]) {
                EXPECT_LE(std::abs(s["offset"][0].get<float>()), 0.5f * w + 1e-4f);
                EXPECT_LE(std::abs(s["offset"][1].get<float>()), 0.5f * w + 1e-4f);
            }
        }
    std::printf("[ pvmf     ] records: %d listed (%d filtered), %d not listed\n", listed, filtered, unlisted);
    EXPECT_GT(filtered, 5);
    EXPECT_GT(unlisted, 50);
}

using volume_tests::hit;

// The volumes exported (`--internals`: penumbra_volumes, the quads the GPU drew) ray-cast on the CPU
// from the light through every mask texel centre give the mask: the nearest volume's depth within
// 1e-3 relative and its d_e (the mesh's edge_distance attribute) within 1e-5, on all but 2% of the
// texels (borders of quads almost edge-on to the light), and the same "no volume" texels.
TEST_F(PvmfRender, ExportedVolumesRayCastGiveTheMask) {
    for (const char* name : {"square-occluder", "sphere-light"}) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(name);
        RenderOptions options;
        options.width = options.height = 64;
        options.technique = "pvmf";
        options.sets = {{"sm_size", "96"}};
        Renderer renderer(scene, options);
        renderer.renderFrame(0, renderer.internalRequests(false));
        Collected c;
        renderer.writeInternals(c, std::nullopt);
        ASSERT_TRUE(c.meshes.count("penumbra_volumes") && c.images.count("pvmf_mask"));
        const MeshData& mesh = c.meshes["penumbra_volumes"];
        const Image& mask = c.images["pvmf_mask"];
        ASSERT_EQ(mask.width, 96);
        ASSERT_EQ(mask.channels, 2);
        ASSERT_EQ(mesh.primitiveAttributes[3].first, "edge_distance");
        const std::vector<float>& de = mesh.primitiveAttributes[3].second;
        const Light& light = scene.lights[0];
        const LightView view = fitLightView(light, light.position, scene.bounds(0.0));
        const glm::mat4 worldFromClip = glm::inverse(view.clipFromView * view.viewFromWorld);
        size_t differ = 0, covered = 0;
        for (int y = 0; y < mask.height; ++y)
            for (int x = 0; x < mask.width; ++x) {
                const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / float(mask.width) * 2.0f - 1.0f;
                const glm::vec4 far = worldFromClip * glm::vec4(ndc, 0.5f, 1.0f);
                const glm::vec3 d = glm::normalize(glm::vec3(far) / far.w - light.position);
                float t = INFINITY, nearestDe = 0.0f;
                for (size_t i = 0; i < mesh.primitiveCount(); ++i) {
                    const float ti = hit(light.position, d, mesh.positions[mesh.indices[3 * i]],
                                         mesh.positions[mesh.indices[3 * i + 1]], mesh.positions[mesh.indices[3 * i + 2]]);
                    if (ti < t) t = ti, nearestDe = de[i];
                }
                float z = INFINITY;
                if (std::isfinite(t)) {
                    const glm::vec4 v = view.viewFromWorld * glm::vec4(light.position + t * d, 1.0f);
                    z = -v.z;
                    if (z > view.farZ) z = INFINITY, nearestDe = 0.0f;
                }
                const int row = mask.height - 1 - y;
                const float gpu = mask.data[(size_t(row) * mask.width + x) * 2];
                const float gpuDe = mask.data[(size_t(row) * mask.width + x) * 2 + 1];
                covered += std::isfinite(gpu);
                const bool same = (std::isinf(z) && std::isinf(gpu) && gpuDe == 0.0f) ||
                                  (std::isfinite(z) && std::isfinite(gpu) && std::abs(z - gpu) <= 1e-3f * z &&
                                   std::abs(gpuDe - nearestDe) <= 1e-5f * std::max(1.0f, nearestDe));
                differ += !same;
            }
        std::printf("[ pvmf     ] %s: %zu of %d mask texels covered, %zu differ from the exported mesh ray-cast\n",
                    name, covered, mask.width * mask.height, differ);
        EXPECT_GT(covered, 50u);
        EXPECT_LE(differ, size_t(0.02 * mask.width * mask.height));
    }
}

// Sec. 5.5: the mask restricts the work. As the camera moves away from sphere-light's occluder, the
// pixels filtered (the counter's listed_pixels) fall; they are never more than the geometry pixels,
// and the unlisted pixels' visibility is exactly their front fraction (lit).
TEST_F(PvmfRender, ListedPixelsFallAsTheCameraMovesAway) {
    Scene scene = loadScene("sphere-light");
    const glm::vec3 target = scene.camera.target, from = scene.camera.position;
    std::vector<double> listed;
    for (float k : {0.5f, 1.0f, 2.0f, 4.0f}) {
        Scene s = scene;
        s.camera.position = target + k * (from - target);
        s.camera.farPlane = std::max(s.camera.farPlane, 10.0f * k * glm::length(from - target));
        RenderOptions options;
        options.width = options.height = 128;
        options.technique = "pvmf";
        Renderer renderer(s, options);
        renderer.renderFrame(0, {"visibility"});
        const nlohmann::json c = renderer.stats({}, 0)["lights"][0]["counters"]["mask"];
        std::printf("[ pvmf     ] camera at %.1fx: %s\n", k, c.dump().c_str());
        EXPECT_LE(c["listed_pixels"].get<double>(), c["geometry_pixels"].get<double>());
        EXPECT_EQ(c["listed_pixels"].get<double>(),
                  c["in_volume_pixels"].get<double>() + c["shadow_test_only_pixels"].get<double>());
        listed.push_back(c["listed_pixels"].get<double>());
    }
    for (size_t i = 1; i < listed.size(); ++i) EXPECT_LT(listed[i], listed[i - 1]);
    EXPECT_GT(listed.front(), 4.0 * listed.back());
}

// The seed: the same seed renders the same image, another seed moves the jitter (sec. 5.2's noise),
// and the blur hides most of it (sec. 5.3): the blurred images differ less than the raw ones.
TEST_F(PvmfRender, SeedAndBlur) {
    Scene scene = loadScene("sphere-light");
    const Image a = renderVisibility(scene, "pvmf", 96, {{"seed", "1"}});
    const Image b = renderVisibility(scene, "pvmf", 96, {{"seed", "1"}});
    const Image c = renderVisibility(scene, "pvmf", 96, {{"seed", "2"}});
    EXPECT_EQ(rmse(a, b), 0.0);
    const Image rawA = renderVisibility(scene, "pvmf", 96, {{"seed", "1"}, {"n_blur", "0"}});
    const Image rawC = renderVisibility(scene, "pvmf", 96, {{"seed", "2"}, {"n_blur", "0"}});
    const double blurred = rmse(a, c), raw = rmse(rawA, rawC);
    std::printf("[ pvmf     ] seed 1 against seed 2: RMSE %.5f blurred, %.5f without the blur\n", blurred, raw);
    EXPECT_GT(raw, 0.0);
    EXPECT_LT(blurred, 0.5 * raw);
}

// Open and non-manifold meshes (techniques/pvm/README.md, "Silhouettes": pvmf uses the same loops):
// an open square of two triangles has its four boundary edges as silhouettes and gives the open
// square's shadow within RMSE 0.06 of `raytraced`; the same square with two fins on one edge (four
// faces there) is named on stderr and renders finite values in [0, 1].
TEST_F(PvmfRender, OpenAndNonManifoldMeshes) {
    const std::vector<glm::vec3> square = {{-0.5f, 2, -0.5f}, {0.5f, 2, -0.5f}, {0.5f, 2, 0.5f}, {-0.5f, 2, 0.5f}};
    const std::vector<uint32_t> two = {0, 2, 1, 0, 3, 2};
    const Scene open = loadScene(testing::writeGltf("pvmf-open-square", square, two));
    const double e = rmse(renderVisibility(open, "pvmf", 96), renderVisibility(open, "raytraced", 96));
    std::printf("[ pvmf     ] open square vs raytraced: RMSE %.5f\n", e);
    EXPECT_LE(e, 0.06);
    std::vector<glm::vec3> finned = square;
    finned.push_back({0.0f, 1.6f, -0.5f});
    finned.push_back({0.0f, 2.4f, -0.5f});
    std::vector<uint32_t> fins = two;
    fins.insert(fins.end(), {0, 1, 4, 1, 0, 5});
    const Scene nm = loadScene(testing::writeGltf("pvmf-finned-square", finned, fins));
    ::testing::internal::CaptureStderr();
    const Image v = renderVisibility(nm, "pvmf", 96);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("pvmf: object 'pvmf-finned-square' is not a manifold"), std::string::npos) << err;
    for (float x : v.data) ASSERT_TRUE(std::isfinite(x) && x >= 0.0f && x <= 1.0f);
}

}  // namespace
}  // namespace shadowlab
