// libFuzzer target: the PFM reader (techniques/core/image/image.cpp readPFM, through the input gate:
// header checked from its first 4 KB, sizes against the file's length and the pixel limit) and
// the metrics that read what it accepts (computeMetrics: a comparison with no finite pixel in
// common is refused). Bad input must be an InputError; anything else is a finding. An accepted
// image must be what its header says: width x height x channels floats.
#include <cstdio>
#include <cstdlib>

#include "fuzz_common.h"
#include "image/image.h"
#include "image/metrics.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const std::string path = fuzz::writeInput("in.pfm", data, size);
    Image image;
    try {
        image = readPFM(path);
    } catch (const InputError&) {
        return 0;
    }
    if (image.width < 1 || image.height < 1 || (image.channels != 1 && image.channels != 3) ||
        image.data.size() != size_t(image.width) * size_t(image.height) * size_t(image.channels)) {
        std::fprintf(stderr, "fuzz_pfm: accepted a %dx%dx%d image holding %zu floats\n", image.width, image.height,
                     image.channels, image.data.size());
        std::abort();
    }
    try {
        const Metrics m = computeMetrics(image, image);
        if (!(m.rmse == 0.0)) {
            std::fprintf(stderr, "fuzz_pfm: an image compared with itself has RMSE %g\n", double(m.rmse));
            std::abort();
        }
    } catch (const InputError&) {
    }
    return 0;
}
