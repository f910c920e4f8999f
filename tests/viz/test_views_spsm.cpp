// The `spsm-texels` view (viz/view_spsm_texels.cpp) on square-occluder: for a pixel the CPU record
// says was decided by the reconstructed edge (found by scanning the `branches` image and asking the
// record), the picture is drawn (p, the tangent and the edge in their colours), the triangles it
// draws (its export's polygons) are exactly the distinct triangles of the record's `tested` list,
// the caption counts them, and the legend's counts are the branches image's, counted here; a larger
// neighbourhood widens the grid; techniques without the record and a request without a pixel are
// refused.
#include <gtest/gtest.h>

#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <set>

#include "error.h"
#include "graph/renderer.h"
#include "image/image.h"
#include "scene/scene.h"
#include "support/gl_fixture.h"
#include "view_common.h"
#include "views.h"

namespace fs = std::filesystem;

namespace shadowlab {
namespace {

class SpsmTexelsView : public testing::GLTest {
protected:
    static RenderOptions options(std::vector<std::pair<std::string, std::string>> sets = {}) {
        RenderOptions o;
        o.width = 192;
        o.height = 160;
        o.technique = "spsm";
        o.sets = std::move(sets);
        return o;
    }
    // The `branches` internal and, with a pixel, its light-0 record, as the technique writes them.
    static Image branches(Renderer& renderer) {
        std::set<std::string> requested = renderer.internalRequests(false);
        requested.insert("visibility");
        renderer.renderFrame(0, requested);
        InternalCollector sink;
        renderer.writeInternals(sink, std::nullopt);
        auto it = sink.entries.find("branches");
        EXPECT_TRUE(it != sink.entries.end());
        return it == sink.entries.end() ? Image() : it->second.levels.at(0);
    }
    static nlohmann::json record(Renderer& renderer, glm::ivec2 pixel) {
        std::set<std::string> requested = renderer.internalRequests(true);
        requested.insert("visibility");
        renderer.renderFrame(0, requested);
        InternalCollector sink;
        renderer.writeInternals(sink, pixel);
        for (const auto& l : sink.entries.at("pixel").json.at("lights"))
            if (l.value("light", -1) == 0) return l;
        return nlohmann::json();
    }
    // The first pixel (scan order) whose branch image value is `value` and whose CPU record agrees.
    static std::optional<glm::ivec2> pixelDecidedBy(Renderer& renderer, const Image& b, int value, const std::string& name) {
        int asked = 0;
        for (int y = 0; y < b.height; ++y)
            for (int x = 0; x < b.width; ++x) {
                if (std::lround(b.at(x, y)) != value) continue;
                const nlohmann::json r = record(renderer, {x, y});
                if (r.value("branch", "") == name) return glm::ivec2(x, y);
                if (++asked > 40) return std::nullopt;
            }
        return std::nullopt;
    }
    static ViewRequest request(glm::ivec2 pixel, int w, int h) {
        ViewRequest q;
        q.view = "spsm-texels";
        q.pixel = pixel;
        q.width = w;
        q.height = h;
        return q;
    }
    static std::string outPath(const std::string& name) {
        const fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / "views-spsm";
        fs::create_directories(dir);
        return (dir / name).string();
    }
};

size_t pixelsNear(const Image& img, glm::vec3 rgb, float tol = 0.04f) {
    size_t n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (std::abs(img.at(x, y, 0) - rgb.r) < tol && std::abs(img.at(x, y, 1) - rgb.g) < tol &&
                std::abs(img.at(x, y, 2) - rgb.b) < tol)
                ++n;
    return n;
}

using Triangle = std::array<float, 6>;

// The record's tested triangles, each distinct one once (a triangle stored in several texels).
std::set<Triangle> recordTriangles(const nlohmann::json& rec) {
    std::set<Triangle> out;
    for (const auto& t : rec.at("tested")) {
        Triangle v;
        for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 2; ++c) v[size_t(2 * i + c)] = t.at("vertices")[size_t(i)][size_t(c)].get<float>();
        out.insert(v);
    }
    return out;
}

struct Exported {
    std::set<Triangle> triangles;
    int texels = 0;                 // the triangles' `texels`, summed
    std::array<int, 5> parts{};     // cells per part
};
Exported loadExport(const std::string& path) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkPolyData* d = reader->GetOutput();
    Exported e;
    vtkDataArray* part = d->GetCellData()->GetArray("part");
    vtkDataArray* texels = d->GetCellData()->GetArray("texels");
    EXPECT_TRUE(part && texels);
    if (!part || !texels) return e;
    for (vtkIdType c = 0; c < d->GetNumberOfCells(); ++c) {
        const int p = int(part->GetTuple1(c));
        if (p >= 0 && p < 5) ++e.parts[size_t(p)];
        if (p != 0) continue;
        vtkCell* cell = d->GetCell(c);
        EXPECT_EQ(cell->GetNumberOfPoints(), 3);
        Triangle v;
        for (int i = 0; i < 3; ++i) {
            double x[3];
            cell->GetPoints()->GetPoint(i, x);
            v[size_t(2 * i)] = float(x[0]);
            v[size_t(2 * i + 1)] = float(x[1]);
        }
        e.triangles.insert(v);
        e.texels += int(texels->GetTuple1(c));
    }
    return e;
}

