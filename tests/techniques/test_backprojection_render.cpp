// End-to-end renders of ssm-gbp06 and ssm-contour (guennebaud2007 sections 3-4) against the oracles:
// the square-occluder closed form, `reference` on the plant (the paper's Fig. 1 and 11 claims), the
// per-pixel records against the image, the parameter t, disk lights and the point-light limit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "graph/renderer.h"
#include "image/metrics.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

namespace fs = std::filesystem;
using testing::GLTest;

struct Render {
    Image visibility, positions, ids;
};

Render render(const Scene& scene, const std::string& technique, std::vector<std::pair<std::string, std::string>> sets,
              int size, std::optional<float> lightSize = {}) {
    RenderOptions options;
    options.width = options.height = size;
    options.technique = technique;
    options.sets = std::move(sets);
    options.lightSize = lightSize;
    Renderer renderer(scene, options);
    renderer.renderFrame(0, {"visibility", "gbuffer"});
    return {renderer.visibility(), renderer.positions(), renderer.ids()};
}

// Closed form of DESIGN.md section 5 on floor pixels (id 0), NaN elsewhere.
Image closedForm(const Render& r) {
    Image out(r.visibility.width, r.visibility.height, 1, NAN);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            if (r.ids.at(x, y) != 0.0f) continue;
            glm::vec3 p(r.positions.at(x, y, 0), 0.0f, r.positions.at(x, y, 2));
            out.at(x, y) = shared::squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f);
        }
    return out;
}

struct ErrorStats {
    double rmse = 0.0, mean = 0.0;
    size_t n = 0;
};
// Error of `v` against `oracle` over pixels where the oracle is a number (and, with penumbraOnly,
// strictly between 0 and 1).
ErrorStats errorStats(const Image& v, const Image& oracle, bool penumbraOnly = false) {
    ErrorStats s;
    double sq = 0.0, sum = 0.0;
    for (size_t i = 0; i < oracle.data.size(); ++i) {
        float o = oracle.data[i];
        if (std::isnan(o)) continue;
        if (penumbraOnly && (o <= 0.0f || o >= 1.0f)) continue;
        double d = double(v.data[i]) - o;
        sq += d * d;
        sum += d;
        ++s.n;
    }
    s.rmse = s.n ? std::sqrt(sq / double(s.n)) : INFINITY;
    s.mean = s.n ? sum / double(s.n) : 0.0;
    return s;
}

class BackprojectionRender : public GLTest {};

// ssm-contour against the closed form, over the penumbra (closed form strictly between 0 and 1,
// where back-projection acts): measured RMSE 0.0045 for both at 256 x 256 (0.0019 over the whole
// floor), the texel quantisation of the plate's border in the map; bound 0.012, 2.7x. The plate is
// parallel to the light, so GBP06's quads tile it without gaps or overlaps and ssm-gbp06 is just
// as close. An HSM read or built one level off fails here (scripts/mutation-check.sh).
// With the light-space multi-resolution at its defaults (t_k = 16, sec. 5.1) the plate's penumbra is
// walked on HSM levels 1-2: ssm-contour blends levels and shrinks their contours (t = 1, Fig. 7c),
// measured penumbra RMSE 0.0093 (bound 0.012 as above); ssm-gbp06 walks eq. 2's level without
// blending and with the min-fattened quads (as GBP06 did), measured 0.021, bound 0.03 (1.4x).
TEST_F(BackprojectionRender, SquareOccluderMatchesClosedForm) {
    Scene scene = loadScene("square-occluder");
    for (const char* multires : {"false", "true"})
    for (const char* technique : {"ssm-contour", "ssm-gbp06"}) {
        SCOPED_TRACE(std::string(technique) + " light_multires=" + multires);
        Render r = render(scene, technique, {{"light_multires", multires}}, 256);
        ErrorStats e = errorStats(r.visibility, closedForm(r));
        ErrorStats pen = errorStats(r.visibility, closedForm(r), true);
        EXPECT_GT(e.n, size_t(30000));
        EXPECT_GT(pen.n, size_t(3000));
        bool coarseGbp06 = std::string(multires) == "true" && std::string(technique) == "ssm-gbp06";
        EXPECT_LE(pen.rmse, coarseGbp06 ? 0.03 : 0.012) << technique;
        std::string key = std::string(technique) + (std::string(multires) == "true" ? "_multires" : "");
        RecordProperty(key + "_rmse", std::to_string(e.rmse));
        RecordProperty(key + "_penumbra_rmse", std::to_string(pen.rmse));
        std::printf("[ square   ] %s vs closed form: RMSE %.5f mean error %.5f over %zu floor pixels; penumbra RMSE %.5f "
                    "over %zu\n",
                    technique, e.rmse, e.mean, e.n, pen.rmse, pen.n);
    }
}

