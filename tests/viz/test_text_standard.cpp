// The text and layout standard (issue 19, viz/README.md "Text and colour"): every view and the
// accuracy-time chart at 640x480 and 1280x960, checked from the measured boxes of every text they
// draw (viz/style.h textLayout): no two texts overlap, every text lies inside the picture and its
// panel, and no text is smaller than the standard (14 px, 1/30 of the picture's height). The boxes
// are checked against the picture too: each holds pixels of its text's colour, so a record that
// drifted from what was drawn fails. Colour bars keep their ticks apart on narrow and short panels
// and on the ranges that used to collide; palettes never reach the background grey.
#include <gtest/gtest.h>

#include <vtkLookupTable.h>
#include <vtkRenderer.h>

#include <filesystem>
#include <glm/glm.hpp>

#include "chart_accuracy_time.h"
#include "graph/renderer.h"
#include "image/palette.h"
#include "scene/scene.h"
#include "style.h"
#include "support/cli_run.h"
#include "support/gl_fixture.h"
#include "view_common.h"
#include "views.h"
#include "vtk_offscreen.h"

namespace fs = std::filesystem;

namespace shadowlab {
namespace {

using testing::GLTest;

// Text pixels inside a box: texts are light (0.95 grey) or saturated (a step's red number) on dark
// panels, so some channel above 0.8.
int brightPixels(const Image& img, const TextBox& b) {
    int n = 0;
    for (int y = std::max(0, b.y0); y < std::min(img.height, b.y1); ++y)
        for (int x = std::max(0, b.x0); x < std::min(img.width, b.x1); ++x)
            if (std::max({img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)}) > 0.8f) ++n;
    return n;
}

std::string describe(const std::vector<TextBox>& boxes) {
    std::string s;
    for (const TextBox& b : boxes)
        s += "  [" + std::to_string(b.x0) + "," + std::to_string(b.y0) + " - " + std::to_string(b.x1) + "," +
             std::to_string(b.y1) + "] " + std::to_string(b.fontPx) + "px '" + b.text.substr(0, 50) + "'\n";
    return s;
}

class TextStandard : public GLTest {
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

