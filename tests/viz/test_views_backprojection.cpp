// The `backprojection` view (viz/view_backprojection.cpp) on ssm-contour and ssm-gbp06: the visible
// fraction it prints equals the technique's visibility at the pixel, its export loads back with one
// cell per edge or sample (and one for the initial area), each cell's polygon has the area the
// record gives it and the cells add up to the occluded area; the hsm view (viz/view_hsm.cpp) marks
// the kernel steps `render --pixel` records, labels every level and draws the kernel in the colour
// its title names; techniques without the record are refused.
#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkNew.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "error.h"
#include "graph/renderer.h"
#include "image/image.h"
#include "scene/scene.h"
#include "support/cli_run.h"
#include "support/gl_fixture.h"
#include "view_common.h"
#include "views.h"

namespace shadowlab {
namespace {

class BackprojectionView : public testing::GLTest {};

// A polygon cell's signed area in the xy plane (counter-clockwise positive).
double shoelaceArea(vtkCell* cell) {
    double twice = 0.0;
    for (vtkIdType i = 0, n = cell->GetNumberOfPoints(); i < n; ++i) {
        double a[3], b[3];
        cell->GetPoints()->GetPoint(i, a);
        cell->GetPoints()->GetPoint((i + 1) % n, b);
        twice += a[0] * b[1] - a[1] * b[0];
    }
    return 0.5 * twice;
}

// A renderer of `technique` at w x h with an sm_size map, and a 320x240 request for `view`.
RenderOptions options(const std::string& technique, int w, int h, const std::string& smSize) {
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.technique = technique;
    o.sets = {{"sm_size", smSize}};
    return o;
}
ViewRequest viewRequest(const std::string& view, glm::ivec2 pixel, int light = 0) {
    ViewRequest request;
    request.view = view;
    request.pixel = pixel;
    request.light = light;
    request.width = 320;
    request.height = 240;
    return request;
}

// The hsm view's crop (level-0 texels) holds every kernel step's texels.
void expectStepsInsideTheCrop(const ViewResult& r) {
    const auto& crop = r.data["crop"];
    for (const auto& s : r.data.value("steps", nlohmann::json::array())) {
        const double scale = std::ldexp(1.0, s["level"].get<int>());
        EXPECT_LE(crop[0].get<double>(), s["texels"][0].get<double>() * scale) << s.dump();
        EXPECT_LE(crop[1].get<double>(), s["texels"][1].get<double>() * scale) << s.dump();
        EXPECT_GE(crop[2].get<double>(), (s["texels"][2].get<double>() + 1) * scale) << s.dump();
        EXPECT_GE(crop[3].get<double>(), (s["texels"][3].get<double>() + 1) * scale) << s.dump();
    }
}

// Tolerance 1e-4: the record's areas are floats summed on the CPU, the image's visibility on the
// GPU (the techniques' own record test uses the same bound).
TEST_F(BackprojectionView, VisibleFractionEqualsTheImageAndExportLoadsBack) {
    Scene scene = loadScene("square-occluder");
    int checked = 0, withItems = 0;
    for (const std::string technique : {"ssm-contour", "ssm-gbp06"}) {
        Renderer renderer(scene, options(technique, 96, 96, "256"));
        renderer.renderFrame(0, {"visibility"});
        const Image vis = renderer.visibility();
        // A penumbra pixel and a few others along a row through the shadow.
        std::vector<glm::ivec2> pixels;
        for (int x = 8; x < 96; x += 11) pixels.push_back({x, 60});
        for (const glm::ivec2 p : pixels) {
            if (renderer.ids().at(p.x, p.y) < 0.0f) continue;
            ViewRequest request = viewRequest("backprojection", p);
            request.exportPath = test::testPath("viz", "bp-" + technique + "-" + std::to_string(p.x) + ".vtp");
            ASSERT_EQ(viewRefusal(renderer, request), "");
            ViewResult r = renderView(renderer, scene, request);
            const double shown = r.data["visible_fraction"].get<double>();
            EXPECT_NEAR(shown, vis.at(p.x, p.y), 1e-4) << technique << " pixel " << p.x << "," << p.y;
            EXPECT_NE(r.caption.find("visible fraction"), std::string::npos);
            vtkNew<vtkXMLPolyDataReader> reader;
            reader->SetFileName(request.exportPath.c_str());
            reader->Update();
            // One cell per edge or sample, and one for the initial area (the centre occluded).
            EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(),
                      r.data["count"].get<vtkIdType>() + (r.data["initial_area"].get<double>() > 0.0 ? 1 : 0))
                << technique;
            EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), r.data["cells"].get<vtkIdType>()) << technique;
            EXPECT_NE(reader->GetOutput()->GetCellData()->GetArray("signed_area"), nullptr);
            ++checked;
            if (r.data["count"].get<int>() > 0) ++withItems;
        }
    }
    EXPECT_GE(checked, 10);
    EXPECT_GE(withItems, 2);  // some pixels are in the penumbra: edges / samples drawn
}