// The paper's Fig. 1 and 11 on the plant at 384x384 against `reference` with 256 samples:
// ssm-contour has the lower RMSE, and ssm-gbp06 overestimates the shadow: its mean error over the
// penumbra is negative, and below ssm-contour's (measured: RMSE 0.017 vs 0.027; penumbra mean error
// -0.01 vs +0.005). (pcss, once it exists, joins the RMSE comparison.)
TEST_F(BackprojectionRender, PlantContourBeatsGbp06AndGbp06Overestimates) {
    Scene scene = loadScene("plant");
    Render ref = render(scene, "reference", {{"samples", "256"}}, 384);
    Render contour = render(scene, "ssm-contour", {}, 384);
    Render gbp06 = render(scene, "ssm-gbp06", {}, 384);
    ErrorStats ec = errorStats(contour.visibility, ref.visibility), eg = errorStats(gbp06.visibility, ref.visibility);
    ErrorStats pc = errorStats(contour.visibility, ref.visibility, true),
               pg = errorStats(gbp06.visibility, ref.visibility, true);
    std::printf("[ plant    ] RMSE contour %.5f gbp06 %.5f; penumbra mean error contour %+.5f gbp06 %+.5f (%zu pixels)\n",
                ec.rmse, eg.rmse, pc.mean, pg.mean, pc.n);
    RecordProperty("contour_rmse", std::to_string(ec.rmse));
    RecordProperty("gbp06_rmse", std::to_string(eg.rmse));
    EXPECT_LT(ec.rmse, eg.rmse);
    EXPECT_GT(pc.n, size_t(5000));
    EXPECT_LT(pg.mean, 0.0) << "ssm-gbp06 should overestimate the shadow";
    EXPECT_LT(pg.mean, pc.mean - 0.005);
}

// A disk (sphere) light: both techniques integrate over the unit disk; against `reference` the
// contour method stays within 0.03 RMSE (measured ~0.018 at 192x192).
TEST_F(BackprojectionRender, SphereLightAgainstReference) {
    Scene scene = loadScene("sphere-light");
    Render ref = render(scene, "reference", {{"samples", "256"}}, 160);
    Render contour = render(scene, "ssm-contour", {}, 160);
    ErrorStats e = errorStats(contour.visibility, ref.visibility);
    std::printf("[ sphere   ] contour vs reference RMSE %.5f\n", e.rmse);
    EXPECT_LE(e.rmse, 0.03);
}

// t shrinks (t = 1) or grows (t = -1) the contour (sec. 4.1): the mean visibility over the square
// occluder's floor rises with t, and t = 0 is the closest to the closed form.
TEST_F(BackprojectionRender, ContourParameterTShrinksAndGrows) {
    Scene scene = loadScene("square-occluder");
    double previous = -1.0;
    double rmse[3];
    int k = 0;
    for (const char* t : {"-1", "0", "1"}) {
        Render r = render(scene, "ssm-contour", {{"t", t}, {"sm_size", "128"}}, 96);
        Image oracle = closedForm(r);
        double mean = 0.0;
        size_t n = 0;
        for (size_t i = 0; i < oracle.data.size(); ++i)
            if (!std::isnan(oracle.data[i])) mean += r.visibility.data[i], ++n;
        mean /= double(n);
        EXPECT_GT(mean, previous) << "t = " << t;
        previous = mean;
        rmse[k++] = errorStats(r.visibility, oracle).rmse;
    }
    EXPECT_LT(rmse[1], rmse[0]);
    EXPECT_LT(rmse[1], rmse[2]);
}

// A point light runs no soft pass: both techniques give `hard` exactly.
TEST_F(BackprojectionRender, PointLightGivesHardShadows) {
    Scene scene = loadScene("square-occluder");
    Render hard = render(scene, "hard", {}, 64, 0.0f);
    for (const char* technique : {"ssm-contour", "ssm-gbp06"}) {
        Render r = render(scene, technique, {}, 64, 0.0f);
        EXPECT_EQ(r.visibility.data, hard.visibility.data) << technique;
    }
}

// ---- per-pixel records ------------------------------------------------------------------------------

nlohmann::json pixelRecord(Renderer& renderer, glm::ivec2 pixel, const std::string& dir) {
    fs::create_directories(dir);
    OutputSet outputs;
    InternalWriter writer(dir, outputs);
    renderer.writeInternals(writer, pixel);
    outputs.commit();
    std::ifstream in(dir + "/pixel.json");
    return nlohmann::json::parse(in);
}

