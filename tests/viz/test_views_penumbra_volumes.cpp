// The `penumbra-volumes` view (viz/view_penumbra_volumes.cpp) on pvm and pvmf: it draws exactly the
// quads the technique rasterized (its export holds the `penumbra_volumes` internal's triangles, point
// for point, with their edge and side), the volume it marks as covering the picked pixel is the
// record's (pvm: the PVEM's edge and side) or the nearest the ray from the light centre to the point
// crosses (pvmf: the mask's rule), and techniques without volumes are refused.
#include <gtest/gtest.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <map>

#include "graph/internals.h"
#include "graph/renderer.h"
#include "scene/scene.h"
#include "support/cli_run.h"
#include "support/gl_fixture.h"
#include "view_common.h"
#include "views.h"

namespace shadowlab {
namespace {

class PenumbraVolumesView : public testing::GLTest {};

struct Collect : InternalSink {
    std::map<std::string, MeshData> meshes;
    std::map<std::string, nlohmann::json> records;
    void image(const std::string&, const Image&, const std::string&, const std::string&, int) override {}
    void mesh(const std::string& name, const MeshData& mesh, const std::string&, const std::string&) override {
        meshes[prefix_ + name] = mesh;
    }
    void json(const std::string& name, const nlohmann::json& value, const std::string&, const std::string&) override {
        records[name] = value;
    }
};

float segmentHit(const glm::vec3& o, const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 d = glm::normalize(p - o);
    const glm::vec3 e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
    const float det = glm::dot(e1, h);
    if (std::abs(det) < 1e-12f) return INFINITY;
    const glm::vec3 s = o - a;
    const float u = glm::dot(s, h) / det;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) / det;
    if (u < 0.0f || v < 0.0f || u + v > 1.0f) return INFINITY;
    const float t = glm::dot(e2, q) / det;
    return t > 0.0f && t < glm::length(p - o) ? t : INFINITY;
}

TEST_F(PenumbraVolumesView, DrawsTheVolumesTheTechniqueDrewAndTheOneCoveringThePick) {
    for (const char* technique : {"pvm", "pvmf"}) {
        SCOPED_TRACE(technique);
        Scene scene = loadScene("sphere-light");
        RenderOptions o;
        o.width = o.height = 96;
        o.technique = technique;
        Renderer renderer(scene, o);
        renderer.renderFrame(0, renderer.internalRequests(true));
        Collect drawn;
        renderer.writeInternals(drawn, std::nullopt);
        const MeshData& volumes = drawn.meshes.at("penumbra_volumes");
        // A pixel inside a volume (the record says so).
        const Image vis = renderer.visibility();
        glm::ivec2 pick(-1);
        nlohmann::json rec;
        for (int y = 0; y < vis.height && pick.x < 0; y += 2)
            for (int x = 0; x < vis.width; x += 2) {
                if (renderer.ids().at(x, y) < 0.0f || vis.at(x, y) < 0.1f || vis.at(x, y) > 0.9f) continue;
                Collect c;
                renderer.writeInternals(c, glm::ivec2(x, y));
                const nlohmann::json& j = c.records["pixel"]["lights"][0];
                if (j.value("in_volume", false)) {
                    pick = {x, y};
                    rec = j;
                    break;
                }
            }
        ASSERT_GE(pick.x, 0);
        ViewRequest request;
        request.view = "penumbra-volumes";
        request.pixel = pick;
        request.exportPath = test::testPath("viz", std::string("penumbra-volumes-") + technique + ".vtp");
        ASSERT_EQ(viewRefusal(renderer, request), "");
        ViewResult r = renderView(renderer, scene, request);
        EXPECT_EQ(r.data["outer_volumes"].get<size_t>() + r.data["inner_volumes"].get<size_t>(),
                  volumes.primitiveCount() / 2);
        ASSERT_TRUE(r.data["volume"].is_object()) << r.caption;
        const int heldEdge = r.data["volume"]["edge"].get<int>();
        const int heldSide = r.data["volume"]["side"].get<std::string>() == "outer" ? 0 : 1;
        if (std::string(technique) == "pvm") {
            EXPECT_EQ(heldEdge, rec["volume"]["edge"].get<int>());
            EXPECT_EQ(r.data["volume"]["side"], rec["volume"]["side"]);
        }

        vtkNew<vtkXMLPolyDataReader> reader;
        reader->SetFileName(request.exportPath.c_str());
        reader->Update();
        vtkPolyData* poly = reader->GetOutput();
        vtkDataArray* part = poly->GetCellData()->GetArray("part");
        vtkDataArray* edge = poly->GetCellData()->GetArray("edge");
        vtkDataArray* face = poly->GetCellData()->GetArray("face");
        vtkDataArray* holds = poly->GetCellData()->GetArray("holds_pixel");
        ASSERT_TRUE(part && edge && face && holds);
        // Every exported volume triangle is one the technique drew, per (edge, side) in order.
        std::map<std::pair<int, int>, std::vector<glm::vec3>> exported, internal;
        std::vector<glm::vec3> held;
        for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c) {
            if (int(part->GetTuple1(c)) != 3) continue;
            vtkCell* cell = poly->GetCell(c);
            ASSERT_EQ(cell->GetNumberOfPoints(), 3);
            const std::pair<int, int> key(int(edge->GetTuple1(c)), int(face->GetTuple1(c)));
            for (int k = 0; k < 3; ++k) {
                double x[3];
                cell->GetPoints()->GetPoint(k, x);
                exported[key].push_back(glm::vec3(float(x[0]), float(x[1]), float(x[2])));
                if (holds->GetTuple1(c) == 1.0) held.push_back(exported[key].back());
            }
            if (holds->GetTuple1(c) == 1.0) {
                EXPECT_EQ(key.first, heldEdge);
                EXPECT_EQ(key.second, heldSide);
            }
        }
        const std::vector<float>& edgeOf = volumes.primitiveAttributes[0].second;
        const std::vector<float>& sideOf = volumes.primitiveAttributes[1].second;
        for (size_t t = 0; t < volumes.primitiveCount(); ++t)
            for (int k = 0; k < 3; ++k)
                internal[{int(edgeOf[t]), int(sideOf[t])}].push_back(volumes.positions[volumes.indices[3 * t + k]]);
        EXPECT_EQ(exported, internal);
        ASSERT_EQ(held.size(), 6u);  // one quad: two triangles
        if (std::string(technique) == "pvmf") {
            // The held quad is crossed by the ray from the light centre to the point, nearer than any other.
            const Image positions = renderer.positions();
            const glm::vec3 p(positions.at(pick.x, pick.y, 0), positions.at(pick.x, pick.y, 1),
                              positions.at(pick.x, pick.y, 2));
            const glm::vec3 l = scene.lights[0].position;
            const float heldHit = std::min(segmentHit(l, p, held[0], held[1], held[2]),
                                           segmentHit(l, p, held[3], held[4], held[5]));
            EXPECT_TRUE(std::isfinite(heldHit));
            for (size_t t = 0; t < volumes.primitiveCount(); ++t)
                EXPECT_GE(segmentHit(l, p, volumes.positions[volumes.indices[3 * t]],
                                     volumes.positions[volumes.indices[3 * t + 1]],
                                     volumes.positions[volumes.indices[3 * t + 2]]),
                          heldHit - 1e-5f);
            EXPECT_NE(r.caption.find("w_pcf"), std::string::npos) << r.caption;
        } else {
            EXPECT_NE(r.caption.find("k = "), std::string::npos) << r.caption;
        }
    }
    // Refused for a technique without volumes.
    Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 32;
    o.technique = "pcf";
    Renderer renderer(scene, o);
    ViewRequest request;
    request.view = "penumbra-volumes";
    EXPECT_NE(viewRefusal(renderer, request).find("no penumbra volumes"), std::string::npos);
}

}  // namespace
}  // namespace shadowlab
