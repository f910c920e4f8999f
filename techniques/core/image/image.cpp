// Float images on disk: PFM (the float visibility, position and id buffers of section 6 of
// DESIGN.md), 8-bit PNG, and all-or-nothing output sets.
//
// PFM layout (Paul Debevec's Portable Float Map): an ASCII header
//     "Pf" (1 channel) or "PF" (3 channels)   whitespace
//     width height                            whitespace
//     scale                                   exactly one whitespace character
// followed by width * height * channels 32-bit IEEE floats. The sign of scale gives the byte
// order (negative: little-endian, positive: big-endian); its magnitude is unused here. Rows are
// stored bottom-to-top, so the first row on disk is the BOTTOM row of the picture, whereas an
// Image keeps row 0 at the top.
#include "image/image.h"
#include "scene/input_file.h"

#include <atomic>
#include <csignal>
#include <cstring>

#include <unistd.h>

#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <locale>
#include <sstream>

#include <stb_image_write.h>  // the implementation comes from libstb (pkg-config stb)

#include "error.h"

namespace shadowlab {

namespace {

static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559, "PFM needs IEEE 754 binary32 floats");

// The largest image side we accept from a file: guards the size computation against overflow and
// against a corrupt header asking for terabytes.
constexpr long long kMaxPfmSide = 1 << 20;
constexpr long long kMaxPfmFloats = 1LL << 32;

std::uint32_t byteSwap32(std::uint32_t v) {
    return (v >> 24) | ((v >> 8) & 0x0000FF00u) | ((v << 8) & 0x00FF0000u) | (v << 24);
}

std::string describeErrno() { return std::strerror(errno); }

// Reads one whitespace-delimited header token starting at `pos`; skips leading whitespace.
// Leaves `pos` on the character right after the token. Returns "" at the end of the data.
std::string headerToken(const std::string& bytes, size_t& pos) {
    while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        ++pos;
    }
    size_t start = pos;
    // A header token is short; stop early on binary garbage.
    while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos])) && pos - start < 64) {
        ++pos;
    }
    return bytes.substr(start, pos - start);
}

bool parseInt(const std::string& token, long long& value) {
    if (token.empty() || token.size() > 18) return false;
    for (char c : token) {
        if (c < '0' || c > '9') return false;
    }
    value = std::stoll(token);
    return true;
}

bool parseFloat(const std::string& token, double& value) {
    if (token.empty()) return false;
    std::istringstream in(token);
    in.imbue(std::locale::classic());
    in >> value;
    return !in.fail() && in.peek() == std::char_traits<char>::eof();
}

void writeAll(const std::string& path, const std::string& bytes) {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) {
        throw InputError(path + ": cannot open for writing: " + describeErrno());
    }
    size_t written = std::fwrite(bytes.data(), 1, bytes.size(), file);
    bool ok = written == bytes.size();
    ok = (std::fclose(file) == 0) && ok;
    if (!ok) {
        std::remove(path.c_str());
        throw InputError(path + ": write failed: " + describeErrno());
    }
}

}  // namespace

