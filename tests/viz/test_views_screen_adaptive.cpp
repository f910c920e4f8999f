// The `skipped-pixels` and `pull-push` views (viz/view_screen_adaptive.cpp)
// of the screen-space multi-resolution (guennebaud2007 sec. 5.2, 6) on ssm-contour: they draw what
// they count. The skipped-pixels picture's legend colours cover the image panel in the proportions
// of the `selection` internal's codes, counted here from the internal itself; its caption's
// evaluated fraction is evaluated / (evaluated + skipped) of that internal; the pull-push view draws
// every level it lists and marks exactly the skipped pixels; both say what is missing (turn
// screen_adaptive on; no such internal) for ssm-contour with screen_adaptive=false and for hard,
// and apply to ssm-gbp06; the skipped-pixels export loads back with the same codes.
#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

#include <array>
#include <cmath>
#include <filesystem>

#include "error.h"
#include "graph/renderer.h"
#include "image/image.h"
#include "scene/scene.h"
#include "shared/shared.h"
#include "style.h"
#include "support/gl_fixture.h"
#include "view_common.h"
#include "views.h"

namespace fs = std::filesystem;

namespace shadowlab {
namespace {

class ScreenAdaptiveViews : public testing::GLTest {
protected:
    // square-occluder under a light of size 2: the floor's penumbra is wide on screen, so eq. 6
    // skips most of it (the pictures of viz/README.md use the same).
    static RenderOptions options(const std::string& technique, std::vector<std::pair<std::string, std::string>> sets = {}) {
        RenderOptions o;
        o.width = 256;
        o.height = 192;
        o.technique = technique;
        o.sets = std::move(sets);
        o.lightSize = 2.0f;
        return o;
    }
    static ViewRequest request(const std::string& view, int w = 640, int h = 480) {
        ViewRequest q;
        q.view = view;
        q.width = w;
        q.height = h;
        return q;
    }
    // The technique's own internal, collected as the views see it.
    static Image internalImage(Renderer& renderer, const std::string& name, int level = 0) {
        std::set<std::string> requested = renderer.internalRequests(false);
        requested.insert("visibility");
        renderer.renderFrame(0, requested);
        InternalCollector sink;
        renderer.writeInternals(sink, std::nullopt);
        auto it = sink.entries.find(name);
        EXPECT_TRUE(it != sink.entries.end()) << name;
        return it == sink.entries.end() ? Image() : it->second.levels.at(size_t(level));
    }
    static void savePng(const ViewResult& r, const std::string& name) {
        const fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / "views-screen-adaptive";
        fs::create_directories(dir);
        writePNG((dir / name).string(), r.image);
    }
};

bool near(const Image& img, int x, int y, glm::vec3 rgb, float tol = 0.02f) {
    return std::abs(img.at(x, y, 0) - rgb.r) < tol && std::abs(img.at(x, y, 1) - rgb.g) < tol &&
           std::abs(img.at(x, y, 2) - rgb.b) < tol;
}

// The selection's codes, counted here (not through the view's own counting).
std::array<size_t, 7> countCodes(const Image& selection) {
    std::array<size_t, 7> n{};
    for (size_t i = 0; i < selection.pixelCount(); ++i) ++n[size_t(std::lround(selection.data[i]))];
    return n;
}

TEST_F(ScreenAdaptiveViews, SkippedPixelsDrawsTheSelectionInItsLegendColoursAndCountsIt) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options("ssm-contour"));
    const Image selection = internalImage(renderer, "selection");
    ASSERT_EQ(selection.width, 256);
    const std::array<size_t, 7> n = countCodes(selection);
    EXPECT_EQ(selectionCounts(selection), n);
    const size_t evaluated = n[SEL_SELECTED] + n[SEL_FORCED] + n[SEL_BLOCK], skipped = n[SEL_SKIPPED];
    ASSERT_GT(skipped, 100u) << "the wide penumbra should be skipped in part";
    ASSERT_GT(evaluated, 100u);

