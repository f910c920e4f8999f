// Texel formats of the renderer's textures and images, and the live-object counters that give the
// memory figures of --stats and the leak checks of the tests.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>

#include "gl/loader.h"

namespace shadowlab {

// Every format a pass may declare for a texture. Integer formats (R32UI ... R32I) are read and
// written exactly (imageLoad/imageStore, texelFetch) and are never filtered.
enum class Format { R32F, RG32F, RGBA32F, R32UI, RG32UI, RGBA32UI, R32I, RGBA8, RGBA16F, DEPTH32F, DEPTH32F_STENCIL8 };

GLenum glInternalFormat(Format format);
const char* formatName(Format format);  // "R32F", ..., "DEPTH32F_STENCIL8"
// Bytes per texel as drivers store it: DEPTH32F_STENCIL8 takes 8 (a float and a padded byte).
size_t formatTexelBytes(Format format);
int formatChannels(Format format);  // 1 for the depth formats (the stencil is read on its own)
bool formatIsInteger(Format format);
bool formatIsDepth(Format format);
bool formatHasStencil(Format format);
// The Format of a GL internal format, or nothing when shadowlab has no name for it.
std::optional<Format> formatFromGL(GLenum internalFormat);

// GPU objects alive right now (Texture and Buffer count themselves in their constructors,
// destructors and moves), so that memory figures and leak checks need no bookkeeping elsewhere.
struct GpuMemoryStats {
    int64_t textures = 0;
    int64_t textureBytes = 0;  // every level and layer
    int64_t buffers = 0;
    int64_t bufferBytes = 0;
    int64_t totalBytes() const { return textureBytes + bufferBytes; }
};
GpuMemoryStats gpuMemory();

namespace detail {
// Called by Texture and Buffer only: +1 object and +bytes, or -1 and -bytes.
void countTexture(int64_t objects, int64_t bytes);
void countBuffer(int64_t objects, int64_t bytes);
}  // namespace detail

}  // namespace shadowlab