// Issue 19: the view draws exactly what it counts. For every picked penumbra pixel, each exported
// cell's polygon (shoelace over its points, signed by its orientation) has the record's area
// (`signed_area`: an edge's signed area, a sample's clipped quad area, the initial area), and the
// cells add up to the occluded area the caption prints. Tolerance 1e-4: the square's cells are
// exact up to float rounding, the disk's border is cut into chords of 2 pi / 2048 (at most 5e-6 off
// for the whole disk). Scenes with penumbrae under a square light (square-occluder,
// overlapping-occluders, plant) and a sphere light (sphere-light: the record's unit disk).
TEST_F(BackprojectionView, CellsHaveTheAreasTheRecordAddsUp) {
    double maxCellError = 0.0, maxSumError = 0.0, maxRasterError = 0.0;
    int cases = 0, diskCases = 0, withInitial = 0, withNegative = 0;
    for (const std::string name : {"square-occluder", "overlapping-occluders", "plant", "sphere-light"}) {
        Scene scene = loadScene(name);
        for (const std::string technique : {"ssm-gbp06", "ssm-contour"}) {
            SCOPED_TRACE(name + " " + technique);
            Renderer renderer(scene, options(technique, 96, 96, "512"));
            renderer.renderFrame(0, {"visibility"});
            const Image vis = renderer.visibility();
            // Penumbra pixels (0.05 < v < 0.95) in scan order; five spread evenly over them.
            std::vector<glm::ivec2> penumbra;
            for (int y = 0; y < vis.height; ++y)
                for (int x = 0; x < vis.width; ++x)
                    if (renderer.ids().at(x, y) >= 0.0f && vis.at(x, y) > 0.05f && vis.at(x, y) < 0.95f)
                        penumbra.push_back({x, y});
            ASSERT_GE(penumbra.size(), 5u);
            for (int k = 0; k < 5; ++k) {
                const glm::ivec2 p = penumbra[size_t((k + 0.5) * double(penumbra.size()) / 5.0)];
                SCOPED_TRACE("pixel " + std::to_string(p.x) + "," + std::to_string(p.y));
                ViewRequest request = viewRequest("backprojection", p);
                request.exportPath = test::testPath("viz", "bp-cells-" + name + "-" + technique + "-" + std::to_string(k) + ".vtp");
                ViewResult r = renderView(renderer, scene, request);
                vtkNew<vtkXMLPolyDataReader> reader;
                reader->SetFileName(request.exportPath.c_str());
                reader->Update();
                vtkPolyData* poly = reader->GetOutput();
                vtkDataArray* areas = poly->GetCellData()->GetArray("signed_area");
                vtkDataArray* kinds = poly->GetCellData()->GetArray("kind");
                ASSERT_NE(areas, nullptr);
                ASSERT_NE(kinds, nullptr);
                ASSERT_EQ(poly->GetNumberOfCells(), r.data["cells"].get<vtkIdType>());
                double sum = 0.0;
                for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c) {
                    const double area = shoelaceArea(poly->GetCell(c)), recorded = areas->GetTuple1(c);
                    const int kind = int(kinds->GetTuple1(c));
                    // Samples' quads are counter-clockwise, so their signed area is their area.
                    EXPECT_NEAR(area, recorded, 1e-4) << "cell " << c << " kind " << kind;
                    EXPECT_EQ(kind, technique == "ssm-contour" ? (c == 0 && r.data["initial_area"].get<double>() > 0.0 ? 0 : 1)
                                                                 : (c == 0 && r.data["initial_area"].get<double>() > 0.0 ? 0 : 2));
                    maxCellError = std::max(maxCellError, std::abs(area - recorded));
                    if (kind == 0) ++withInitial;
                    if (recorded < 0.0) ++withNegative;
                    sum += area;
                }
                const double occluded = r.data["occluded_area"].get<double>();
                EXPECT_NEAR(sum, occluded, 1e-4);
                EXPECT_NE(r.caption.find("occluded " + formatNumber(occluded, 5)), std::string::npos) << r.caption;
                maxSumError = std::max(maxSumError, std::abs(sum - occluded));
                // The right panel's net count, integrated over its 256^2 texels, is the same sum
                // (texel-centre sampling of every cell's border; 0.011 measured).
                EXPECT_NEAR(r.data["coverage_area"].get<double>(), occluded, 0.04);
                maxRasterError = std::max(maxRasterError, std::abs(r.data["coverage_area"].get<double>() - occluded));
                if (r.data["light_shape"] == "disk") ++diskCases;
                ++cases;
            }
        }
    }
    EXPECT_EQ(cases, 40);
    EXPECT_EQ(diskCases, 10);  // sphere-light, both techniques
    EXPECT_GE(withNegative, 1);  // contour edges that uncover light were drawn
    std::printf("backprojection cells: max |polygon area - record| %.3g, max |sum of cells - occluded| %.3g, max "
                "|net count raster - occluded| %.3g; %d initial cells, %d negative cells\n",
                maxCellError, maxSumError, maxRasterError, withInitial, withNegative);
}

