// viz/: the VTK bridge (VTK renders into the program's own headless EGL context), the views and
// `shadowlab viz`.
#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkAxis.h>
#include <vtkCamera.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPlot.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTable.h>

#include <filesystem>
#include <glm/glm.hpp>
#include <fstream>
#include <set>
#include <sstream>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <nlohmann/json.hpp>

#include "error.h"
#include "gl/loader.h"
#include "graph/renderer.h"
#include "image/metrics.h"
#include "scene/scene.h"
#include "support/cli_run.h"
#include "support/gl_fixture.h"
#include "view_common.h"
#include "views.h"
#include "vtk_offscreen.h"

namespace fs = std::filesystem;

namespace shadowlab {
namespace {

using testing::GLTest;

class VizBridgeTest : public GLTest {
protected:
    void SetUp() override {
        GLTest::SetUp();
        vtkErrorsBefore_ = vtkMessages().errors;
    }
    void TearDown() override {
        EXPECT_EQ(vtkMessages().errors, vtkErrorsBefore_) << "VTK error: " << vtkMessages().last;
        GLTest::TearDown();
    }
    int vtkErrorsBefore_ = 0;
};

// Mean RGB of a block of pixels.
glm::vec3 meanColor(const Image& img, int x0, int y0, int x1, int y1) {
    glm::vec3 sum(0.0f);
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x, ++n) sum += glm::vec3(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
    return sum / float(n);
}

// A red sphere in the upper half of a blue frame: the image comes back with row 0 at the top, the
// right colours, and the program's GL state (framebuffer, program, viewport, enables) untouched.
TEST_F(VizBridgeTest, RendersA3DViewIntoTheProgramsContextUprightAndKeepsGLState) {
    // State the program had set before the view renders.
    GLuint fbo = 0;
    glCreateFramebuffers(1, &fbo);
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    glTextureStorage2D(tex, 1, GL_RGBA8, 8, 8);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(1, 2, 3, 4);
    glEnable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    glBindTextureUnit(3, tex);

    VtkOffscreen out(160, 120);
    vtkRenderer* renderer = out.addRenderer();
    renderer->SetBackground(0.0, 0.0, 1.0);
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(0.0, 0.5, 0.0);
    sphere->SetRadius(0.4);
    sphere->SetThetaResolution(32);
    sphere->SetPhiResolution(32);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(sphere->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(1.0, 0.0, 0.0);
    actor->GetProperty()->SetAmbient(1.0);
    actor->GetProperty()->SetDiffuse(0.0);
    actor->GetProperty()->SetSpecular(0.0);
    renderer->AddActor(actor);
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    camera->SetPosition(0, 0, 5);
    camera->SetFocalPoint(0, 0, 0);
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(1.0);  // half-height 1: y in [-1, 1]
    renderer->ResetCameraClippingRange();

    Image img = out.render();
    ASSERT_EQ(img.width, 160);
    ASSERT_EQ(img.height, 120);
    ASSERT_EQ(img.channels, 4);
    // The sphere centre y = 0.5 maps to row (1 - 0.5) / 2 * 120 = 30 from the top.
    glm::vec3 sphereColour = meanColor(img, 76, 26, 84, 34);
    glm::vec3 below = meanColor(img, 76, 86, 84, 94);
    EXPECT_GT(sphereColour.r, 0.9f);
    EXPECT_LT(sphereColour.b, 0.1f);
    EXPECT_LT(below.r, 0.1f);
    EXPECT_GT(below.b, 0.9f);
    // Second render of the same window (cached GL objects of VTK) gives the same picture.
    writePNG((fs::path(SHADOWLAB_TEST_TMP) / "viz-bridge-sphere.png").string(), img);
    Image again = out.render();
    EXPECT_EQ(again.data, img.data);

    GLint bound = 0, viewport[4] = {}, packAlignment = 0, unit3 = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    glGetIntegerv(GL_VIEWPORT, viewport);
    glGetIntegerv(GL_PACK_ALIGNMENT, &packAlignment);
    glActiveTexture(GL_TEXTURE3);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &unit3);
    glActiveTexture(GL_TEXTURE0);
    EXPECT_EQ(GLuint(bound), fbo);
    EXPECT_EQ(viewport[0], 1);
    EXPECT_EQ(viewport[3], 4);
    EXPECT_TRUE(glIsEnabled(GL_CULL_FACE));
    EXPECT_FALSE(glIsEnabled(GL_DEPTH_TEST));
    EXPECT_EQ(packAlignment, 2);
    EXPECT_EQ(GLuint(unit3), tex);

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glDisable(GL_CULL_FACE);
    glBindTextureUnit(3, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
}

// A chart (vtkContextView + vtkChartXY) renders through the same bridge and exports as SVG.
TEST_F(VizBridgeTest, RendersA2DChartAndExportsSvg) {
    VtkOffscreen out(320, 240);
    vtkNew<vtkContextView> view;
    out.attach(view);
    view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    vtkNew<vtkChartXY> chart;
    view->GetScene()->AddItem(chart);
    vtkNew<vtkTable> table;
    vtkNew<vtkFloatArray> x, y;
    x->SetName("time (ms)");
    y->SetName("RMSE");
    table->AddColumn(x);
    table->AddColumn(y);
    table->SetNumberOfRows(20);
    for (int i = 0; i < 20; ++i) {
        table->SetValue(i, 0, float(i));
        table->SetValue(i, 1, 1.0f / float(i + 1));
    }
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, 1);
    line->SetColor(255, 0, 0, 255);
    line->SetWidth(3.0f);
    chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (ms)");

    Image img = out.render();
    // White background, red line, dark axis text: at least the three colours appear.
    int red = 0, white = 0, dark = 0;
    for (size_t i = 0; i < img.pixelCount(); ++i) {
        float r = img.data[i * 4], g = img.data[i * 4 + 1], b = img.data[i * 4 + 2];
        if (r > 0.8f && g < 0.3f && b < 0.3f) ++red;
        if (r > 0.95f && g > 0.95f && b > 0.95f) ++white;
        if (r < 0.3f && g < 0.3f && b < 0.3f) ++dark;
    }
    EXPECT_GT(red, 100);
    EXPECT_GT(white, int(img.pixelCount() / 2));
    EXPECT_GT(dark, 50);

    fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / "viz-bridge";
    fs::create_directories(dir);
    fs::path svg = dir / "chart.svg";
    fs::remove(svg);
    out.exportVector(svg.string());
    std::ifstream in(svg);
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_NE(text.str().find("<svg"), std::string::npos);
    EXPECT_NE(text.str().find("stroke=\"#ff0000\""), std::string::npos) << "the red line is in the SVG";
    fs::path pdf = dir / "chart.pdf";
    fs::remove(pdf);
    out.exportVector(pdf.string());
    std::ifstream pdfIn(pdf, std::ios::binary);
    std::string magic(5, ' ');
    pdfIn.read(magic.data(), 5);
    EXPECT_EQ(magic, "%PDF-");
    writePNG((dir / "chart.png").string(), img);
    EXPECT_THROW(out.exportVector((dir / "chart.eps").string()), InputError);
}

// ---- views -------------------------------------------------------------------------------------------
// Pictures are checked for what must be in them (not against baselines: VTK's text rendering and
// llvmpipe's rasterisation may move pixels): a picture that is not uniform, colour bars (their end
// colours present at the expected side), markers in their colours.

// Pixels within `tolerance` (per channel) of `rgb` in the columns [x0, x1) (fractions of the width).
int countColour(const Image& img, glm::vec3 rgb, float tolerance, double x0 = 0.0, double x1 = 1.0) {
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = int(x0 * img.width); x < int(x1 * img.width); ++x) {
            glm::vec3 c(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
            if (glm::all(glm::lessThanEqual(glm::abs(c - rgb), glm::vec3(tolerance)))) ++n;
        }
    return n;
}

// Distinct colours (6 bits per channel).
size_t distinctColours(const Image& img) {
    std::set<int> colours;
    for (size_t i = 0; i < img.pixelCount(); ++i) {
        int r = int(img.data[i * 4] * 63.0f + 0.5f), g = int(img.data[i * 4 + 1] * 63.0f + 0.5f),
            b = int(img.data[i * 4 + 2] * 63.0f + 0.5f);
        colours.insert((r << 12) | (g << 6) | b);
    }
    return colours.size();
}

// The two ends of the sequential colour bar (viridis: dark purple and yellow) in columns [x0, x1).
void expectSequentialBar(const Image& img, double x0, double x1) {
    EXPECT_GT(countColour(img, {0.993f, 0.906f, 0.144f}, 0.06f, x0, x1), 20) << "yellow end of the colour bar";
    EXPECT_GT(countColour(img, {0.267f, 0.005f, 0.329f}, 0.06f, x0, x1), 20) << "purple end of the colour bar";
}

class VizViewTest : public VizBridgeTest {
protected:
    static RenderOptions options(const std::string& technique, std::vector<std::pair<std::string, std::string>> sets = {}) {
        RenderOptions o;
        o.width = 128;
        o.height = 96;
        o.technique = technique;
        o.sets = std::move(sets);
        return o;
    }
    // A pixel of square-occluder's penumbra at 128x96: visibility of the raytraced reference strictly
    // between 0.3 and 0.7 (found, not hard-coded, so a camera change does not silently move it).
    static glm::ivec2 penumbraPixel(const Scene& scene) {
        Renderer traced(scene, options("raytraced", {{"rays", "64"}}));
        traced.renderFrame(0, {"visibility"});
        Image v = traced.visibility();
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x)
                if (v.at(x, y) > 0.3f && v.at(x, y) < 0.7f) return {x, y};
        ADD_FAILURE() << "no penumbra pixel";
        return {0, 0};
    }
};

TEST_F(VizViewTest, ListsTheViewsWithTheirRules) {
    std::vector<std::string> names;
    for (const ViewInfo& v : listViews()) {
        names.push_back(v.name);
        EXPECT_FALSE(v.doc.empty());
        EXPECT_FALSE(v.appliesTo.empty());
        EXPECT_TRUE(v.exportExtension == ".vtp" || v.exportExtension == ".vti") << v.name;
    }
    EXPECT_EQ(names, (std::vector<std::string>{"scene3d", "shadow-map", "internal", "error", "kernel-size", "reuse", "backprojection", "hsm", "wedges", "penumbra-volumes", "pull-push", "skipped-pixels", "spsm-texels"}));
}

// scene3d: the rays from the picked point are the raytraced reference's samples, tested by an
// independent ray-triangle test: the free weight equals raytraced visibility with M = 64 rays.
// Tolerance: one ray's weight (1/64), for a ray grazing an occluder edge that Embree and the
// Moller-Trumbore test may decide differently; on this scene they agree exactly in practice.
TEST_F(VizViewTest, Scene3dRaysAgreeWithRaytracedAndExportLoadsBack) {
    Scene scene = loadScene("square-occluder");
    glm::ivec2 pixel = penumbraPixel(scene);
    Renderer traced(scene, options("raytraced", {{"rays", "64"}}));
    traced.renderFrame(0, {"visibility"});
    const float reference = traced.visibility().at(pixel.x, pixel.y);

    Renderer renderer(scene, options("pcf", {{"sm_size", "256"}}));
    ViewRequest request;
    request.view = "scene3d";
    request.pixel = pixel;
    request.rays = 64;
    request.width = 320;
    request.height = 240;
    request.exportPath = test::testPath("viz", "scene3d.vtp");
    ViewResult result = renderView(renderer, scene, request);
    writePNG(test::testPath("viz", "scene3d.png"), result.image);

    EXPECT_NEAR(result.data["free_weight"].get<double>(), reference, 1.0 / 64.0 + 1e-6);
    EXPECT_GT(result.data["blocked"].get<int>(), 0);
    EXPECT_LT(result.data["blocked"].get<int>(), 64);
    Image positions = renderer.positions();
    for (int c = 0; c < 3; ++c) EXPECT_EQ(result.data["point"][c].get<float>(), positions.at(pixel.x, pixel.y, c));
    // The picture: not uniform, blocked (red) and free (green) rays both drawn.
    EXPECT_GT(distinctColours(result.image), 50u);
    EXPECT_GT(countColour(result.image, {0.95f, 0.2f, 0.2f}, 0.12f), 10) << "blocked rays";
    EXPECT_GT(countColour(result.image, {0.35f, 0.95f, 0.45f}, 0.12f), 10) << "free rays";
    EXPECT_NE(result.caption.find("rays to L0 blocked"), std::string::npos);

    // The export: every scene triangle, 64 rays (part 5) and the picked point (part 4) at the G-buffer's position.
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(request.exportPath.c_str());
    reader->Update();
    vtkPolyData* data = reader->GetOutput();
    size_t triangles = 0;
    for (const Object& o : scene.objects) triangles += o.mesh.triangleCount();
    EXPECT_EQ(size_t(data->GetNumberOfPolys()), triangles);
    vtkDataArray* part = data->GetCellData()->GetArray("part");
    vtkDataArray* blocked = data->GetCellData()->GetArray("blocked");
    ASSERT_TRUE(part && blocked);
    int rays = 0, blockedRays = 0, pickedVertices = 0;
    for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) {
        if (part->GetTuple1(c) == 5) {
            ++rays;
            blockedRays += int(blocked->GetTuple1(c));
        }
        if (part->GetTuple1(c) == 4 && data->GetCellType(c) == VTK_VERTEX) {
            ++pickedVertices;
            double p[3];
            data->GetPoint(data->GetCell(c)->GetPointId(0), p);
            for (int k = 0; k < 3; ++k) EXPECT_EQ(float(p[k]), positions.at(pixel.x, pixel.y, k));
        }
    }
    EXPECT_EQ(rays, 64);
    EXPECT_EQ(blockedRays, result.data["blocked"].get<int>());
    EXPECT_EQ(pickedVertices, 1);
}

