// The `wedges` view (viz/view_volumes.cpp) on ssv: it draws exactly the meshes the technique drew
// (its export holds the `silhouettes` and `wedges` internals' geometry, point for point), the
// wedges it marks as holding the picked pixel are the per-pixel record's and each holds the point
// (its exported triangles' planes), and techniques without wedges are refused.
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

class WedgesView : public testing::GLTest {};

struct Meshes : InternalSink {
    std::map<std::string, MeshData> meshes;
    void image(const std::string&, const Image&, const std::string&, const std::string&, int) override {}
    void mesh(const std::string& name, const MeshData& mesh, const std::string&, const std::string&) override {
        meshes[prefix_ + name] = mesh;
    }
    void json(const std::string&, const nlohmann::json&, const std::string&, const std::string&) override {}
};

TEST_F(WedgesView, DrawsTheWedgesTheTechniqueDrewAndThoseHoldingThePick) {
    for (const char* name : {"square-occluder", "overlapping-occluders"}) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(name);
        RenderOptions o;
        o.width = o.height = 96;
        o.technique = "ssv";
        Renderer renderer(scene, o);
        renderer.renderFrame(0, renderer.internalRequests(false));
        Meshes drawn;
        renderer.writeInternals(drawn, std::nullopt);
        const MeshData& wedges = drawn.meshes.at("wedges");
        const MeshData& edges = drawn.meshes.at("silhouettes");
        // A penumbra pixel.
        const Image vis = renderer.visibility();
        glm::ivec2 pick(-1);
        for (int y = 0; y < vis.height && pick.x < 0; ++y)
            for (int x = 0; x < vis.width; ++x)
                if (renderer.ids().at(x, y) >= 0.0f && vis.at(x, y) > 0.2f && vis.at(x, y) < 0.8f) {
                    pick = {x, y};
                    break;
                }
        ASSERT_GE(pick.x, 0);
        ViewRequest request;
        request.view = "wedges";
        request.pixel = pick;
        request.exportPath = test::testPath("viz", std::string("wedges-") + name + ".vtp");
        ASSERT_EQ(viewRefusal(renderer, request), "");
        ViewResult r = renderView(renderer, scene, request);
        EXPECT_EQ(r.data["edges"].get<size_t>(), edges.primitiveCount());
        EXPECT_EQ(r.data["wedges"].get<size_t>() * 8, wedges.primitiveCount());
        const std::vector<int> holding = r.data["holding"].get<std::vector<int>>();
        EXPECT_FALSE(holding.empty()) << "a penumbra pixel lies inside some wedge";

        vtkNew<vtkXMLPolyDataReader> reader;
        reader->SetFileName(request.exportPath.c_str());
        reader->Update();
        vtkPolyData* poly = reader->GetOutput();
        vtkDataArray* part = poly->GetCellData()->GetArray("part");
        vtkDataArray* edge = poly->GetCellData()->GetArray("edge");
        vtkDataArray* holds = poly->GetCellData()->GetArray("holds_pixel");
        ASSERT_TRUE(part && edge && holds);
        // Every exported wedge triangle is one the technique drew: the same corners, in the same
        // order, for the same edge (the internal's triangles, matched in export order per edge).
        std::map<int, std::vector<glm::vec3>> exported, internal;
        std::map<int, int> heldTriangles;
        for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c) {
            if (int(part->GetTuple1(c)) != 3) continue;
            vtkCell* cell = poly->GetCell(c);
            ASSERT_EQ(cell->GetNumberOfPoints(), 3);
            const int e = int(edge->GetTuple1(c));
            for (int k = 0; k < 3; ++k) {
                double x[3];
                cell->GetPoints()->GetPoint(k, x);
                exported[e].push_back(glm::vec3(float(x[0]), float(x[1]), float(x[2])));
            }
            if (holds->GetTuple1(c) == 1.0) ++heldTriangles[e];
        }
        const std::vector<float>& edgeOf = wedges.primitiveAttributes[0].second;
        for (size_t t = 0; t < wedges.primitiveCount(); ++t)
            for (int k = 0; k < 3; ++k) internal[int(edgeOf[t])].push_back(wedges.positions[wedges.indices[3 * t + k]]);
        EXPECT_EQ(exported, internal);
        // The held wedges are the record's, all 8 triangles each, and each holds the picked point:
        // it lies on the inner side of every triangle's plane (wound outwards).
        const Image positions = renderer.positions();
        const glm::vec3 p(positions.at(pick.x, pick.y, 0), positions.at(pick.x, pick.y, 1), positions.at(pick.x, pick.y, 2));
        EXPECT_EQ(heldTriangles.size(), holding.size());
        for (int e : holding) {
            EXPECT_EQ(heldTriangles[e], 8) << "edge " << e;
            const std::vector<glm::vec3>& corners = internal[e];
            for (size_t t = 0; t + 2 < corners.size(); t += 3) {
                glm::vec3 n = glm::cross(corners[t + 1] - corners[t], corners[t + 2] - corners[t]);
                if (glm::length(n) == 0.0f) continue;
                EXPECT_LE(glm::dot(glm::normalize(n), p - corners[t]), 1e-4f) << "edge " << e << " triangle " << t / 3;
            }
        }
        EXPECT_NE(r.caption.find("inside " + std::to_string(holding.size()) + " wedge"), std::string::npos) << r.caption;
    }
    // Refused for a technique without wedges.
    Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 32;
    o.technique = "pcf";
    Renderer renderer(scene, o);
    ViewRequest request;
    request.view = "wedges";
    EXPECT_NE(viewRefusal(renderer, request).find("no penumbra wedges"), std::string::npos);
}

}  // namespace
}  // namespace shadowlab
