// Error metrics and the error heat map (techniques/core/image/metrics.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "error.h"
#include "image/metrics.h"

using namespace shadowlab;

namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

// A smooth visibility-like pattern with a soft edge, so SSIM has structure to compare.
Image pattern(int w, int h) {
    Image image(w, h, 1);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            float edge = std::clamp((float(x) - 0.4f * w) / (0.2f * w), 0.0f, 1.0f);
            image.at(x, y) = 0.2f + 0.6f * edge * (0.75f + 0.25f * std::sin(0.3f * y));
        }
    }
    return image;
}

Image withNoise(const Image& image, float amplitude, unsigned seed) {
    std::mt19937 rng(seed);
    Image noisy = image;
    for (float& v : noisy.data) {
        // Uniform in [-amplitude, amplitude] from raw 32-bit words: identical on every platform.
        v += amplitude * (float(rng()) / 4294967296.0f * 2.0f - 1.0f);
    }
    return noisy;
}

}  // namespace

TEST(Metrics, IdenticalImagesHaveNoError) {
    Image a = pattern(40, 30);
    Metrics m = computeMetrics(a, a);
    EXPECT_EQ(m.rmse, 0.0);
    EXPECT_EQ(m.maxAbs, 0.0);
    EXPECT_TRUE(std::isinf(m.psnr) && m.psnr > 0);
    EXPECT_EQ(m.ssim, 1.0);
    EXPECT_EQ(m.pixels, 40u * 30u);
}

// Offsets exactly representable in binary, so the expected values are exact.
TEST(Metrics, ConstantOffsetGivesExactRmseAndPsnr) {
    Image reference(16, 16, 1, 0.5f);
    for (float offset : {0.25f, 0.125f, 0.5f}) {
        Image test(16, 16, 1, 0.5f + offset);
        Metrics m = computeMetrics(test, reference);
        EXPECT_DOUBLE_EQ(m.rmse, offset);
        EXPECT_DOUBLE_EQ(m.maxAbs, offset);
        EXPECT_NEAR(m.psnr, -20.0 * std::log10(double(offset)), 1e-12);
    }
    Metrics quarter = computeMetrics(Image(8, 8, 1, 0.75f), Image(8, 8, 1, 0.5f));
    EXPECT_NEAR(quarter.psnr, 12.041199826559248, 1e-9);  // 20 log10(4)
}

// Two constant images: sigma = 0, so SSIM is the luminance term alone,
// (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1) with C1 = (0.01 * 1)^2 (Wang et al. 2004 eq. 13).
TEST(Metrics, SsimOfConstantImagesMatchesTheFormula) {
    Metrics m = computeMetrics(Image(20, 20, 1, 0.5f), Image(20, 20, 1, 0.75f));
    const double c1 = 1e-4;
    EXPECT_NEAR(m.ssim, (2 * 0.5 * 0.75 + c1) / (0.25 + 0.5625 + c1), 1e-12);
}

TEST(Metrics, SsimIsSymmetric) {
    Image a = pattern(32, 24);
    Image b = withNoise(a, 0.1f, 7);
    EXPECT_NEAR(computeMetrics(a, b).ssim, computeMetrics(b, a).ssim, 1e-12);
}

TEST(Metrics, SsimDecreasesWithNoise) {
    Image reference = pattern(64, 48);
    double previous = 1.0;
    for (float amplitude : {0.01f, 0.05f, 0.1f, 0.2f, 0.4f}) {
        double ssim = computeMetrics(withNoise(reference, amplitude, 1234), reference).ssim;
        EXPECT_LT(ssim, previous) << "amplitude " << amplitude;
        EXPECT_GT(ssim, -1.0);
        previous = ssim;
    }
    EXPECT_LT(previous, 0.5);
}