// shadow-map: the receiver's texel and the texels pcf read (n x n = 25 with pcf_kernel 5; one for
// hard) are marked, the colour bar is drawn, and the export is the map itself.
TEST_F(VizViewTest, ShadowMapMarksTheTexelsTheTechniqueReadAndExportsTheMap) {
    Scene scene = loadScene("square-occluder");
    glm::ivec2 pixel = penumbraPixel(scene);
    for (const std::string technique : {"pcf", "hard"}) {
        Renderer renderer(scene, options(technique, {{"sm_size", "256"}}));
        ViewRequest request;
        request.view = "shadow-map";
        request.pixel = pixel;
        request.exportPath = test::testPath("viz", "shadow-map-" + technique + ".vti");
        ViewResult result = renderView(renderer, scene, request);
        writePNG(test::testPath("viz", "shadow-map-" + technique + ".png"), result.image);
        EXPECT_EQ(result.data["texels_read_count"].get<int>(), technique == "pcf" ? 25 : 1) << technique;
        const auto& rect = result.data["texels_read"][0];
        const auto& texel = result.data["texel"];
        EXPECT_EQ(rect[2].get<int>() - rect[0].get<int>(), technique == "pcf" ? 4 : 0);
        EXPECT_EQ(rect[0].get<int>() + (technique == "pcf" ? 2 : 0), texel[0].get<int>()) << "kernel centred on the texel";
        EXPECT_GT(distinctColours(result.image), 30u);
        EXPECT_GT(countColour(result.image, {1.0f, 0.2f, 1.0f}, 0.1f), 20) << "the texel's marker (magenta)";
        if (technique == "pcf")  // (hard reads only the marked texel: its outline hides under the texel's)
            EXPECT_GT(countColour(result.image, {1.0f, 0.45f, 0.0f}, 0.1f), 20) << "the texels read (orange)";
        EXPECT_GT(countColour(result.image, {0.267f, 0.005f, 0.329f}, 0.06f, 0.62, 1.0), 20) << "the colour bar";

        vtkNew<vtkXMLImageDataReader> reader;
        reader->SetFileName(request.exportPath.c_str());
        reader->Update();
        vtkImageData* image = reader->GetOutput();
        EXPECT_EQ(image->GetNumberOfPoints(), 256 * 256);
        vtkDataArray* depth = image->GetPointData()->GetArray("depth");
        ASSERT_TRUE(depth);
        // The stored depth at the receiver's texel (the record's "stored_depth": null when no caster).
        double stored = depth->GetTuple1(vtkIdType(texel[1].get<int>()) * 256 + texel[0].get<int>());
        EXPECT_TRUE(std::isnan(stored) || stored > 0.0);
    }
}

