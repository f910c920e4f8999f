// The `kernel-size` and `reuse` views (viz/view_kernel_reuse.cpp) on pcss and
// sssm: their numbers are those of the techniques' own resources (pcss_blockers' kernel channel,
// sssm's kernel_size and reuse_step2/3, read back here from the renderer's pool and averaged the
// way each view's caption says), and techniques without the data are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "error.h"
#include "gl/util.h"
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

// The mean and largest of one channel of a technique's resource over the geometry pixels where
// it exceeds `above` (NaN and background left out), as a view's caption reports them.
struct ChannelStats {
    double mean = 0.0, largest = 0.0;
    size_t pixels = 0;
};
ChannelStats resourceStats(const Renderer& renderer, const std::string& name, int channels, int channel, float above) {
    const Resource* r = renderer.pool().find("L0/" + name);
    EXPECT_TRUE(r) << name;
    ChannelStats s;
    if (!r) return s;
    const Image image = readTexture(r->texture, channels);
    const Image ids = renderer.ids();
    double sum = 0.0;
    for (size_t i = 0; i < image.pixelCount(); ++i) {
        const float v = image.data[i * size_t(channels) + size_t(channel)];
        if (ids.data[i] < 0.0f || !std::isfinite(v) || v <= above) continue;
        sum += v;
        s.largest = std::max(s.largest, double(v));
        ++s.pixels;
    }
    s.mean = s.pixels ? sum / double(s.pixels) : 0.0;
    return s;
}

// kernel-size on pcss (texels, one channel) and sssm (pixels, x and y): the view's mean, max and
// pixel count are those of the technique's kernel resource over the pixels whose kernel is wider
// than one (to float rounding of the sum). square-occluder's floor penumbra is 1 world unit wide,
// so the kernels are well above 1 and within the cap m.
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
        const double cap = renderer.lights().at(0)->params.getInt("filter_kernel");
        for (size_t k = 0; k < channels.size(); ++k) {
            const auto& c = channels[k];
            const ChannelStats own = technique == "pcss" ? resourceStats(renderer, "pcss_blockers", 4, 3, 1.0f)
                                                         : resourceStats(renderer, "kernel_size", 2, int(k), 1.0f);
            SCOPED_TRACE(technique + " channel " + std::to_string(k));
            EXPECT_GT(own.pixels, 100u);
            EXPECT_EQ(c["filtered_pixels"].get<size_t>(), own.pixels);
            EXPECT_NEAR(c["mean"].get<double>(), own.mean, 1e-4 * own.mean);
            EXPECT_EQ(c["max"].get<double>(), own.largest);
            EXPECT_GT(own.mean, 4.0);
            EXPECT_LE(own.largest, cap);
        }
        EXPECT_NE(result.caption.find("kernel"), std::string::npos);
        EXPECT_EQ(result.image.width, 480);
    }
}

// reuse on sssm: each step's percentage is the mean of its reuse map (reuse_step2, reuse_step3,
// the fraction of rows reused per pixel) over the pixels where the step ran (map >= 0), computed
// here from the technique's resources; on the plane at 0.10 nearly every row is reused, at
// alpha = beta = 0 none is.
TEST_F(KernelReuseViews, ReuseGivesTheSharePerStep) {
    Scene scene = loadScene("square-occluder");
    for (const char* ab : {"0.1", "0"}) {
        Renderer renderer(scene, options("sssm", {{"sm_size", "256"}, {"alpha", ab}, {"beta", ab}}));
        ViewRequest request;
        request.view = "reuse";
        ViewResult result = renderView(renderer, scene, request);
        const auto& maps = result.data["maps"];
        ASSERT_EQ(maps.size(), 2u);
        const char* names[2] = {"reuse_step2", "reuse_step3"};
        for (size_t k = 0; k < 2; ++k) {
            const auto& m = maps[k];
            SCOPED_TRACE(std::string(names[k]) + " at " + ab);
            EXPECT_EQ(m["internal"].get<std::string>(), names[k]);
            // Where the step ran: >= 0 (-1 marks "did not run"); a reuse of 0 counts.
            const ChannelStats own = resourceStats(renderer, names[k], 1, 0, -0.5f);
            EXPECT_GT(own.pixels, 100u);
            EXPECT_EQ(m["pixels"].get<size_t>(), own.pixels);
            EXPECT_NEAR(m["percent"].get<double>(), 100.0 * own.mean, 1e-3);
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