// ssv (soft shadow volumes) in the same view: each silhouette edge whose wedge holds the picked
// point is drawn as the part of the light beyond it (weight 2 edges of open meshes twice), each hard
// shadow volume holding it as one whole light; every exported cell has the record's area within
// 1e-4, the cells add up to the occluded area, and the visible fraction is the image's (1e-4), on
// the same four scenes, five penumbra pixels each. With split 2 (four lights) the view refuses.
TEST_F(BackprojectionView, SsvCellsHaveTheRecordsAreasAndTheImagesVisibility) {
    int cases = 0, withInitial = 0, withNegative = 0, diskCases = 0;
    double maxCellError = 0.0;
    for (const std::string name : {"square-occluder", "overlapping-occluders", "plant", "sphere-light"}) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(name);
        RenderOptions o;
        o.width = o.height = 96;
        o.technique = "ssv";
        Renderer renderer(scene, o);
        renderer.renderFrame(0, {"visibility"});
        const Image vis = renderer.visibility();
        std::vector<glm::ivec2> penumbra;
        for (int y = 0; y < vis.height; ++y)
            for (int x = 0; x < vis.width; ++x)
                if (renderer.ids().at(x, y) >= 0.0f && vis.at(x, y) > 0.05f && vis.at(x, y) < 0.95f) penumbra.push_back({x, y});
        ASSERT_GE(penumbra.size(), 5u);
        for (int k = 0; k < 5; ++k) {
            const glm::ivec2 p = penumbra[size_t((k + 0.5) * double(penumbra.size()) / 5.0)];
            SCOPED_TRACE("pixel " + std::to_string(p.x) + "," + std::to_string(p.y));
            ViewRequest request = viewRequest("backprojection", p);
            request.exportPath = test::testPath("viz", "bp-ssv-" + name + "-" + std::to_string(k) + ".vtp");
            ASSERT_EQ(viewRefusal(renderer, request), "");
            ViewResult r = renderView(renderer, scene, request);
            EXPECT_NEAR(r.data["visible_fraction"].get<double>(), vis.at(p.x, p.y), 1e-4);
            vtkNew<vtkXMLPolyDataReader> reader;
            reader->SetFileName(request.exportPath.c_str());
            reader->Update();
            vtkPolyData* poly = reader->GetOutput();
            vtkDataArray* areas = poly->GetCellData()->GetArray("signed_area");
            vtkDataArray* kinds = poly->GetCellData()->GetArray("kind");
            ASSERT_NE(areas, nullptr);
            double sum = 0.0;
            for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c) {
                const double area = shoelaceArea(poly->GetCell(c)), recorded = areas->GetTuple1(c);
                EXPECT_NEAR(area, recorded, 1e-4) << "cell " << c;
                maxCellError = std::max(maxCellError, std::abs(area - recorded));
                withInitial += int(kinds->GetTuple1(c)) == 0;
                withNegative += recorded < 0.0;
                sum += area;
            }
            EXPECT_NEAR(sum, r.data["occluded_area"].get<double>(), 1e-4);
            EXPECT_NE(r.caption.find("silhouette edges"), std::string::npos) << r.caption;
            diskCases += r.data["light_shape"] == "disk";
            ++cases;
        }
    }
    EXPECT_EQ(cases, 20);
    EXPECT_EQ(diskCases, 5);
    EXPECT_GE(withInitial, 1);   // pixels inside a hard volume: the whole light first
    EXPECT_GE(withNegative, 1);  // edges that uncover light
    std::printf("backprojection ssv: max |polygon area - record| %.3g; %d initial cells, %d negative cells\n",
                maxCellError, withInitial, withNegative);
    // Split 2: refused, naming the split.
    Scene scene = loadScene("square-occluder");
    RenderOptions o;
    o.width = o.height = 64;
    o.technique = "ssv";
    o.sets = {{"split", "2"}};
    Renderer renderer(scene, o);
    renderer.renderFrame(0, {"visibility"});
    try {
        renderView(renderer, scene, viewRequest("backprojection", {32, 40}));
        ADD_FAILURE() << "split 2 was drawn";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("split 2"), std::string::npos) << e.what();
    }
}