TEST_F(VizViewTest, InternalViewShowsAnImageInternalWithItsDocAndRefusesOthers) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options("hard", {{"sm_size", "128"}}));
    ViewRequest request;
    request.view = "internal";
    request.exportPath = test::testPath("viz", "internal.vti");
    ViewResult result = renderView(renderer, scene, request);
    writePNG(test::testPath("viz", "internal.png"), result.image);
    EXPECT_NE(result.caption.find("light-view depth z of the nearest caster"), std::string::npos) << result.caption;
    EXPECT_GT(distinctColours(result.image), 20u);
    EXPECT_GT(countColour(result.image, {0.267f, 0.005f, 0.329f}, 0.06f, 0.8, 1.0), 20) << "the colour bar";
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(request.exportPath.c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 128 * 128);

    request.exportPath.clear();
    request.internal = "nope";
    try {
        renderView(renderer, scene, request);
        ADD_FAILURE() << "an unknown internal was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("expected one of: shadow_map"), std::string::npos) << e.what();
    }
    Renderer traced(scene, options("raytraced", {{"rays", "1"}}));
    request.internal.clear();
    EXPECT_NE(viewRefusal(traced, request).find("no image or pyramid internal"), std::string::npos);
    EXPECT_THROW(renderView(traced, scene, request), InputError);
}

