// Error metrics on visibility buffers (DESIGN.md section 3): RMSE, max abs error, PSNR, SSIM, each
// over all pixels and over the penumbra region, and an error heat map with a colour scale.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"

namespace shadowlab {

struct Metrics {
    double rmse = 0.0;
    double maxAbs = 0.0;
    double psnr = 0.0;   // dB, peak value 1; +infinity when rmse == 0 (reported as 1e9 in JSON? no: "inf")
    double ssim = 1.0;   // mean SSIM (Wang et al. 2004: 11x11 Gaussian window, sigma 1.5, K1 0.01, K2 0.03, L 1)
    size_t pixels = 0;   // pixels that entered the average
};

// Pixels where the reference is strictly inside (0,1): reference > kPenumbraEpsilon and
// reference < 1 - kPenumbraEpsilon. The epsilon only absorbs float rounding of averaged samples.
constexpr float kPenumbraEpsilon = 1e-4f;
std::vector<uint8_t> penumbraMask(const Image& reference);

// Metrics of `test` against `reference` (both 1-channel, same size, else InputError). Only pixels
// where mask is non-zero (all pixels when mask is null) and both values are finite take part.
// SSIM is computed on the full image (windows see all finite pixels) and averaged over the mask.
Metrics computeMetrics(const Image& test, const Image& reference, const std::vector<uint8_t>* mask = nullptr);

// RGB heat map of |test - reference| with a colour bar and its scale written under the image.
// maxError <= 0 means: use the largest error in the image.
Image errorHeatmap(const Image& test, const Image& reference, float maxError = 0.0f);

}  // namespace shadowlab