TEST_F(SpsmTexelsView, AnEdgePixelDrawsTheRecordsTrianglesTangentAndEdgeAndCountsEveryBranch) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options());
    const Image b = branches(renderer);
    ASSERT_EQ(b.width, 192);
    const std::optional<glm::ivec2> pixel = pixelDecidedBy(renderer, b, 5, "reconstructed_edge");
    ASSERT_TRUE(pixel) << "no pixel of square-occluder's plate edge decided by the reconstructed edge";
    const nlohmann::json rec = record(renderer, *pixel);
    ASSERT_TRUE(rec["edge"].is_object()) << rec.dump();
    const std::set<Triangle> expected = recordTriangles(rec);
    ASSERT_GE(expected.size(), 2u) << "an edge pixel's neighbourhood stores several triangles";

    std::array<size_t, 9> counts{};
    for (size_t i = 0; i < b.pixelCount(); ++i) ++counts[size_t(std::lround(b.data[i]))];

    for (glm::ivec2 size : {glm::ivec2(1024, 400), glm::ivec2(640, 480)}) {
        SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y));
        ViewRequest q = request(*pixel, size.x, size.y);
        q.exportPath = outPath("edge-" + std::to_string(size.x) + ".vtp");
        ASSERT_EQ(viewRefusal(renderer, q), "");
        ViewResult r = renderView(renderer, scene, q);
        writePNG(outPath("edge-" + std::to_string(size.x) + ".png"), r.image);
        // Drawn: p (magenta), the tangent (cyan), the edge (yellow), and the legend's branch colours.
        EXPECT_GT(pixelsNear(r.image, {1.0f, 0.2f, 0.9f}), 10u) << "p";
        EXPECT_GT(pixelsNear(r.image, {0.2f, 0.9f, 1.0f}), 20u) << "tangent";
        EXPECT_GT(pixelsNear(r.image, {1.0f, 0.85f, 0.1f}, 0.01f), 20u) << "edge (the branch colour has green 0.82)";
        // The triangles drawn are the record's tested ones, each once, and store every tested texel.
        const Exported e = loadExport(q.exportPath);
        EXPECT_EQ(e.triangles, expected);
        EXPECT_EQ(size_t(e.texels), rec["tested"].size());
        EXPECT_EQ(e.parts[2], 1) << "p";
        EXPECT_EQ(e.parts[3], 1) << "tangent";
        EXPECT_EQ(e.parts[4], 1) << "edge";
        EXPECT_EQ(e.parts[1], 2 * (3 + 1)) << "a 3x3 grid: four lines each way";
        EXPECT_EQ(r.data["triangles_drawn"].get<size_t>(), expected.size());
        EXPECT_NE(r.caption.find(std::to_string(rec["tested"].size()) + " tested ("), std::string::npos) << r.caption;
        EXPECT_NE(r.caption.find(std::to_string(expected.size()) + " distinct triangles"), std::string::npos)
            << r.caption;
        EXPECT_NE(r.caption.find("decided by reconstructed_edge"), std::string::npos) << r.caption;
        // The legend's counts are the image's.
        size_t total = 0;
        for (const auto& entry : r.data["legend"]) {
            const int k = entry["branch"].get<int>();
            EXPECT_EQ(entry["count"].get<size_t>(), counts[size_t(k)]) << entry["name"];
            total += entry["count"].get<size_t>();
        }
        EXPECT_EQ(r.data["legend"].size(), 9u);
        EXPECT_EQ(total, b.pixelCount());
        EXPECT_GT(counts[5], 0u);
        // Each branch that decided a pixel shows in the map in its legend colour.
        for (const auto& entry : r.data["legend"])
            if (entry["count"].get<size_t>() > 200u)
                EXPECT_GT(pixelsNear(r.image, {entry["rgb"][0].get<float>(), entry["rgb"][1].get<float>(), entry["rgb"][2].get<float>()}, 0.02f), 10u)
                    << entry["name"];
    }
}