// Pyramids as a stack: synthetic levels 32x32 .. 1x1 of a gradient (no technique exposes one yet).
TEST_F(VizViewTest, PyramidStackDrawsEveryLevelWithOneColourScale) {
    std::vector<Image> levels;
    for (int size = 32; size >= 1; size /= 2) {
        Image level(size, size, 1);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) level.at(x, y) = float(x + y) / float(2 * size) + float(levels.size());
        levels.push_back(level);
    }
    VtkOffscreen out(400, 300);
    auto [lo, hi] = addPyramidStack(out, levels, "min", "test pyramid", 0.0);
    EXPECT_FLOAT_EQ(lo, 0.0f);
    EXPECT_FLOAT_EQ(hi, 5.0f);  // the 1x1 level: 0 / 2 + 5
    Image img = out.render();
    writePNG(test::testPath("viz", "pyramid.png"), img);
    EXPECT_GT(distinctColours(img), 30u);
    // The bar takes the width its labels need at the standard's text size (style.h colourBarWidthPx):
    // about a fifth of this 400 px frame.
    expectSequentialBar(img, 0.75, 1.0);
    // The 1x1 top level (value 5: the yellow end) is a full square on the stack, left of the bar, and
    // level 0 (values 0..1: the purple-blue end) is drawn too.
    EXPECT_GT(countColour(img, {0.993f, 0.906f, 0.144f}, 0.06f, 0.0, 0.75), 200);
    EXPECT_GT(countColour(img, {0.275f, 0.194f, 0.496f}, 0.08f, 0.0, 0.75), 200);
}