// pvm (issue 22): the light's disk with the cutting line. Inside a volume the hidden part is one
// cell whose polygon has the area pi - 2a / r^2 (the record's segment_area a, eq. 4.1 at -s, on the
// unit disk), the visible fraction is k = 2a / (pi r^2) (the record's k, eq. 4.2) and the caption's
// 3k^2 - 2k^3 times the front fraction is the image's visibility; outside every volume the whole
// disk (umbra) or no cell (lit). Tolerance 1e-4 as above (float record against the GPU's float).
TEST_F(BackprojectionView, PvmDiskHasTheRecordsSegmentAndTheImagesVisibility) {
    int inVolume = 0, umbra = 0, lit = 0;
    for (const std::string name : {"sphere-light", "overlapping-occluders"}) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(name);
        RenderOptions o;
        o.width = o.height = 96;
        o.technique = "pvm";
        Renderer renderer(scene, o);
        renderer.renderFrame(0, {"visibility"});
        const Image vis = renderer.visibility();
        // Up to 8 penumbra pixels (0 < v < 1), 3 dark and 3 lit ones, spread over the image.
        std::vector<glm::ivec2> picks;
        int want[3] = {8, 3, 3};
        for (int y = 2; y < 96; y += 3)
            for (int x = 2 + (y / 3) % 3; x < 96; x += 7) {
                if (renderer.ids().at(x, y) < 0.0f) continue;
                const float v = vis.at(x, y);
                const int kind = v <= 0.0f ? 1 : (v >= 1.0f ? 2 : 0);
                if (want[kind] > 0 && (kind != 0 || (x + y) % 2 == 0)) {
                    --want[kind];
                    picks.push_back({x, y});
                }
            }
        for (const glm::ivec2 pick : picks) {
                const int x = pick.x, y = pick.y;
                SCOPED_TRACE("pixel " + std::to_string(x) + "," + std::to_string(y));
                ViewRequest request = viewRequest("backprojection", {x, y});
                request.exportPath = test::testPath("viz", "bp-pvm-" + name + ".vtp");
                ASSERT_EQ(viewRefusal(renderer, request), "");
                ViewResult r = renderView(renderer, scene, request);
                EXPECT_NEAR(r.data["visible_fraction"].get<double>(), vis.at(x, y), 1e-4);
                vtkNew<vtkXMLPolyDataReader> reader;
                reader->SetFileName(request.exportPath.c_str());
                reader->Update();
                vtkPolyData* poly = reader->GetOutput();
                if (r.caption.find(" volume of edge ") != std::string::npos) {
                    ASSERT_EQ(poly->GetNumberOfCells(), 1);
                    const double hidden = shoelaceArea(poly->GetCell(0));
                    const double k = 1.0 - hidden / M_PI;
                    EXPECT_NEAR(hidden, r.data["occluded_area"].get<double>(), 1e-4);
                    EXPECT_NEAR(k, r.data["unoccluded_fraction"].get<double>(), 1e-4);
                    EXPECT_NE(r.caption.find("k = 2a/(pi r^2)"), std::string::npos) << r.caption;
                    ++inVolume;
                } else if (poly->GetNumberOfCells() == 1) {
                    EXPECT_NEAR(shoelaceArea(poly->GetCell(0)), M_PI, 1e-4);
                    EXPECT_NE(r.caption.find("umbra"), std::string::npos) << r.caption;
                    ++umbra;
                } else {
                    EXPECT_EQ(poly->GetNumberOfCells(), 0);
                    const bool behind = r.data["front_fraction"].get<double>() <= 0.0;
                    EXPECT_NE(r.caption.find(behind ? "behind the receiver's tangent plane" : "lit"), std::string::npos)
                        << r.caption;
                    lit += !behind;
                }
            }
    }
    std::printf("backprojection pvm: %d pixels in a volume, %d umbra, %d lit\n", inVolume, umbra, lit);
    EXPECT_GE(inVolume, 10);
    EXPECT_GE(umbra, 2);
    EXPECT_GE(lit, 4);
}