Image readPFM(const std::string& path) {
    const std::string bytes = readInputFile(path, "PFM file", kMaxImageInputBytes);

    size_t pos = 0;
    std::string magic = headerToken(bytes, pos);
    int channels = 0;
    if (magic == "Pf") {
        channels = 1;
    } else if (magic == "PF") {
        channels = 3;
    } else {
        throw InputError(path + ": not a PFM file: expected \"Pf\" (1 channel) or \"PF\" (3 channels) at the start");
    }

    long long width = 0;
    long long height = 0;
    std::string widthToken = headerToken(bytes, pos);
    std::string heightToken = headerToken(bytes, pos);
    if (!parseInt(widthToken, width) || !parseInt(heightToken, height) || width <= 0 || height <= 0 ||
        width > kMaxPfmSide || height > kMaxPfmSide) {
        throw InputError(path + ": PFM header: expected a width and a height as positive integers up to " +
                         std::to_string(kMaxPfmSide) + ", got \"" + widthToken + "\" \"" + heightToken + "\"");
    }
    if (width * height * channels > kMaxPfmFloats) {
        throw InputError(path + ": PFM header: image " + widthToken + "x" + heightToken + " is too large");
    }

    std::string scaleToken = headerToken(bytes, pos);
    double scale = 0.0;
    if (!parseFloat(scaleToken, scale) || !std::isfinite(scale) || scale == 0.0) {
        throw InputError(path + ": PFM header: expected a non-zero scale (negative: little-endian, positive: "
                         "big-endian), got \"" + scaleToken + "\"");
    }
    // Exactly one whitespace character separates the header from the raster.
    if (pos >= bytes.size() || !std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        throw InputError(path + ": PFM header: expected one whitespace character after the scale");
    }
    ++pos;
    const bool fileLittleEndian = scale < 0.0;

    const size_t count = size_t(width) * size_t(height) * size_t(channels);
    const size_t rasterBytes = count * sizeof(float);
    if (bytes.size() - pos < rasterBytes) {
        throw InputError(path + ": truncated PFM data: expected " + std::to_string(rasterBytes) + " bytes of floats for " +
                         std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels) +
                         ", found " + std::to_string(bytes.size() - pos));
    }

    Image image(int(width), int(height), channels);
    const bool swap = fileLittleEndian != (std::endian::native == std::endian::little);
    const size_t rowFloats = size_t(width) * channels;
    const char* raster = bytes.data() + pos;
    for (long long fileRow = 0; fileRow < height; ++fileRow) {
        // File row 0 is the bottom row of the picture.
        float* dst = image.data.data() + size_t(height - 1 - fileRow) * rowFloats;
        const char* src = raster + size_t(fileRow) * rowFloats * sizeof(float);
        for (size_t i = 0; i < rowFloats; ++i) {
            std::uint32_t bits;
            std::memcpy(&bits, src + i * sizeof(float), sizeof(bits));
            if (swap) bits = byteSwap32(bits);
            std::memcpy(&dst[i], &bits, sizeof(bits));
        }
    }
    return image;
}

void writePFM(const std::string& path, const Image& image) {
    if (image.channels != 1 && image.channels != 3 && image.channels != 4) {
        throw InternalError("writePFM(" + path + "): images of " + std::to_string(image.channels) +
                            " channels cannot be written as PFM (1, 3 or 4 expected)");
    }
    if (image.width <= 0 || image.height <= 0 || image.data.size() != image.pixelCount() * image.channels) {
        throw InternalError("writePFM(" + path + "): inconsistent image " + std::to_string(image.width) + "x" +
                            std::to_string(image.height) + "x" + std::to_string(image.channels) + " with " +
                            std::to_string(image.data.size()) + " values");
    }
    const int fileChannels = image.channels == 1 ? 1 : 3;
    // Always little-endian (scale -1.0) whatever the host, so files are byte-identical everywhere.
    std::string header = std::string(fileChannels == 1 ? "Pf" : "PF") + "\n" + std::to_string(image.width) + " " +
                         std::to_string(image.height) + "\n-1.0\n";
    std::string bytes = header;
    bytes.resize(header.size() + image.pixelCount() * fileChannels * sizeof(float));
    char* out = bytes.data() + header.size();
    const bool swap = std::endian::native != std::endian::little;
    for (int fileRow = 0; fileRow < image.height; ++fileRow) {
        const int y = image.height - 1 - fileRow;  // bottom row first
        for (int x = 0; x < image.width; ++x) {
            for (int c = 0; c < fileChannels; ++c) {
                std::uint32_t bits;
                float value = image.at(x, y, c);
                std::memcpy(&bits, &value, sizeof(bits));  // bit-exact, NaN payloads included
                if (swap) bits = byteSwap32(bits);
                std::memcpy(out, &bits, sizeof(bits));
                out += sizeof(bits);
            }
        }
    }
    writeAll(path, bytes);
}