// The record recomputes the pixel on the CPU with the shared functions: its list's areas plus the
// initial area are the occluded area, and 1 - that / light area (clamped) is the image's visibility
// within 1e-4, on penumbra, lit and umbra pixels of four scenes (square and disk lights, occluder
// fusion, many depths).
// Every record against the image, with the light-space multi-resolution off (the map itself) and
// with t_k = 4 (coarse HSM levels and, for ssm-contour, blended pairs of levels, sec. 5.1): the
// CPU mirror walks the level the shader walked, and the blend reproduces the image.
TEST_F(BackprojectionRender, PixelRecordsAddUpToTheImage) {
    std::string root = std::string(SHADOWLAB_TEST_TMP) + "/backprojection-records";
    int penumbraRecords = 0, withItems = 0, coarse = 0, blended = 0, skipped = 0;
    for (const char* multires : {"false", "true"})
    for (const char* sceneName : {"square-occluder", "sphere-light", "plant", "overlapping-occluders"}) {
        Scene scene = loadScene(sceneName);
        for (const char* technique : {"ssm-contour", "ssm-gbp06"}) {
            SCOPED_TRACE(std::string(sceneName) + " " + technique + " light_multires=" + multires);
            RenderOptions options;
            options.width = options.height = 96;
            options.technique = technique;
            options.sets = {{"sm_size", "256"}, {"light_multires", multires}};
            if (std::string(multires) == "true") options.sets.push_back({"t_k", "4"});
            Renderer renderer(scene, options);
            renderer.renderFrame(0, renderer.internalRequests(true));
            Image v = renderer.visibility();
            // Pixels: up to five penumbra pixels spread over the image, plus the first lit and umbra ones.
            std::vector<glm::ivec2> pixels, penumbra;
            bool lit = false, umbra = false;
            for (int y = 0; y < v.height; ++y)
                for (int x = 0; x < v.width; ++x) {
                    float value = v.at(x, y);
                    if (value > 0.02f && value < 0.98f) penumbra.push_back({x, y});
                    if (value == 1.0f && !lit && renderer.ids().at(x, y) >= 0.0f) lit = true, pixels.push_back({x, y});
                    if (value == 0.0f && !umbra) umbra = true, pixels.push_back({x, y});
                }
            ASSERT_GE(penumbra.size(), size_t(5));
            for (int k = 0; k < 5; ++k) pixels.push_back(penumbra[penumbra.size() * size_t(2 * k + 1) / 10]);
            for (glm::ivec2 p : pixels) {
                SCOPED_TRACE("pixel " + std::to_string(p.x) + "," + std::to_string(p.y));
                nlohmann::json all = pixelRecord(renderer, p, root + "/" + sceneName + "-" + technique);
                const nlohmann::json& rec = all["lights"][0];
                ASSERT_EQ(rec["technique"], technique);
                ASSERT_FALSE(rec.contains("background"));
                EXPECT_EQ(rec["light"], 0);  // the light's index, not shadowed by the record's own fields
                double area = rec["light_geometry"]["area"].get<double>();
                double items = 0.0;
                const char* list = std::string(technique) == "ssm-contour" ? "edges" : "samples";
                const char* field = std::string(technique) == "ssm-contour" ? "signed_area" : "area";
                if (rec.contains(list)) {
                    for (const auto& item : rec[list]) items += item[field].get<double>();
                    if (!rec[list].empty()) ++withItems;
                }
                double occluded = rec["initial_area"].get<double>() + items;
                EXPECT_NEAR(occluded, rec["occluded_area"].get<double>(), 1e-4 * std::max(1.0, area));
                // Times the light's fraction in front of the receiver's tangent plane (the visibility
                // convention, shaders/shared/tangent_plane.glsl), as the shader multiplies it.
                double front = rec["front_fraction"].get<double>();
                EXPECT_GE(front, 0.0);
                EXPECT_LE(front, 1.0);
                double visibility = std::clamp(1.0 - occluded / area, 0.0, 1.0);
                if (rec.contains("light_levels") && !rec["light_levels"].is_null()) {
                    const nlohmann::json& levels = rec["light_levels"];
                    if (levels["level"].get<int>() > 0) ++coarse;
                    double weight = levels["blend_weight"].get<double>();
                    if (weight > 0.0) {
                        ++blended;
                        double other = std::clamp(1.0 - rec["blend_occluded_area"].get<double>() / area, 0.0, 1.0);
                        visibility += (other - visibility) * weight;
                    }
                }
                visibility *= front;
                EXPECT_NEAR(visibility, rec["visibility_recomputed"].get<double>(), 1e-5);
                // A pixel the screen-space selection skipped holds pull-push's value (sec. 5.2).
                ASSERT_TRUE(rec.contains("selection"));
                if (rec["selection"] == "skipped") {
                    ++skipped;
                } else {
                    EXPECT_NEAR(visibility, rec["visibility"].get<double>(), 1e-4) << rec.dump().substr(0, 2000);
                }
                EXPECT_FLOAT_EQ(rec["visibility"].get<float>(), v.at(p.x, p.y));
                if (rec["classification"] == "penumbra") ++penumbraRecords;
            }
        }
    }
    EXPECT_GE(penumbraRecords, 60);
    EXPECT_GE(withItems, 60);
    EXPECT_GE(coarse, 10);  // the multi-resolution branch is exercised, not only level 0
    EXPECT_GE(blended, 1);
    std::printf("%d penumbra records, %d on pixels the screen-space selection skipped\n", penumbraRecords, skipped);
}

}  // namespace
}  // namespace shadowlab