    static RenderOptions options(const std::string& technique) {
        RenderOptions o;
        o.width = 128;
        o.height = 96;
        o.technique = technique;
        return o;
    }
    // A penumbra pixel of the technique's own visibility (found, not hard-coded); for a hard shadow
    // (no penumbra) a shadowed pixel.
    static glm::ivec2 penumbraPixel(Renderer& r) {
        r.renderFrame(0, {"visibility"});
        Image v = r.visibility();
        for (float lo : {0.2f, 0.0f})
            for (int y = 0; y < v.height; ++y)
                for (int x = 0; x < v.width; ++x)
                    if (v.at(x, y) >= lo && v.at(x, y) < 0.8f) return {x, y};
        ADD_FAILURE() << "no shadowed pixel";
        return {0, 0};
    }
    void checkLayout(const ViewResult& result, int w, int h, const std::string& what) {
        SCOPED_TRACE(what + " at " + std::to_string(w) + "x" + std::to_string(h));
        ASSERT_FALSE(result.texts.empty());
        const std::string problems = layoutProblems(result.texts, w, h);
        EXPECT_TRUE(problems.empty()) << problems << "texts:\n" << describe(result.texts);
        for (const TextBox& b : result.texts) {
            EXPECT_GE(b.y1 - b.y0, int(0.7 * textPx(h))) << "a text lower than its font: '" << b.text << "'";
            EXPECT_GT(brightPixels(result.image, b), 0) << "no text drawn in the box of '" << b.text << "'";
        }
    }
};

// Every view at the lessons' smallest size (480x360: the handouts' and the window's view cells),
// the default 640x480 and twice it.
struct ViewCase {
    std::string view, technique;
    bool pixel;
};

TEST_F(TextStandard, EveryViewAtTwoSizesKeepsTheTextStandard) {
    Scene scene = loadScene("square-occluder");
    const std::vector<ViewCase> cases = {
        {"scene3d", "pcf", true},       {"shadow-map", "hard", false},    {"shadow-map", "hard", true},
        {"internal", "pcss", false},    {"error", "pcf", false},          {"kernel-size", "pcss", false},
        {"reuse", "sssm", false},       {"backprojection", "ssm-contour", true},
        {"backprojection", "ssm-gbp06", true}, {"hsm", "ssm-contour", true},
        {"backprojection", "ssv", true},       {"wedges", "ssv", false},        {"wedges", "ssv", true},
        {"penumbra-volumes", "pvm", true}, {"penumbra-volumes", "pvmf", true}, {"penumbra-volumes", "pvmf", false},
        {"skipped-pixels", "ssm-contour", false}, {"pull-push", "ssm-contour", false},
        {"spsm-texels", "spsm", true},
    };
    std::set<std::string> covered;
    for (const ViewCase& c : cases) {
        SCOPED_TRACE(c.view + " of " + c.technique);
        Renderer renderer(scene, options(c.technique));
        ViewRequest request;
        request.view = c.view;
        if (c.pixel) request.pixel = penumbraPixel(renderer);
        request.referenceSamples = 16;
        request.rays = 16;
        for (glm::ivec2 size : {glm::ivec2(480, 360), glm::ivec2(640, 480), glm::ivec2(1280, 960)}) {
            request.width = size.x;
            request.height = size.y;
            ViewResult result = renderView(renderer, scene, request);
            checkLayout(result, size.x, size.y, c.view + " of " + c.technique + (c.pixel ? " with a pixel" : ""));
            if (::testing::Test::HasFailure()) {
                const fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / "text-standard";
                fs::create_directories(dir);
                writePNG((dir / (c.view + "-" + c.technique + "-" + std::to_string(size.x) + ".png")).string(), result.image);
            }
        }
        covered.insert(c.view);
    }
    for (const ViewInfo& v : listViews()) EXPECT_TRUE(covered.count(v.name)) << "view " << v.name << " is not checked";
}

// The window's cells (~250 x 200 px at 1024x768, ~450 x 350 at 1920x1080) ask for a caption of at most 40% of the picture
// (ViewRequest::captionMaxShare): a longer one keeps its first lines and ends with
// kCaptionContinues, the whole caption staying in ViewResult::caption (the cell's tooltip). At the
// default (0.9, headless) the same caption is drawn whole and takes more than 40%: the cut was
// needed, and only the window asks for it.
TEST_F(TextStandard, WindowCellsCutALongCaptionToItsFirstLines) {
    Scene scene = loadScene("square-occluder");
    for (const std::string view : {"skipped-pixels", "error", "pull-push"}) {
        SCOPED_TRACE(view);
        Renderer renderer(scene, options("ssm-contour"));
        ViewRequest request;
        request.view = view;
        request.referenceSamples = 16;
        request.width = 320;
        request.height = 240;
        // The caption is the text lowest in the picture (its strip runs along the bottom).
        auto captionBox = [](const ViewResult& r) {
            TextBox lowest = r.texts.front();
            for (const TextBox& b : r.texts)
                if (b.y1 > lowest.y1) lowest = b;
            return lowest;
        };
        ViewResult whole = renderView(renderer, scene, request);
        ASSERT_FALSE(whole.texts.empty());
        const TextBox wholeBox = captionBox(whole);
        EXPECT_EQ(wholeBox.text.find(kCaptionContinues), std::string::npos) << describe(whole.texts);
        EXPECT_LT(wholeBox.y0, int(0.6 * request.height)) << "the caption fits in 40% anyway: the test shows nothing\n"
                                                       << describe(whole.texts);
        request.captionMaxShare = 0.4f;
        ViewResult cell = renderView(renderer, scene, request);
        // The tooltip's caption is the whole caption (skipped-pixels' last line gives the share of its
        // pixels drawn, which grows with the picture's room: compared up to it).
        const std::string shown = "\nshown at ";
        EXPECT_EQ(cell.caption.substr(0, cell.caption.find(shown)), whole.caption.substr(0, whole.caption.find(shown)));
        ASSERT_FALSE(cell.texts.empty());
        const TextBox cellBox = captionBox(cell);
        EXPECT_NE(cellBox.text.find(kCaptionContinues), std::string::npos) << describe(cell.texts);
        EXPECT_GE(cellBox.y0, int(0.6 * request.height) - 1) << describe(cell.texts);
        // The kept lines are the caption's first ones (the wrapping joins its double spaces).
        const std::string firstWord = cell.caption.substr(0, cell.caption.find(' '));
        EXPECT_EQ(cellBox.text.rfind(firstWord, 0), 0u) << cellBox.text;
        // The whole layout too (skipped-pixels' legend then lists only the classes present), except
        // pull-push's: at a cell's size its two colour bars are too short for two ticks each (noted
        // on issue 20).
        if (view != "pull-push") checkLayout(cell, request.width, request.height, view + " in a window cell");
    }
}

// Colour bars on panels of several shapes, with the ranges whose labels used to collide
// ("1.98.99 2.00 .01 2.02") and a long title: no overlap, nothing outside, ticks >= 2.
TEST_F(TextStandard, ColourBarsLayTheirLabelsOutFromTheirMeasuredBoxes) {
    struct Case {
        double lo, hi;
        std::string title;
        double width;  // of the frame
        double height;
        bool horizontal;
    };
    const std::vector<Case> cases = {
        {1.98, 2.02, "light-view depth z", 0.2, 1.0, false},
        {-0.0975, 0.0975, "signed error v - v_ref", 0.15, 0.6, false},
        {0.0, 123456.0, "a long colour bar title that has to wrap onto several lines", 0.25, 1.0, false},
        {0.0, 1.0, "reused", 0.12, 0.35, false},
        {0.31, 0.99, "light-view depth z", 0.4, 0.25, true},
    };
    for (int frameH : {480, 960}) {
        const int frameW = frameH * 4 / 3;
        for (const Case& c : cases) {
            VtkOffscreen out(frameW, frameH);
            vtkRenderer* r = out.addRenderer();
            auto lut = paletteLut(Palette::Depth, c.lo, c.hi);
            // A viewport at least as wide as the bar asks for (what addImagePanelWithBar gives).
            const double need = double(colourBarWidthPx(lut, c.title, frameH)) / frameW;
            r->SetViewport(0.0, 0.0, c.horizontal ? c.width : std::max(c.width, need), c.height);
            r->SetBackground(0.12, 0.12, 0.14);
            addColourBar(r, lut, c.title, frameH, c.horizontal);
            Image img = out.render();
            std::vector<TextBox> boxes = textLayout(out);
            SCOPED_TRACE(c.title + " [" + std::to_string(c.lo) + ", " + std::to_string(c.hi) + "] at " +
                         std::to_string(frameH));
            EXPECT_GE(boxes.size(), 4u) << "title, two ticks at least, 'no data'";
            const std::string problems = layoutProblems(boxes, frameW, frameH);
            EXPECT_TRUE(problems.empty()) << problems << describe(boxes);
            for (const TextBox& b : boxes) EXPECT_GT(brightPixels(img, b), 0) << b.text;
        }
    }
}

TEST_F(TextStandard, TheAccuracyTimeChartKeepsTheStandardAndLeavesNoLabelOverAnother) {
    std::vector<AccuracyTimePoint> points;
    // Settings close together in time and error (labels compete for room), over two decades.
    for (int n : {3, 5, 7, 9, 11, 13, 15}) points.push_back({"pcf", "k=" + std::to_string(n), 2.0 + 0.3 * n, 0.05 / n, false});
    for (int n : {9, 17, 29}) points.push_back({"pcss", "n=" + std::to_string(n), 10.0 + n, 0.02 / n, n == 17});
    points.push_back({"reference", "N=64", 120.0, 0.0, false});
    points.push_back({"hard", "", 1.1, 0.09, false});
    const fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / "text-standard";
    fs::create_directories(dir);
    for (glm::ivec2 size : {glm::ivec2(640, 480), glm::ivec2(1280, 960)}) {
        std::vector<TextBox> boxes;
        std::string problems;
        int hidden = 0;
        AccuracyTimeStyle style;
        style.record = &boxes;
        style.problems = &problems;
        style.hiddenLabels = &hidden;
        const std::string path = (dir / ("chart-" + std::to_string(size.x) + ".png")).string();
        writeAccuracyTimeChart({{"square-occluder", points}}, style, size.x, size.y, path, ".png");
        SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y));
        EXPECT_TRUE(problems.empty()) << problems;
        const std::string overlaps = layoutProblems(boxes, size.x, size.y);
        EXPECT_TRUE(overlaps.empty()) << overlaps << describe(boxes);
        // Most labels find a place; the legend has an entry per technique.
        EXPECT_LE(hidden, 4);
        int legend = 0;
        for (const TextBox& b : boxes) legend += (b.text == "pcf" || b.text == "pcss" || b.text == "reference");
        EXPECT_EQ(legend, 3) << describe(boxes);
    }
}

