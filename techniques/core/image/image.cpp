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

#include <fcntl.h>
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
constexpr long long kMaxPfmSide = 8192;  // the largest image the renderer makes
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

namespace {

struct PfmHeader {
    int channels = 0;
    long long width = 0, height = 0;
    bool fileLittleEndian = true;
    size_t rasterStart = 0;  // the first byte of the floats
};

// The header at the start of `bytes`; InputError naming `path` when it is not a PFM header.
PfmHeader parsePfmHeader(const std::string& bytes, const std::string& path) {
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
    PfmHeader header;
    header.channels = channels;
    header.width = width;
    header.height = height;
    header.fileLittleEndian = scale < 0.0;
    header.rasterStart = pos;
    return header;

}

}  // namespace

Image readPFM(const std::string& path) {
    // The header is checked from the file's first bytes, before the raster is read: a header over
    // the size limits, or asking for more floats than the file holds, is refused without reading
    // the file (a 30000x30000 header on a sparse file was read whole).
    const std::string bytes = readInputFile(path, "PFM file", kMaxImageInputBytes, [&](const std::string& start, uintmax_t fileBytes) {
        PfmHeader h;
        try {
            h = parsePfmHeader(start, path);
        } catch (const InputError&) {
            // Refused now when the start holds the four header tokens and the whitespace after
            // them; a header longer than the start is checked on the whole file.
            size_t pos = 0;
            for (int token = 0; token < 4; ++token) headerToken(start, pos);
            if (pos < start.size() || start.size() == fileBytes) throw;
            return;
        }
        const uintmax_t raster = uintmax_t(h.width) * uintmax_t(h.height) * uintmax_t(h.channels) * sizeof(float);
        if (fileBytes - h.rasterStart < raster)
            throw InputError(path + ": truncated PFM data: expected " + std::to_string(raster) + " bytes of floats for " +
                             std::to_string(h.width) + "x" + std::to_string(h.height) + "x" + std::to_string(h.channels) +
                             ", found " + std::to_string(fileBytes - h.rasterStart));
        // Beyond a little slack (a trailing newline some tools add), bytes past the raster are no
        // part of this image: refused before gigabytes of them are read.
        if (fileBytes - h.rasterStart > raster + 4096)
            throw InputError(path + ": PFM data: the header says " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                             "x" + std::to_string(h.channels) + " (" + std::to_string(raster) + " bytes of floats), but " +
                             std::to_string(fileBytes - h.rasterStart) + " bytes follow it");
    });
    const PfmHeader header = parsePfmHeader(bytes, path);
    const int channels = header.channels;
    const long long width = header.width, height = header.height;
    const bool fileLittleEndian = header.fileLittleEndian;
    const size_t pos = header.rasterStart;

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

// The staged temporaries, where a signal handler can read them without allocating or locking: a
// list of nodes that only grows (a node is reused once free, never freed), so there is no fixed slot
// count (the first round kept 64 slots: a handout staging more left the rest behind on SIGTERM) and
// no limit on a path's length. Each node is free (0), being changed (1) or holding a path (2); the
// handler unlinks the paths of nodes in state 2 only.
struct StagedNode {
    std::atomic<int> state{1};
    char* path = nullptr;  // written only in state 1
    size_t capacity = 0;
    StagedNode* next = nullptr;
};
std::atomic<StagedNode*> gStagedHead{nullptr};

void fillNode(StagedNode* node, const std::string& path) {
    if (node->capacity < path.size() + 1) {
        delete[] node->path;
        node->path = new char[path.size() + 1];
        node->capacity = path.size() + 1;
    }
    std::memcpy(node->path, path.c_str(), path.size() + 1);
}

void registerStaged(const std::string& path) {
    for (StagedNode* n = gStagedHead.load(); n; n = n->next) {
        int expected = 0;
        if (n->state.compare_exchange_strong(expected, 1)) {
            fillNode(n, path);
            n->state.store(2);
            return;
        }
    }
    auto* node = new StagedNode;  // state 1 until filled and linked
    fillNode(node, path);
    node->next = gStagedHead.load();
    while (!gStagedHead.compare_exchange_weak(node->next, node)) {
    }
    node->state.store(2);
}

void unregisterStaged(const std::string& path) {
    for (StagedNode* n = gStagedHead.load(); n; n = n->next) {
        int expected = 2;
        if (n->state.load() == 2 && std::strcmp(n->path, path.c_str()) == 0 && n->state.compare_exchange_strong(expected, 1)) {
            n->path[0] = '\0';
            n->state.store(0);
            return;
        }
    }
}

extern "C" void removeStagedAndDie(int signal) {
    for (StagedNode* n = gStagedHead.load(); n; n = n->next) {
        if (n->state.load() == 2) ::unlink(n->path);
    }
    // SA_RESETHAND restored the default action: the signal, re-raised, kills the process once this
    // handler returns (it is blocked until then), so the exit status says which signal it was.
    ::raise(signal);
}

}  // namespace

size_t stagedTemporaryCount() {
    size_t n = 0;
    for (StagedNode* node = gStagedHead.load(); node; node = node->next) n += node->state.load() == 2;
    return n;
}

void checkOutputWritable(const std::string& finalPath) {
    // Tried, not asked (access() says yes to root in a read-only place): the temporary this path is
    // staged as is created and removed again, so a folder that cannot take the output is an input
    // error naming the user's path before any work, not "internal error" naming the temporary after.
    // Registered while it exists, so a signal in between removes it too.
    const std::string temporary = finalPath + ".tmp-" + std::to_string(static_cast<long long>(::getpid()));
    registerStaged(temporary);
    struct Unregister {
        const std::string& path;
        ~Unregister() { unregisterStaged(path); }
    } unregister{temporary};
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
        const int error = errno;
        if (error == EEXIST) return;  // staged already by this process
        std::string folder = std::filesystem::path(finalPath).parent_path().string();
        if (folder.empty()) folder = ".";
        throw InputError(finalPath + ": cannot write the output in the folder '" + folder + "': " + std::strerror(error));
    }
    ::close(fd);
    ::unlink(temporary.c_str());
}

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
    checkOutputWritable(finalPath);
    std::string temporary = finalPath + ".tmp-" + std::to_string(static_cast<long long>(::getpid()));
    staged_.emplace_back(temporary, finalPath);
    registerStaged(temporary);
    return temporary;
}

void OutputSet::commit() {
    // Check first that every output was written and that every final path can take a file, so a
    // missing file or a folder where a sidecar goes renames nothing (the PNG and PFM stayed while
    // the command exited 2).
    for (const auto& [temporary, finalPath] : staged_) {
        std::error_code error;
        if (!std::filesystem::is_regular_file(temporary, error)) {
            throw InternalError(finalPath + ": output was staged but never written (" + temporary + ")");
        }
        const std::filesystem::file_status status = std::filesystem::symlink_status(finalPath, error);
        if (std::filesystem::is_directory(status))
            throw InputError(finalPath + ": is a folder, expected a file path (nothing was written)");
        if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) && !std::filesystem::is_symlink(status))
            throw InputError(finalPath + ": is not a regular file (a FIFO, a device or a socket), expected a file path "
                                         "(nothing was written)");
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