// Without a given reference the error view renders `reference` in the renderer's state (here a
// moved light, set live): its metrics equal those against a `reference` renderer set up the same way.
TEST_F(VizViewTest, ErrorViewComputesTheReferenceInTheRenderersState) {
    Scene scene = loadScene("square-occluder");
    Light moved = scene.lights[0];
    moved.position += glm::vec3(0.3f, 0.0f, 0.0f);
    Renderer renderer(scene, options("pcf", {{"sm_size", "256"}}));
    renderer.setLight(0, moved);
    ViewRequest request;
    request.view = "error";
    request.referenceSamples = 16;
    ViewResult result = renderView(renderer, scene, request);
    writePNG(test::testPath("viz", "error.png"), result.image);

    // The reference is independent of the tested technique's parameters: its own defaults but samples.
    Renderer reference(scene, options("reference", {{"samples", "16"}}));
    reference.setLight(0, moved);
    reference.renderFrame(0, {"visibility"});
    Metrics expected = computeMetrics(renderer.visibility(), reference.visibility());
    EXPECT_EQ(result.data["all"]["rmse"].get<double>(), expected.rmse);
    EXPECT_EQ(result.data["all"]["pixels"].get<size_t>(), expected.pixels);
    EXPECT_GT(expected.rmse, 0.0);
    EXPECT_NE(result.caption.find("`reference` (16 light samples)"), std::string::npos) << result.caption;
    // Both colour bars: the diverging one (blue and red ends) left, the absolute error's inferno
    // (black and pale yellow ends, as compare --heatmap and the figures) right.
    EXPECT_GT(countColour(result.image, {0.230f, 0.299f, 0.754f}, 0.06f, 0.3, 0.5), 20);
    EXPECT_GT(countColour(result.image, {0.706f, 0.016f, 0.150f}, 0.06f, 0.3, 0.5), 20);
    EXPECT_GT(countColour(result.image, {0.988f, 0.998f, 0.645f}, 0.06f, 0.8, 1.0), 20) << "inferno's top";
}