// The per-pixel record of the back-projection techniques has its own "light_geometry" (shape,
// area); it used to be called "light" and replaced the light's index the renderer merges under that
// key, so ViewContext::pixelRecord() threw a json type_error for ssm-* (the shadow-map view with a
// picked pixel failed), and the backprojection view took records by position, which is wrong when
// a light before the picked one casts no shadow (its record is skipped). Both now find the record
// by index: a scene whose light 0 casts no shadows and whose light 1 runs ssm-contour.
TEST_F(BackprojectionView, RecordsAreFoundByLightIndex) {
    const std::string path = test::testPath("viz", "two-lights.json");
    std::ofstream(path) << R"({
      "camera": {"position": [0, 5.5, 6.5], "target": [0, 0, 0.3], "fov_deg": 40},
      "lights": [
        {"type": "square", "position": [3, 4, 0], "direction": [0, -1, 0], "width": 1, "casts_shadows": false},
        {"type": "square", "position": [0, 4, 0], "direction": [0, -1, 0], "up": [0, 0, -1], "width": 1}],
      "objects": [
        {"name": "floor", "id": 0, "type": "quad", "size": [8, 8], "casts_shadows": false},
        {"name": "plate", "id": 1, "type": "box", "size": [1, 0.001, 1], "transform": {"translate": [0, 2, 0]}}]})";
    Scene scene = loadScene(path);
    Renderer renderer(scene, options("ssm-contour", 96, 96, "256"));
    renderer.renderFrame(0, {"visibility"});
    const glm::ivec2 pixel(48, 60);
    ASSERT_GE(renderer.ids().at(pixel.x, pixel.y), 0.0f);
    for (const char* view : {"backprojection", "shadow-map"}) {
        SCOPED_TRACE(view);
        const ViewRequest request = viewRequest(view, pixel, 1);
        ASSERT_EQ(viewRefusal(renderer, request), "");
        ViewResult r;
        ASSERT_NO_THROW(r = renderView(renderer, scene, request));
        if (std::string(view) == "backprojection")
            EXPECT_TRUE(r.data.contains("visible_fraction")) << r.data.dump();
    }
}