void writePNG(const std::string& path, const Image& image) {
    if (image.channels < 1 || image.channels > 4 || image.width <= 0 || image.height <= 0 ||
        image.data.size() != image.pixelCount() * image.channels) {
        throw InternalError("writePNG(" + path + "): inconsistent image " + std::to_string(image.width) + "x" +
                            std::to_string(image.height) + "x" + std::to_string(image.channels));
    }
    std::vector<unsigned char> pixels(image.data.size());
    for (size_t i = 0; i < image.data.size(); ++i) {
        float v = image.data[i];
        if (!(v > 0.0f)) v = 0.0f;  // NaN and negatives
        if (v > 1.0f) v = 1.0f;
        pixels[i] = static_cast<unsigned char>(std::floor(v * 255.0f + 0.5f));
    }
    // stb_image_write's deflate is deterministic, so the same image always gives the same bytes.
    if (!stbi_write_png(path.c_str(), image.width, image.height, image.channels, pixels.data(),
                        image.width * image.channels)) {
        throw InputError(path + ": cannot write PNG file: " + describeErrno());
    }
}

namespace {

// The staged temporaries, where a signal handler can read them without allocating or locking:
// fixed slots, each free (0), being changed (1) or holding a path (2).
constexpr int kStagedSlots = 64;
constexpr size_t kStagedPathMax = 4096;
char gStagedPaths[kStagedSlots][kStagedPathMax];
std::atomic<int> gStagedState[kStagedSlots];

void registerStaged(const std::string& path) {
    if (path.size() + 1 > kStagedPathMax) return;
    for (int i = 0; i < kStagedSlots; ++i) {
        int expected = 0;
        if (gStagedState[i].compare_exchange_strong(expected, 1)) {
            std::memcpy(gStagedPaths[i], path.c_str(), path.size() + 1);
            gStagedState[i].store(2);
            return;
        }
    }
}

void unregisterStaged(const std::string& path) {
    for (int i = 0; i < kStagedSlots; ++i) {
        int expected = 2;
        if (std::strcmp(gStagedPaths[i], path.c_str()) == 0 && gStagedState[i].compare_exchange_strong(expected, 1)) {
            gStagedPaths[i][0] = '\0';
            gStagedState[i].store(0);
            return;
        }
    }
}

extern "C" void removeStagedAndDie(int signal) {
    for (int i = 0; i < kStagedSlots; ++i) {
        if (gStagedState[i].load() == 2) ::unlink(gStagedPaths[i]);
    }
    // SA_RESETHAND restored the default action: the signal, re-raised, kills the process once this
    // handler returns (it is blocked until then), so the exit status says which signal it was.
    ::raise(signal);
}

}  // namespace

void removeStagedOutputsOnSignals() {
    struct sigaction action {};
    action.sa_handler = removeStagedAndDie;
    sigemptyset(&action.sa_mask);
    sigaddset(&action.sa_mask, SIGINT);
    sigaddset(&action.sa_mask, SIGTERM);
    action.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

OutputSet::~OutputSet() {
    for (const auto& [temporary, finalPath] : staged_) {
        if (!committed_) {
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
        }
        unregisterStaged(temporary);
    }
}

std::string OutputSet::stage(const std::string& finalPath) {
    for (const auto& [temporary, staged] : staged_) {
        if (staged == finalPath) return temporary;
    }
    std::string temporary = finalPath + ".tmp-" + std::to_string(static_cast<long long>(::getpid()));
    staged_.emplace_back(temporary, finalPath);
    registerStaged(temporary);
    return temporary;
}

void OutputSet::commit() {
    // Check first that every output was written, so a missing file renames nothing.
    for (const auto& [temporary, finalPath] : staged_) {
        std::error_code error;
        if (!std::filesystem::is_regular_file(temporary, error)) {
            throw InternalError(finalPath + ": output was staged but never written (" + temporary + ")");
        }
    }
    for (const auto& [temporary, finalPath] : staged_) {
        std::error_code error;
        std::filesystem::rename(temporary, finalPath, error);
        if (error) {
            throw InputError(finalPath + ": cannot move the finished output into place: " + error.message());
        }
        unregisterStaged(temporary);
    }
    committed_ = true;
}

}  // namespace shadowlab