// The window's use: views rendered between frames into one kept VtkOffscreen. The renderer's picture
// after a view is bit-identical to a fresh renderer's (VTK leaves no GL state the passes depend on),
// and the kept frame shows each view in turn.
TEST_F(VizViewTest, ViewsBetweenFramesLeaveTheRendererExactAndReuseOneFrame) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options("pcf", {{"sm_size", "256"}}));
    renderer.renderFrame(0, {"image", "visibility"});
    const Image before = renderer.image();
    VtkOffscreen out(64, 64);
    ViewRequest request;
    request.width = 320;
    request.height = 240;
    request.pixel = glm::ivec2(60, 40);
    std::vector<std::vector<float>> pictures;
    for (const std::string view : {"scene3d", "shadow-map", "internal", "scene3d"}) {
        request.view = view;
        ViewResult result = renderView(renderer, scene, request, out);
        EXPECT_EQ(out.width(), 320);
        pictures.push_back(result.image.data);
        renderer.invalidate();  // every pass runs again, after VTK touched the context
        renderer.renderFrame(0, {"image", "visibility"});
        EXPECT_EQ(renderer.image().data, before.data) << "after the " << view << " view";
    }
    EXPECT_NE(pictures[0], pictures[1]);
    EXPECT_NE(pictures[1], pictures[2]);
    EXPECT_EQ(pictures[0], pictures[3]) << "the same view twice in one frame gives the same picture";
    Renderer fresh(scene, options("pcf", {{"sm_size", "256"}}));
    fresh.renderFrame(0, {"image", "visibility"});
    EXPECT_EQ(fresh.image().data, before.data);
}

