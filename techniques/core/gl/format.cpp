#include "gl/format.h"

#include <atomic>

#include "error.h"

namespace shadowlab {

namespace {
struct FormatInfo {
    Format format;
    GLenum internalFormat;
    const char* name;
    size_t texelBytes;
    int channels;
    bool integer, depth, stencil;
};
// One table: every property of a format is read from its row.
constexpr FormatInfo kFormats[] = {
    {Format::R32F, GL_R32F, "R32F", 4, 1, false, false, false},
    {Format::RG32F, GL_RG32F, "RG32F", 8, 2, false, false, false},
    {Format::RGBA32F, GL_RGBA32F, "RGBA32F", 16, 4, false, false, false},
    {Format::R32UI, GL_R32UI, "R32UI", 4, 1, true, false, false},
    {Format::RG32UI, GL_RG32UI, "RG32UI", 8, 2, true, false, false},
    {Format::RGBA32UI, GL_RGBA32UI, "RGBA32UI", 16, 4, true, false, false},
    {Format::R32I, GL_R32I, "R32I", 4, 1, true, false, false},
    {Format::RGBA8, GL_RGBA8, "RGBA8", 4, 4, false, false, false},
    {Format::RGBA16F, GL_RGBA16F, "RGBA16F", 8, 4, false, false, false},
    {Format::DEPTH32F, GL_DEPTH_COMPONENT32F, "DEPTH32F", 4, 1, false, true, false},
    {Format::DEPTH32F_STENCIL8, GL_DEPTH32F_STENCIL8, "DEPTH32F_STENCIL8", 8, 1, false, true, true},
};

const FormatInfo& info(Format format) {
    for (const FormatInfo& row : kFormats)
        if (row.format == format) return row;
    throw InternalError("unknown Format " + std::to_string(int(format)));
}

std::atomic<int64_t> g_textures{0}, g_textureBytes{0}, g_buffers{0}, g_bufferBytes{0};
}  // namespace

GLenum glInternalFormat(Format format) { return info(format).internalFormat; }
const char* formatName(Format format) { return info(format).name; }
size_t formatTexelBytes(Format format) { return info(format).texelBytes; }
int formatChannels(Format format) { return info(format).channels; }
bool formatIsInteger(Format format) { return info(format).integer; }
bool formatIsDepth(Format format) { return info(format).depth; }
bool formatHasStencil(Format format) { return info(format).stencil; }

std::optional<Format> formatFromGL(GLenum internalFormat) {
    for (const FormatInfo& row : kFormats)
        if (row.internalFormat == internalFormat) return row.format;
    return std::nullopt;
}

GpuMemoryStats gpuMemory() {
    GpuMemoryStats stats;
    stats.textures = g_textures;
    stats.textureBytes = g_textureBytes;
    stats.buffers = g_buffers;
    stats.bufferBytes = g_bufferBytes;
    return stats;
}

namespace detail {
void countTexture(int64_t objects, int64_t bytes) {
    g_textures += objects;
    g_textureBytes += bytes;
}
void countBuffer(int64_t objects, int64_t bytes) {
    g_buffers += objects;
    g_bufferBytes += bytes;
}
}  // namespace detail

}  // namespace shadowlab