TEST_F(BackprojectionView, TechniquesWithoutTheRecordAreRefused) {
    auto r = test::run("viz --view backprojection --scene square-occluder --technique pcf --pixel 40,40 --size 64x64 --out " +
                       test::testPath("viz", "bp-refused.png"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("records no back-projection"), std::string::npos) << r.output;
}

// hsm: the steps the view marks are the record's (same levels and texels as --internals' pixel.json
// gives), each step's texels lie inside its level, and techniques without an HSM are refused.
TEST_F(BackprojectionView, HsmMarksTheKernelStepsOfTheRecord) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options("ssm-contour", 96, 96, "256"));
    const ViewRequest request = viewRequest("hsm", glm::ivec2(48, 60));
    ASSERT_EQ(viewRefusal(renderer, request), "");
    ViewResult r = renderView(renderer, scene, request);
    EXPECT_EQ(r.data["levels"].get<int>(), 8);  // 128x128 .. 1x1 over a 256x256 map
    ASSERT_TRUE(r.data.contains("steps"));
    ASSERT_GE(r.data["steps"].size(), 1u);
    for (const auto& s : r.data["steps"]) {
        const int level = s["level"].get<int>(), size = 256 >> level;
        for (int c = 0; c < 4; ++c) {
            EXPECT_GE(s["texels"][c].get<int>(), 0);
            EXPECT_LT(s["texels"][c].get<int>(), size) << s.dump();
        }
    }
    EXPECT_NE(r.caption.find("steps"), std::string::npos);
    // The same pixel's record as the command line writes it (--internals DIR/pixel.json).
    const std::string dir = test::testPath("viz", "hsm-record");
    std::filesystem::remove_all(dir);
    const auto cli = test::run("render --scene square-occluder --technique ssm-contour --size 96x96 --set sm_size=256 "
                               "--pixel 48,60 --out " + dir + ".png --internals " + dir);
    ASSERT_EQ(cli.code, 0) << cli.output;
    std::ifstream in(dir + "/pixel.json");
    ASSERT_TRUE(in) << dir;
    const nlohmann::json record = nlohmann::json::parse(in);
    const auto& recorded = record["lights"][0]["kernel"]["steps"];
    ASSERT_EQ(recorded.size(), r.data["steps"].size()) << recorded.dump() << " vs " << r.data["steps"].dump();
    for (size_t i = 0; i < recorded.size(); ++i) {
        EXPECT_EQ(recorded[i]["level"], r.data["steps"][i]["level"]) << i;
        EXPECT_EQ(recorded[i]["texels"], r.data["steps"][i]["texels"]) << i;
    }
    expectStepsInsideTheCrop(r);
    Renderer pcf(scene, [] { RenderOptions p; p.width = 64; p.height = 64; p.technique = "pcf"; return p; }());
    EXPECT_NE(viewRefusal(pcf, request).find("no min/max pyramid"), std::string::npos);
}

// On plant the casters cover a quarter of the map's width: every level is cropped to the square
// around them (the note of issue 10: the levels were unreadable at full size), which still holds
// the picked penumbra pixel's kernel steps.
TEST_F(BackprojectionView, HsmCropsToTheCasters) {
    Scene scene = loadScene("plant");
    Renderer renderer(scene, options("ssm-contour", 160, 120, "512"));
    ViewResult r = renderView(renderer, scene, viewRequest("hsm", glm::ivec2(80, 100)));
    ASSERT_GE(r.data.value("steps", nlohmann::json::array()).size(), 1u) << r.caption;
    expectStepsInsideTheCrop(r);
    const auto& crop = r.data["crop"];
    const double side = crop[2].get<double>() - crop[0].get<double>();
    EXPECT_LT(side, 0.6 * 512) << crop.dump();
    EXPECT_NEAR(crop[3].get<double>() - crop[1].get<double>(), side, 1e-9);  // square, as the levels are
    EXPECT_NE(r.caption.find("shown (the casters)"), std::string::npos) << r.caption;
}