// ---- the command line --------------------------------------------------------------------------------
// The picked point of scene3d is the G-buffer position `render --positions` writes at that pixel.
TEST(VizCli, Scene3dPickedPointEqualsRenderPositions) {
    std::string positions = test::testPath("viz-cli", "p.pfm");
    auto r = test::run("render --scene square-occluder --technique hard --size 96x72 --positions " + positions);
    ASSERT_EQ(r.code, 0) << r.output;
    std::string png = test::testPath("viz-cli", "s.png");
    r = test::run("viz --view scene3d --scene square-occluder --technique hard --size 96x72 --pixel 50,40 --rays 8 "
                  "--view-size 320x240 --json --out " + png);
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
    Image p = readPFM(positions);
    ASSERT_TRUE(j["data"]["point"].is_array()) << r.output;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(j["data"]["point"][c].get<float>(), p.at(50, 40, c)) << c;
    EXPECT_TRUE(std::filesystem::exists(png));
}

// The error view's caption carries exactly the lines `shadowlab compare` prints for the same pair.
TEST(VizCli, ErrorCaptionEqualsCompare) {
    std::string v = test::testPath("viz-cli", "v.pfm"), ref = test::testPath("viz-cli", "ref.pfm");
    auto r = test::run("render --scene square-occluder --technique pcf --set sm_size=256 --size 96x72 --visibility " + v);
    ASSERT_EQ(r.code, 0) << r.output;
    r = test::run("reference --scene square-occluder --samples 16 --set sm_size=256 --size 96x72 --out " + ref);
    ASSERT_EQ(r.code, 0) << r.output;
    auto compare = test::run("compare " + v + " " + ref);
    ASSERT_EQ(compare.code, 0) << compare.output;
    std::string png = test::testPath("viz-cli", "error.png"), vti = test::testPath("viz-cli", "error.vti");
    auto viz = test::run("viz --view error --scene square-occluder --technique pcf --set sm_size=256 --size 96x72 "
                         "--reference " + ref + " --out " + png + " --export " + vti);
    ASSERT_EQ(viz.code, 0) << viz.output;
    std::istringstream lines(compare.output);
    std::string line;
    int matched = 0;
    while (std::getline(lines, line)) {
        if (line.empty()) continue;
        EXPECT_NE(viz.output.find(line), std::string::npos) << "compare: " << line << "\nviz: " << viz.output;
        ++matched;
    }
    EXPECT_EQ(matched, 2);  // "all" and "penumbra"
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(vti.c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 96 * 72);
    EXPECT_TRUE(reader->GetOutput()->GetPointData()->GetArray("signed_error"));
    EXPECT_TRUE(reader->GetOutput()->GetPointData()->GetArray("abs_error"));
}

// Views that do not apply, and bad requests: exit code 2 with the reason, and no output written.
TEST(VizCli, RefusalsExitTwoWithTheReasonAndWriteNothing) {
    std::string png = test::testPath("viz-cli", "refused.png");
    struct Case {
        std::string args, message;
    };
    const std::vector<Case> cases = {
        {"--view shadow-map --technique raytraced", "renders no light-view depth map"},
        {"--view internal --technique raytraced", "no image or pyramid internal"},
        {"--view internal --technique pcf --internal nope", "expected one of: shadow_map"},
        {"--view scene3d --technique pcf --size 64x48 --pixel 64,10", "inside the 64x48 image"},
        {"--view scene3d --technique pcf --export x.vti", "exports .vtp data"},
        {"--view nope", "unknown view 'nope'"},
        {"--view scene3d --reference x.pfm", "only the error view"},
        {"--view scene3d --light 3", "light index in 0..0"},
    };
    for (const Case& c : cases) {
        auto r = test::run("viz --scene square-occluder --out " + png + " " + c.args);
        EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_FALSE(std::filesystem::exists(png)) << c.args;
    }
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(png).parent_path()))
        EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST(VizCli, ListJsonNamesTheViews) {
    auto r = test::run("list --json");
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json j = nlohmann::json::parse(r.output);
    ASSERT_EQ(j["views"].size(), listViews().size());
    EXPECT_EQ(j["views"][0]["name"], "scene3d");
    EXPECT_EQ(j["views"][1]["export"], ".vti");
}

}  // namespace
}  // namespace shadowlab