// A neighbour's hit (branch 3): the drawn triangles hold the one that was hit; no edge is drawn.
TEST_F(SpsmTexelsView, ANeighbourHitDrawsNoEdge) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options());
    const Image b = branches(renderer);
    const std::optional<glm::ivec2> pixel = pixelDecidedBy(renderer, b, 3, "neighbour_hit");
    ASSERT_TRUE(pixel);
    const nlohmann::json rec = record(renderer, *pixel);
    ViewRequest q = request(*pixel, 800, 400);
    q.exportPath = outPath("neighbour-hit.vtp");
    ViewResult r = renderView(renderer, scene, q);
    const Exported e = loadExport(q.exportPath);
    EXPECT_EQ(e.triangles, recordTriangles(rec));
    EXPECT_EQ(e.parts[3] + e.parts[4], 0) << "no tangent, no edge";
    int hits = 0;
    for (const auto& t : rec["tested"]) hits += t["result"] == "hit";
    EXPECT_GE(hits, 1);
    EXPECT_NE(r.caption.find(std::to_string(hits) + " hit"), std::string::npos) << r.caption;
}

// Dai et al. 2008's 7x7 neighbourhood (reconstruction off): the grid drawn widens to the texels tested.
TEST_F(SpsmTexelsView, TheGridCoversALargerNeighbourhood) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options({{"neighbourhood", "7"}, {"reconstruction", "false"}}));
    const Image b = branches(renderer);
    std::optional<glm::ivec2> pixel = pixelDecidedBy(renderer, b, 6, "fallback");
    if (!pixel) pixel = pixelDecidedBy(renderer, b, 4, "neighbour_cover");
    ASSERT_TRUE(pixel) << "no pixel went past the 7x7 tests";
    const nlohmann::json rec = record(renderer, *pixel);
    int reach = 0;
    for (const auto& t : rec["tested"])
        reach = std::max({reach, std::abs(t["texel"][0].get<int>() - rec["texel"][0].get<int>()),
                          std::abs(t["texel"][1].get<int>() - rec["texel"][1].get<int>())});
    ASSERT_GE(reach, 2);
    ViewResult r = renderView(renderer, scene, request(*pixel, 800, 400));
    EXPECT_EQ(r.data["neighbourhood_drawn"].get<int>(), 2 * reach + 1);
}

TEST_F(SpsmTexelsView, RefusedWithoutTheRecordOrAPixel) {
    Scene scene = loadScene("square-occluder");
    Renderer hard(scene, [] { RenderOptions o = options(); o.technique = "hard"; return o; }());
    ViewRequest q = request({90, 80}, 640, 480);
    EXPECT_NE(viewRefusal(hard, q).find("technique hard stores no triangles per texel"), std::string::npos)
        << viewRefusal(hard, q);
    EXPECT_THROW(renderView(hard, scene, q), InputError);
    Renderer spsm(scene, options());
    q.pixel.reset();
    EXPECT_NE(viewRefusal(spsm, q).find("needs a picked pixel"), std::string::npos);
    EXPECT_EQ(viewRefusal(spsm, request({90, 80}, 640, 480)), "");
}

}  // namespace
}  // namespace shadowlab
