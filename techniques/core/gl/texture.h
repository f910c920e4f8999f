// Textures (2D or 2D array, with mip levels), framebuffers that render into one level and layer of
// them, and read-back and upload of any level and layer.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "gl/format.h"
#include "gl/loader.h"
#include "image/image.h"

namespace shadowlab {

// Levels of a full mip chain from w x h down to 1 x 1: 1 + floor(log2(max(w, h))).
int fullMipLevels(int width, int height);

// A 2D texture or 2D array texture with immutable storage; bytes() (every level and layer) feeds
// the memory figures of --stats and gpuMemory().
class Texture {
public:
    Texture() = default;
    // One-level 2D texture (the original constructor; any sized internal format).
    Texture(int width, int height, GLenum internalFormat, GLenum filter = GL_NEAREST);
    // levels = 0: the full chain down to 1x1. With several levels the minifying filter picks the
    // nearest level (GL_NEAREST_MIPMAP_NEAREST / GL_LINEAR_MIPMAP_NEAREST): passes that read a level
    // say which one (textureLod, texelFetch). Integer formats are always GL_NEAREST.
    static Texture create2D(int width, int height, Format format, int levels = 1, GLenum filter = GL_NEAREST);
    static Texture createArray(int width, int height, int layers, Format format, int levels = 1,
                               GLenum filter = GL_NEAREST);
    ~Texture();
    Texture(Texture&& other) noexcept;
    Texture& operator=(Texture&& other) noexcept;
    Texture(const Texture&) = delete;
    Texture& operator=(const Texture&) = delete;

    GLuint id() const { return id_; }
    int width(int level = 0) const;   // max(1, width >> level)
    int height(int level = 0) const;  // max(1, height >> level)
    int levels() const { return levels_; }
    int layers() const { return layers_; }  // 1 for a 2D texture
    bool isArray() const { return array_; }
    GLenum format() const { return format_; }  // GL internal format
    Format textureFormat() const;              // InternalError for a format shadowlab has no name for
    size_t bytes() const;
    std::string formatName() const;  // "R32F" ...; "other" for a format shadowlab has no name for
    explicit operator bool() const { return id_ != 0; }

private:
    Texture(GLenum target, int width, int height, int layers, GLenum internalFormat, int levels, GLenum filter);
    GLuint id_ = 0;
    int width_ = 0, height_ = 0, layers_ = 1, levels_ = 1;
    bool array_ = false;
    GLenum format_ = 0;
};

class Framebuffer {
public:
    // One level of a texture, and for an array texture one layer (layer -1: the whole texture, for
    // a 2D texture; for an array it makes a layered attachment written through gl_Layer).
    struct Attachment {
        const Texture* texture = nullptr;
        int level = 0;
        int layer = -1;
    };

    Framebuffer() = default;
    // Colour attachments in order, optional depth texture (level 0).
    Framebuffer(const std::vector<const Texture*>& colors, const Texture* depth);
    // A DEPTH32F_STENCIL8 depth texture is attached as GL_DEPTH_STENCIL_ATTACHMENT.
    Framebuffer(const std::vector<Attachment>& colors, std::optional<Attachment> depth);
    ~Framebuffer();
    Framebuffer(Framebuffer&& other) noexcept;
    Framebuffer& operator=(Framebuffer&& other) noexcept;
    Framebuffer(const Framebuffer&) = delete;
    Framebuffer& operator=(const Framebuffer&) = delete;
    GLuint id() const { return id_; }
    void bind(int width, int height) const;

private:
    GLuint id_ = 0;
};

// A pass's framebuffer, built at its first use and again only when what it attaches changes (the
// resource pool hands a pass other textures after a resize or a parameter change), keyed by each
// attachment's texture id, level and layer. Every pass that draws into pool textures keeps one.
class FramebufferCache {
public:
    const Framebuffer& get(const std::vector<Framebuffer::Attachment>& colors, std::optional<Framebuffer::Attachment> depth);
    const Framebuffer& get(const std::vector<const Texture*>& colors, const Texture* depth);

private:
    std::vector<GLint> key_;
    Framebuffer fbo_;
};

// Read-backs into client memory: no pixel-pack buffer bound (VTK's views leave one bound now and
// then, and a read would land in it), tight rows. The read functions below call it.
void resetPackState();

// Reads a float texture (R32F, RG32F, RGBA32F ...) into an Image with `channels` channels,
// flipping rows so that row 0 is the top of the picture.
Image readTexture(const Texture& texture, int channels);

// One level and layer in any Format, all of its channels as floats, row 0 at the top. Integer
// formats convert exactly while |value| < 2^24; a depth-stencil texture gives its depth.
Image readTextureLevel(const Texture& texture, int level = 0, int layer = 0);
// The raw values of an R32UI, RG32UI, RGBA32UI or R32I level (R32I as its bit pattern), in GL's
// row order (row 0 at the bottom), channels interleaved.
std::vector<uint32_t> readTextureUint(const Texture& texture, int level = 0, int layer = 0);
// The stencil of a DEPTH32F_STENCIL8 texture (level 0), in GL's row order.
std::vector<uint8_t> readStencil(const Texture& texture);
// Writes a top-first Image into one level and layer of a float or depth texture. The Image has the
// format's channel count (GL converts a float to RGBA16F or RGBA8 as it stores it).
void uploadTexture(const Texture& texture, int level, int layer, const Image& image);

// Binds one level of `texture` to image unit `unit` for imageLoad/imageStore in its own format.
// layer -1: every layer (a layered binding for an array); otherwise that layer alone.
// access: GL_READ_ONLY, GL_WRITE_ONLY or GL_READ_WRITE.
void bindImage(GLuint unit, const Texture& texture, int level, GLenum access, int layer = -1);

}  // namespace shadowlab