    // At 1280x960 the frame's pixels are magnified ~3 times: no pixel of the dither is lost.
    ViewRequest q = request("skipped-pixels", 1280, 960);
    const fs::path exported = fs::path(SHADOWLAB_TEST_TMP) / "views-screen-adaptive" / "skipped-pixels.vti";
    fs::create_directories(exported.parent_path());
    q.exportPath = exported.string();
    ViewResult r = renderView(renderer, scene, q);
    savePng(r, "skipped-pixels.png");
    // The export loads back with the codes counted.
    {
        vtkNew<vtkXMLImageDataReader> reader;
        reader->SetFileName(exported.string().c_str());
        reader->Update();
        vtkDataArray* codes = reader->GetOutput()->GetPointData()->GetArray("code");
        ASSERT_TRUE(codes);
        std::array<size_t, 7> loaded{};
        for (vtkIdType i = 0; i < codes->GetNumberOfTuples(); ++i) ++loaded[size_t(std::lround(codes->GetTuple1(i)))];
        EXPECT_EQ(loaded, n);
    }
    const auto& d = r.data;
    EXPECT_EQ(d["evaluated"].get<size_t>(), evaluated);
    EXPECT_EQ(d["skipped"].get<size_t>(), skipped);
    const double fraction = double(evaluated) / double(evaluated + skipped);
    EXPECT_NEAR(d["evaluated_fraction"].get<double>(), fraction, 1e-12);
    // The caption prints the fraction (3 digits) and the counts.
    EXPECT_NE(r.caption.find("evaluated " + formatNumber(100.0 * fraction, 3) + "% of the penumbra"), std::string::npos)
        << r.caption;
    EXPECT_NE(r.caption.find(std::to_string(evaluated) + " of " + std::to_string(evaluated + skipped)), std::string::npos);
    EXPECT_NE(r.caption.find("skipped " + std::to_string(skipped)), std::string::npos);

    // The picture, pixel by pixel: the centre of each frame pixel's square in the picture has its
    // code's legend colour (the block outlines may cover a few).
    std::vector<glm::vec3> colours(7);
    for (const auto& e : d["legend"]) {
        const int code = e["code"].get<int>();
        colours[size_t(code)] = glm::vec3(e["rgb"][0].get<float>(), e["rgb"][1].get<float>(), e["rgb"][2].get<float>());
        EXPECT_EQ(e["count"].get<size_t>(), n[size_t(code)]);
    }
    const auto& rect = d["image_rect"];
    const double x0 = rect[0].get<double>(), y0 = rect[1].get<double>(), x1 = rect[2].get<double>(), y1 = rect[3].get<double>();
    EXPECT_GT((x1 - x0) / selection.width, 2.5) << "magnified: every pixel drawn";
    EXPECT_NEAR((x1 - x0) / selection.width, (y1 - y0) / selection.height, 1e-6) << "square pixels";
    size_t wrong = 0;
    for (int y = 0; y < selection.height; ++y)
        for (int x = 0; x < selection.width; ++x) {
            const int px = int(x0 + (x + 0.5) * (x1 - x0) / selection.width), py = int(y0 + (y + 0.5) * (y1 - y0) / selection.height);
            if (!near(r.image, px, py, colours[size_t(std::lround(selection.at(x, y)))])) ++wrong;
        }
    const size_t outlined = d["blocks"]["whole"].get<size_t>() * 4 * BP_BLOCK;
    EXPECT_LE(wrong, outlined + selection.pixelCount() / 1000) << wrong << " pixels drawn in another class's colour";
    // And over the frame's rectangle, each colour's share of the picture is its code's share of the
    // frame, to the rounding of the magnified squares (3 or 4 picture pixels across).
    std::array<size_t, 7> drawn{};
    size_t total = 0;
    for (int y = int(std::ceil(y0)); y < int(y1); ++y)
        for (int x = int(std::ceil(x0)); x < int(x1); ++x)
            for (int c = 0; c < 7; ++c)
                if (near(r.image, x, y, colours[size_t(c)])) {
                    ++drawn[size_t(c)];
                    ++total;
                    break;
                }
    ASSERT_GT(total, 10000u);
    const double frame = double(selection.pixelCount());
    for (int c = 0; c < 7; ++c) {
        SCOPED_TRACE("code " + std::to_string(c));
        EXPECT_NEAR(double(drawn[size_t(c)]) / double(total), double(n[size_t(c)]) / frame, 0.01);
    }
}