// A colour bar's ticks never print the same number twice: the hsm view's depth bar over
// 1.99 .. 2.01 (a plate seen from a light 2 units away) read "2.01, 2, 2, 1.99, 1.99" with three
// significant digits everywhere. Wide ranges keep three digits.
TEST(ColourBarTicks, NeighbouringTicksNeverPrintAlike) {
    EXPECT_EQ(colourBarTickLabels(0.0, 1.0, 5), (std::vector<std::string>{"0", "0.25", "0.5", "0.75", "1"}));
    EXPECT_EQ(colourBarTickLabels(-0.999, 0.999, 3), (std::vector<std::string>{"-0.999", "0", "0.999"}));
    EXPECT_EQ(colourBarTickLabels(100.0, 2000.0, 2), (std::vector<std::string>{"100", "2e+03"}));
    for (double lo : {1.99, 2.0, 1234.5, -3.0, 1e-6})
        for (double width : {0.02, 0.001, 1e-5})
            for (int n = 2; n <= 5; ++n) {
                const std::vector<std::string> labels = colourBarTickLabels(lo, lo + width * std::max(1.0, std::abs(lo)), n);
                ASSERT_EQ(labels.size(), size_t(n));
                for (int i = 1; i < n; ++i)
                    EXPECT_NE(labels[size_t(i)], labels[size_t(i) - 1]) << "range " << lo << " + " << width << ", " << n << " ticks";
            }
    const std::vector<std::string> depth = colourBarTickLabels(1.99, 2.01, 5);
    EXPECT_EQ(depth, (std::vector<std::string>{"1.99", "1.995", "2", "2.005", "2.01"}));
}

TEST(Palettes, NeverReachTheBackgroundGreyAndAreOrderedInLightness) {
    for (Palette p : {Palette::Visibility, Palette::SignedError, Palette::AbsoluteError, Palette::Depth, Palette::KernelSize}) {
        float nearest = 1.0f;
        for (int i = 0; i <= 1000; ++i) {
            glm::vec3 c = paletteColour(p, float(i) / 1000.0f);
            glm::vec3 d = glm::abs(c - kBackgroundGrey);
            nearest = std::min(nearest, std::max({d.r, d.g, d.b}));
        }
        EXPECT_GE(nearest, 0.1f) << paletteName(p);
        if (p != Palette::SignedError) {
            // Sequential palettes: luminance grows with t (readable in greyscale print).
            auto lum = [&](float t) { glm::vec3 c = paletteColour(p, t); return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
            for (int i = 0; i < 20; ++i) EXPECT_LT(lum(i / 20.0f), lum((i + 1) / 20.0f) + 1e-3f) << paletteName(p) << " at " << i;
        }
    }
    EXPECT_EQ(paletteColour(Palette::Depth, NAN), kBackgroundGrey);
}

}  // namespace
}  // namespace shadowlab