// Issue 19: the hsm view draws what its title promises. Every level is a tile labelled with its
// number and texel size in level-0 texels; the converged kernel is drawn in the colour the title
// names (cyan), which appears in the picture with a picked pixel and nowhere without one (the depth
// map's colours never reach it); each step's number is a label on its level.
TEST_F(BackprojectionView, HsmLabelsEveryLevelAndDrawsTheKernelInTheTitlesColour) {
    Scene scene = loadScene("plant");
    Renderer renderer(scene, options("ssm-contour", 160, 120, "512"));
    auto cyanPixels = [](const Image& image) {
        int n = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                if (image.at(x, y, 0) < 0.4f && image.at(x, y, 1) > 0.85f && image.at(x, y, 2) > 0.85f) ++n;
        return n;
    };
    // A penumbra pixel (0.05 < v < 0.95), the middle one in scan order: its kernel refines.
    renderer.renderFrame(0, {"visibility"});
    const Image vis = renderer.visibility();
    std::vector<glm::ivec2> penumbra;
    for (int y = 0; y < vis.height; ++y)
        for (int x = 0; x < vis.width; ++x)
            if (renderer.ids().at(x, y) >= 0.0f && vis.at(x, y) > 0.05f && vis.at(x, y) < 0.95f) penumbra.push_back({x, y});
    ASSERT_FALSE(penumbra.empty());
    ViewRequest request = viewRequest("hsm", penumbra[penumbra.size() / 2]);
    request.width = 800;
    request.height = 600;
    ViewResult r = renderView(renderer, scene, request);
    EXPECT_NE(r.data["title"].get<std::string>().find("kernel (cyan)"), std::string::npos) << r.data["title"];
    EXPECT_EQ(r.data["kernel_colour"], nlohmann::json({0.2f, 1.0f, 1.0f}));
    ASSERT_TRUE(r.data.contains("kernel_range")) << r.data.dump();
    EXPECT_NE(r.caption.find("(penumbra)"), std::string::npos) << r.caption;
    const int cyan = cyanPixels(r.image);
    EXPECT_GE(cyan, 40) << "the kernel's outline, on every level's two tiles";
    const int levels = r.data["levels"].get<int>();
    EXPECT_EQ(levels, 9);  // 256x256 .. 1x1 over a 512x512 map
    ASSERT_EQ(r.data["levels_drawn"].size(), size_t(levels));
    for (int k = 1; k <= levels; ++k) {
        const auto& drawn = r.data["levels_drawn"][size_t(k - 1)];
        const std::string n = std::to_string(1 << k);
        EXPECT_EQ(drawn["level"].get<int>(), k);
        EXPECT_EQ(drawn["texel_size"].get<int>(), 1 << k);
        EXPECT_EQ(drawn["label"].get<std::string>(), "level " + std::to_string(k) + ", " + n + "x" + n + " texels");
        // As drawn: the full label, or where the band above the tile is too small for it at the text
        // standard's size, a shorter form that still names the level and its texel size.
        const std::string text = drawn["text"].get<std::string>(), lk = "L" + std::to_string(k);
        EXPECT_TRUE(text == "level " + std::to_string(k) + ",\n" + n + "x" + n + " texels" || text == lk + " " + n + "x" + n ||
                    text == lk + "\n" + n + "x" + n || text == lk + "\n" + n)
            << text;
        EXPECT_NE(r.caption.find("'Lk N' is level k, texels of N x N"), std::string::npos) << r.caption;
    }
    // Every step is numbered once, on the level it read.
    const auto& steps = r.data["steps"];
    ASSERT_GE(steps.size(), 1u);
    std::string numbered;
    for (const auto& label : r.data["step_labels"]) {
        numbered += label["text"].get<std::string>() + ", ";
        EXPECT_EQ(label["drawn_on_level"].get<int>(), std::max(1, label["level"].get<int>()));
    }
    for (size_t i = 0; i < steps.size(); ++i)
        EXPECT_NE(numbered.find(std::to_string(i + 1)), std::string::npos) << numbered;
    // No picked pixel: no kernel, no cyan.
    ViewRequest none = request;
    none.pixel.reset();
    EXPECT_EQ(cyanPixels(renderView(renderer, scene, none).image), 0);
}

}  // namespace
}  // namespace shadowlab
