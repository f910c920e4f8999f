// Float images, PFM and PNG files, and outputs that are written all-or-nothing.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace shadowlab {

// A float image, row 0 at the TOP (as displayed). channels is 1 (visibility, ids), 3 (positions,
// colours) or 4. PFM files store rows bottom-to-top; readPFM/writePFM convert.
struct Image {
    int width = 0;
    int height = 0;
    int channels = 1;
    std::vector<float> data;  // width * height * channels, row-major, top row first

    Image() = default;
    Image(int w, int h, int c, float fill = 0.0f) : width(w), height(h), channels(c), data(size_t(w) * h * c, fill) {}
    float& at(int x, int y, int c = 0) { return data[(size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c = 0) const { return data[(size_t(y) * width + x) * channels + c]; }
    size_t pixelCount() const { return size_t(width) * height; }
};

// PFM: "Pf" (1 channel) or "PF" (3 channels), little-endian (scale -1), rows bottom-to-top.
// 4-channel images are written as PF with the first three channels. Bad files -> InputError naming
// the file and what was expected.
Image readPFM(const std::string& path);
void writePFM(const std::string& path, const Image& image);

// 8-bit PNG through stb_image_write. 1 channel -> grey, 3 -> RGB, 4 -> RGBA. Values are clamped to
// [0,1]; NaN writes as 0. No gamma is applied: callers encode sRGB themselves when they want it.
void writePNG(const std::string& path, const Image& image);

// All-or-nothing outputs: every file is first written to "<path>.tmp-<pid>" and renamed to its
// final name only by commit(). If the object is destroyed without commit() (an error was thrown
// half-way), the temporaries are deleted, so a failed command leaves no partial output file. After
// removeStagedOutputsOnSignals(), SIGINT and SIGTERM delete them too before the process dies of
// the signal (every staged path, however many; stage() first checks that the folder takes the file:
// checkOutputWritable).
class OutputSet {
public:
    OutputSet() = default;
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;
    ~OutputSet();
    // Returns the temporary path to write instead of finalPath. Creates no directories.
    std::string stage(const std::string& finalPath);
    void commit();

private:
    std::vector<std::pair<std::string, std::string>> staged_;  // (temporary, final)
    bool committed_ = false;
};

// InputError "<finalPath>: cannot write the output in the folder '<folder>': <reason>" unless a file
// can be created beside finalPath (tried by creating and removing its temporary).
void checkOutputWritable(const std::string& finalPath);
// The temporaries staged and not yet committed or removed, in the whole process (tests).
size_t stagedTemporaryCount();

// Installs SIGINT and SIGTERM handlers that unlink every staged temporary of every live OutputSet
// (async-signal-safe), then let the signal kill the process as it would have.
void removeStagedOutputsOnSignals();

}  // namespace shadowlab
