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
#include <sstream>

#include "error.h"
#include "gl_fixture.h"
#include "gl_loader.h"
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

}  // namespace
}  // namespace shadowlab