TEST_F(ScreenAdaptiveViews, PullPushDrawsEveryLevelItListsAndMarksTheSkippedPixels) {
    Scene scene = loadScene("square-occluder");
    Renderer renderer(scene, options("ssm-contour"));
    const Image selection = internalImage(renderer, "selection");
    const Image sparse = internalImage(renderer, "visibility_sparse");
    size_t skippedW = 0;
    for (size_t i = 0; i < sparse.pixelCount(); ++i)
        if (!(sparse.data[i * 2 + 1] > 0.0f) && selection.data[i] != SEL_BACKGROUND) ++skippedW;
    EXPECT_EQ(skippedW, countCodes(selection)[SEL_SKIPPED]) << "the weight 0 pixels are the skipped ones";

    for (glm::ivec2 size : {glm::ivec2(640, 480), glm::ivec2(480, 360)}) {
        ViewResult r = renderView(renderer, scene, request("pull-push", size.x, size.y));
        savePng(r, "pull-push-" + std::to_string(size.x) + ".png");
        EXPECT_EQ(r.data["skipped"].get<size_t>(), skippedW);
        // 256x192: levels 0 (256x192), 1 (128x96) ... 8 (1x1): nine, of which 0-3 and 8 are drawn.
        EXPECT_EQ(r.data["levels"].get<int>(), 9);
        EXPECT_EQ(r.data["levels_shown"], nlohmann::json({0, 1, 2, 3, 8}));
        EXPECT_NE(r.caption.find("levels 4..7 not shown"), std::string::npos) << r.caption;
        // Ten tiles labelled: two group titles and five columns in each.
        EXPECT_EQ(r.data["labels"].size(), 12u);
        // Orange (weight 0) pixels on the picture: the skipped ones, magnified.
        const glm::vec3 orange(1.0f, 0.55f, 0.0f);
        size_t marked = 0;
        for (int y = 0; y < r.image.height; ++y)
            for (int x = 0; x < r.image.width; ++x)
                if (near(r.image, x, y, orange)) ++marked;
        const double tileW = r.data["tile_px"][0].get<double>(), tileH = r.data["tile_px"][1].get<double>();
        // Level 0's skipped pixels and the empty texels (weight 0) of the pull levels drawn, each
        // magnified to its tile (the push has none: it fills every texel).
        double expected = 0.0;
        for (const auto& k : r.data["levels_shown"]) {
            const auto& level = r.data["levels_data"][k.get<size_t>()];
            const double texels = level["size"][0].get<double>() * level["size"][1].get<double>();
            EXPECT_EQ(level["size"][0].get<int>(), k.get<int>() == 0 ? 256 : std::max(1, 128 >> (k.get<int>() - 1)));
            const size_t zero = k.get<int>() == 0 ? level["skipped"].get<size_t>() : level["weight_zero"].get<size_t>();
            expected += double(zero) * tileW * tileH / texels;
        }
        const double swatch = std::pow(textPx(size.y), 2);
        EXPECT_GT(double(marked), 0.85 * expected) << marked << " orange pixels, " << expected << " expected";
        EXPECT_LT(double(marked), 1.15 * expected + swatch) << marked << " orange pixels, " << expected << " expected";
        // Not blank: many colours.
        std::set<int> shades;
        for (size_t i = 0; i < r.image.pixelCount(); i += 7) shades.insert(int(r.image.data[i * 4] * 31.0f) * 32 + int(r.image.data[i * 4 + 1] * 31.0f));
        EXPECT_GT(shades.size(), 30u);
    }
}

TEST_F(ScreenAdaptiveViews, SayWhatIsMissingWithoutTheScreenSpaceMultiResolution) {
    Scene scene = loadScene("square-occluder");
    Renderer off(scene, options("ssm-contour", {{"screen_adaptive", "false"}}));
    Renderer hard(scene, options("hard"));
    Renderer gbp06(scene, options("ssm-gbp06"));
    for (const std::string view : {"skipped-pixels", "pull-push"}) {
        SCOPED_TRACE(view);
        const std::string why = viewRefusal(off, request(view));
        EXPECT_NE(why.find("turn screen_adaptive on"), std::string::npos) << why;
        EXPECT_NE(why.find("ssm-contour"), std::string::npos) << why;
        EXPECT_THROW(renderView(off, scene, request(view)), InputError);
        const std::string hardWhy = viewRefusal(hard, request(view));
        EXPECT_NE(hardWhy.find("technique hard computes every pixel's visibility"), std::string::npos) << hardWhy;
        EXPECT_THROW(renderView(hard, scene, request(view)), InputError);
        // ssm-gbp06 shares the screen-space multi-resolution: both views apply and draw.
        EXPECT_EQ(viewRefusal(gbp06, request(view)), "");
        EXPECT_FALSE(renderView(gbp06, scene, request(view, 480, 360)).caption.empty());
    }
}

}  // namespace
}  // namespace shadowlab
