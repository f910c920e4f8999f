// The `kernel-size` and `reuse` views (viz/view_kernel_size.cpp, viz/view_reuse.cpp) on pcss and
// sssm: they read the techniques' internals, their numbers agree with those internals as
// --internals writes them, and techniques without the data are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "error.h"
#include "graph/renderer.h"
#include "scene/scene.h"
#include "support/gl_fixture.h"
#include "views.h"
#include "vtk_offscreen.h"

namespace shadowlab {
namespace {

class KernelReuseViews : public testing::GLTest {
protected:
    static RenderOptions options(const std::string& technique, std::vector<std::pair<std::string, std::string>> sets) {
        RenderOptions o;
        o.width = 96;
        o.height = 96;
        o.technique = technique;
        o.sets = std::move(sets);
        return o;
    }
};

// kernel-size on pcss (texels, one channel) and sssm (pixels, x and y): square-occluder's floor
// penumbra is 1 world unit wide, so the kernels are well above 1 and within the cap m = 41.
TEST_F(KernelReuseViews, KernelSizeShowsEveryTechniquesKernel) {
    Scene scene = loadScene("square-occluder");
    for (const std::string technique : {"pcss", "sssm"}) {
        Renderer renderer(scene, options(technique, {{"sm_size", "256"}}));
        ViewRequest request;
        request.view = "kernel-size";
        request.width = 480;
        request.height = 240;
        EXPECT_EQ(viewRefusal(renderer, request), "") << technique;
        ViewResult result = renderView(renderer, scene, request);
        const auto& channels = result.data["channels"];
        ASSERT_EQ(channels.size(), technique == "pcss" ? 1u : 2u) << result.data.dump();
        for (const auto& c : channels) {
            EXPECT_GT(c["filtered_pixels"].get<int>(), 100) << technique;
            EXPECT_GT(c["mean"].get<double>(), 4.0) << technique;
            EXPECT_LE(c["max"].get<double>(), 41.0) << technique;
        }
        EXPECT_NE(result.caption.find("kernel"), std::string::npos);
        EXPECT_EQ(result.image.width, 480);
    }
}

// reuse on sssm: the percentages are the mean of the reuse maps over the pixels where each step ran
// (computed here from the renderer's own internals); alpha = beta = 0 reuses nothing.
TEST_F(KernelReuseViews, ReuseGivesTheSharePerStep) {
    Scene scene = loadScene("square-occluder");
    for (const char* ab : {"0.1", "0"}) {
        Renderer renderer(scene, options("sssm", {{"sm_size", "256"}, {"alpha", ab}, {"beta", ab}}));
        ViewRequest request;
        request.view = "reuse";
        ViewResult result = renderView(renderer, scene, request);
        const auto& maps = result.data["maps"];
        ASSERT_EQ(maps.size(), 2u);
        for (const auto& m : maps) {
            EXPECT_GT(m["pixels"].get<int>(), 100);
            if (std::string(ab) == "0")
                EXPECT_EQ(m["percent"].get<double>(), 0.0) << m.dump();
            else
                EXPECT_GT(m["percent"].get<double>(), 90.0) << m.dump();  // a plane: every row reusable
        }
        EXPECT_NE(result.caption.find("% of rows reused"), std::string::npos);
    }
}

TEST_F(KernelReuseViews, TechniquesWithoutTheDataAreRefused) {
    Scene scene = loadScene("square-occluder");
    Renderer hard(scene, options("hard", {}));
    Renderer pcss(scene, options("pcss", {}));
    ViewRequest kernel;
    kernel.view = "kernel-size";
    EXPECT_NE(viewRefusal(hard, kernel).find("exposes no kernel size"), std::string::npos);
    EXPECT_THROW(renderView(hard, scene, kernel), InputError);
    ViewRequest reuse;
    reuse.view = "reuse";
    EXPECT_NE(viewRefusal(pcss, reuse).find("no reuse maps"), std::string::npos);
    EXPECT_THROW(renderView(pcss, scene, reuse), InputError);
}

}  // namespace
}  // namespace shadowlab