TEST(Metrics, MaskRestrictsThePixels) {
    Image reference(10, 4, 1, 0.5f);
    Image test = reference;
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 5; ++x) test.at(x, y) = 1.0f;  // error only in the left half
    }
    std::vector<uint8_t> right(40, 0);
    std::vector<uint8_t> left(40, 0);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 10; ++x) (x < 5 ? left : right)[size_t(y) * 10 + x] = 1;
    }
    Metrics r = computeMetrics(test, reference, &right);
    EXPECT_EQ(r.pixels, 20u);
    EXPECT_EQ(r.rmse, 0.0);
    Metrics l = computeMetrics(test, reference, &left);
    EXPECT_EQ(l.pixels, 20u);
    EXPECT_DOUBLE_EQ(l.rmse, 0.5);
    Metrics all = computeMetrics(test, reference);
    EXPECT_EQ(all.pixels, 40u);
    EXPECT_DOUBLE_EQ(all.rmse, std::sqrt(0.125));
    std::vector<uint8_t> none(40, 0);
    EXPECT_EQ(computeMetrics(test, reference, &none).pixels, 0u);
    std::vector<uint8_t> wrong(39, 1);
    EXPECT_THROW(computeMetrics(test, reference, &wrong), InputError);
}

TEST(Metrics, NonFinitePixelsAreLeftOut) {
    Image reference(8, 8, 1, 0.5f);
    Image test(8, 8, 1, 0.75f);
    reference.at(1, 1) = kNaN;
    test.at(2, 2) = kNaN;
    test.at(3, 3) = std::numeric_limits<float>::infinity();
    Metrics m = computeMetrics(test, reference);
    EXPECT_EQ(m.pixels, 61u);
    EXPECT_DOUBLE_EQ(m.rmse, 0.25);
    EXPECT_TRUE(std::isfinite(m.ssim));
    const double c1 = 1e-4;  // constant images around the holes: the windows skip them
    EXPECT_NEAR(m.ssim, (2 * 0.5 * 0.75 + c1) / (0.25 + 0.5625 + c1), 1e-12);
}

TEST(Metrics, SizeMismatchIsAnInputError) {
    try {
        computeMetrics(Image(256, 256, 1), Image(128, 128, 1));
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "images differ in size: 256x256 vs 128x128");
    }
    EXPECT_THROW(errorHeatmap(Image(4, 4, 1), Image(4, 5, 1)), InputError);
    EXPECT_THROW(computeMetrics(Image(4, 4, 3), Image(4, 4, 3)), InputError);
}

TEST(Metrics, PenumbraMaskIsStrictlyBetweenZeroAndOne) {
    Image reference(7, 1, 1);
    const float values[7] = {0.0f, 1e-5f, 0.5f, 1.0f - 1e-5f, 1.0f, kNaN, 0.001f};
    for (int i = 0; i < 7; ++i) reference.at(i, 0) = values[i];
    std::vector<uint8_t> mask = penumbraMask(reference);
    std::vector<uint8_t> expected = {0, 0, 1, 0, 0, 0, 1};
    EXPECT_EQ(mask, expected);
}

// The height of the white label text under the colour bar (the rows below the bar's last row).
int labelHeightUnderBar(const Image& map, int h) {
    int barBottom = h;
    for (int y = h; y < map.height; ++y)
        if (std::abs(map.at(map.width / 2, y, 0) - 0.12f) > 1e-3f && map.at(map.width / 2, y, 0) != 1.0f) barBottom = y;
    int top = map.height, bottom = -1;
    for (int y = barBottom + 1; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x)
            if (map.at(x, y, 0) == 1.0f && map.at(x, y, 1) == 1.0f && map.at(x, y, 2) == 1.0f)
                top = std::min(top, y), bottom = std::max(bottom, y);
    return bottom - top + 1;
}

TEST(Heatmap, SizeColoursAndColourBar) {
    const int w = 64;
    const int h = 32;
    Image reference(w, h, 1, 0.5f);
    Image test = reference;
    test.at(10, 10) = 0.75f;  // the largest error: brightest colour
    test.at(20, 10) = kNaN;   // no data: grey
    Image map = errorHeatmap(test, reference);
    ASSERT_EQ(map.width, w);
    ASSERT_EQ(map.channels, 3);
    ASSERT_GT(map.height, h + 10);  // a strip for the colour bar and its labels
    // No error: inferno(0), black.
    EXPECT_LT(map.at(0, 0, 0) + map.at(0, 0, 1) + map.at(0, 0, 2), 0.05f);
    // The largest error: inferno(1), pale yellow.
    EXPECT_GT(map.at(10, 10, 0), 0.9f);
    EXPECT_GT(map.at(10, 10, 1), 0.9f);
    EXPECT_EQ(map.at(20, 10, 0), 0.5f);
    EXPECT_EQ(map.at(20, 10, 1), 0.5f);

    // The colour bar: a row of the strip running from dark on the left to bright on the right (its
    // ends: the first and last pixels of the row that are not the strip's background).
    int barRows = 0;
    auto isBackground = [&](int x, int y) { return std::abs(map.at(x, y, 0) - 0.12f) < 1e-3f && std::abs(map.at(x, y, 2) - 0.12f) < 1e-3f; };
    for (int y = h; y < map.height; ++y) {
        int x0 = 0, x1 = w - 1;
        while (x0 < w && isBackground(x0, y)) ++x0;
        while (x1 > x0 && isBackground(x1, y)) --x1;
        if (x1 - x0 < w / 2) continue;
        float left = map.at(x0, y, 0) + map.at(x0, y, 1) + map.at(x0, y, 2);
        float right = map.at(x1, y, 0) + map.at(x1, y, 1) + map.at(x1, y, 2);
        float mid = map.at((x0 + x1) / 2, y, 0);
        if (left < 0.2f && right > 2.4f && mid > 0.3f) ++barRows;
    }
    EXPECT_GE(barRows, 5);
    // The labels "0" (left) and the maximum (right) in white text under the bar, at least 14 px high
    // (the text standard, viz/README.md: stb_easy_font's capitals are 7 units, so a scale of 2).
    int whiteLeft = 0;
    int whiteRight = 0;
    for (int y = h; y < map.height; ++y) {
        for (int x = 0; x < w; ++x) {
            if (map.at(x, y, 0) == 1.0f && map.at(x, y, 1) == 1.0f && map.at(x, y, 2) == 1.0f) {
                (x < w / 4 ? whiteLeft : whiteRight) += 1;
            }
        }
    }
    EXPECT_GT(whiteLeft, 3);
    EXPECT_GT(whiteRight, 10);  // "0.25" has more ink than "0"
    EXPECT_GE(labelHeightUnderBar(map, h), 14) << "label text under the standard's 14 px";
}

// A wide heat map has room for the bar's title and the grey "no data" swatch beside the bar, and
// its text grows with the picture (1/30 of its height).
TEST(Heatmap, WideMapsStateTheBackgroundAndScaleTheirText) {
    const int w = 600, h = 600;
    Image reference(w, h, 1, 0.5f);
    Image test = reference;
    test.at(10, 10) = 0.75f;
    Image map = errorHeatmap(test, reference);
    int grey = 0;
    for (int y = h; y < map.height; ++y)
        for (int x = 0; x < w; ++x)
            if (map.at(x, y, 0) == 0.5f && map.at(x, y, 1) == 0.5f && map.at(x, y, 2) == 0.5f) ++grey;
    EXPECT_GT(grey, 100) << "the no-data swatch";
    // An em of 1/30 of the picture's height: capitals of at least 0.65 of it.
    EXPECT_GE(labelHeightUnderBar(map, h), int(0.65 * map.height / 30.0)) << "text at least 1/30 of the picture's height";
}

TEST(Heatmap, ExplicitScaleAndIdenticalImages) {
    Image reference(16, 16, 1, 0.5f);
    Image test = reference;
    test.at(3, 3) = 0.75f;
    Image automatic = errorHeatmap(test, reference);
    Image wide = errorHeatmap(test, reference, 1.0f);  // error 0.25 of a scale of 1: darker
    float a = automatic.at(3, 3, 0) + automatic.at(3, 3, 1) + automatic.at(3, 3, 2);
    float b = wide.at(3, 3, 0) + wide.at(3, 3, 1) + wide.at(3, 3, 2);
    EXPECT_LT(b, a);
    Image same = errorHeatmap(reference, reference);
    for (int y = 0; y < 16; ++y) {
        for (int x = 0; x < 16; ++x) EXPECT_LT(same.at(x, y, 0), 0.05f);
    }
    // Deterministic.
    EXPECT_EQ(errorHeatmap(test, reference).data, automatic.data);
}
