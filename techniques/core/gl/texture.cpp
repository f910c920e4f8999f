#include "gl/texture.h"

#include <algorithm>

#include "error.h"

namespace shadowlab {

int fullMipLevels(int width, int height) {
    int levels = 1;
    for (int size = std::max(width, height); size > 1; size >>= 1) ++levels;
    return levels;
}

// ---- textures ------------------------------------------------------------------------------------
Texture::Texture(int width, int height, GLenum internalFormat, GLenum filter)
    : Texture(GL_TEXTURE_2D, width, height, 1, internalFormat, 1, filter) {}

Texture::Texture(GLenum target, int width, int height, int layers, GLenum internalFormat, int levels, GLenum filter)
    : width_(width), height_(height), layers_(layers), levels_(levels), array_(target == GL_TEXTURE_2D_ARRAY),
      format_(internalFormat) {
    if (width < 1 || height < 1 || layers < 1 || levels < 1 || levels > fullMipLevels(width, height))
        throw InternalError("Texture: bad size " + std::to_string(width) + "x" + std::to_string(height) + ", " +
                            std::to_string(layers) + " layers, " + std::to_string(levels) + " levels");
    std::optional<Format> known = formatFromGL(internalFormat);
    if (known && formatIsInteger(*known)) filter = GL_NEAREST;  // integer textures cannot be filtered
    GLenum minFilter = filter;
    if (levels > 1) minFilter = filter == GL_LINEAR ? GL_LINEAR_MIPMAP_NEAREST : GL_NEAREST_MIPMAP_NEAREST;
    glCreateTextures(target, 1, &id_);
    if (array_)
        glTextureStorage3D(id_, levels, internalFormat, width, height, layers);
    else
        glTextureStorage2D(id_, levels, internalFormat, width, height);
    glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, GLint(minFilter));
    glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, GLint(filter));
    glTextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    detail::countTexture(1, int64_t(bytes()));
}

Texture Texture::create2D(int width, int height, Format format, int levels, GLenum filter) {
    if (levels == 0) levels = fullMipLevels(width, height);
    return Texture(GL_TEXTURE_2D, width, height, 1, glInternalFormat(format), levels, filter);
}
Texture Texture::createArray(int width, int height, int layers, Format format, int levels, GLenum filter) {
    if (levels == 0) levels = fullMipLevels(width, height);
    return Texture(GL_TEXTURE_2D_ARRAY, width, height, layers, glInternalFormat(format), levels, filter);
}

Texture::~Texture() {
    if (id_) {
        glDeleteTextures(1, &id_);
        detail::countTexture(-1, -int64_t(bytes()));
    }
}
Texture::Texture(Texture&& o) noexcept
    : id_(o.id_), width_(o.width_), height_(o.height_), layers_(o.layers_), levels_(o.levels_), array_(o.array_),
      format_(o.format_) {
    o.id_ = 0;
}
Texture& Texture::operator=(Texture&& o) noexcept {
    if (this != &o) {
        if (id_) {
            glDeleteTextures(1, &id_);
            detail::countTexture(-1, -int64_t(bytes()));
        }
        id_ = o.id_;
        width_ = o.width_;
        height_ = o.height_;
        layers_ = o.layers_;
        levels_ = o.levels_;
        array_ = o.array_;
        format_ = o.format_;
        o.id_ = 0;
    }
    return *this;
}

int Texture::width(int level) const { return width_ ? std::max(1, width_ >> level) : 0; }
int Texture::height(int level) const { return height_ ? std::max(1, height_ >> level) : 0; }

Format Texture::textureFormat() const {
    std::optional<Format> known = formatFromGL(format_);
    if (!known) throw InternalError("Texture: GL internal format " + std::to_string(format_) + " has no Format");
    return *known;
}

size_t Texture::bytes() const {
    std::optional<Format> known = formatFromGL(format_);
    size_t texel = known ? formatTexelBytes(*known) : 4;
    size_t total = 0;
    for (int level = 0; level < levels_; ++level) total += texel * size_t(width(level)) * size_t(height(level));
    return total * size_t(layers_);
}
std::string Texture::formatName() const {
    std::optional<Format> known = formatFromGL(format_);
    return known ? shadowlab::formatName(*known) : "other";
}

// ---- framebuffers --------------------------------------------------------------------------------
static std::vector<Framebuffer::Attachment> wholeLevels(const std::vector<const Texture*>& textures) {
    std::vector<Framebuffer::Attachment> attachments;
    for (const Texture* t : textures) attachments.push_back({t, 0, -1});
    return attachments;
}

Framebuffer::Framebuffer(const std::vector<const Texture*>& colors, const Texture* depth)
    : Framebuffer(wholeLevels(colors), depth ? std::optional<Attachment>(Attachment{depth, 0, -1}) : std::nullopt) {}

static void attach(GLuint fbo, GLenum point, const Framebuffer::Attachment& a) {
    if (!a.texture || !*a.texture) throw InternalError("framebuffer: attachment without a texture");
    if (a.level < 0 || a.level >= a.texture->levels() || a.layer >= a.texture->layers())
        throw InternalError("framebuffer: level " + std::to_string(a.level) + " layer " + std::to_string(a.layer) +
                            " outside a texture of " + std::to_string(a.texture->levels()) + " levels, " +
                            std::to_string(a.texture->layers()) + " layers");
    if (a.layer < 0 || !a.texture->isArray())
        glNamedFramebufferTexture(fbo, point, a.texture->id(), a.level);
    else
        glNamedFramebufferTextureLayer(fbo, point, a.texture->id(), a.level, a.layer);
}

Framebuffer::Framebuffer(const std::vector<Attachment>& colors, std::optional<Attachment> depth) {
    glCreateFramebuffers(1, &id_);
    std::vector<GLenum> buffers;
    for (size_t i = 0; i < colors.size(); ++i) {
        attach(id_, GLenum(GL_COLOR_ATTACHMENT0 + i), colors[i]);
        buffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
    }
    if (depth) {
        GLenum f = depth->texture ? depth->texture->format() : 0;
        bool stencil = f == GL_DEPTH32F_STENCIL8 || f == GL_DEPTH24_STENCIL8;
        attach(id_, stencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT, *depth);
    }
    if (buffers.empty())
        glNamedFramebufferDrawBuffer(id_, GL_NONE);
    else
        glNamedFramebufferDrawBuffers(id_, GLsizei(buffers.size()), buffers.data());
    GLenum status = glCheckNamedFramebufferStatus(id_, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        glDeleteFramebuffers(1, &id_);
        throw InternalError("framebuffer incomplete: " + std::to_string(status));
    }
}
Framebuffer::~Framebuffer() {
    if (id_) glDeleteFramebuffers(1, &id_);
}
Framebuffer::Framebuffer(Framebuffer&& o) noexcept : id_(o.id_) { o.id_ = 0; }
Framebuffer& Framebuffer::operator=(Framebuffer&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteFramebuffers(1, &id_);
        id_ = o.id_;
        o.id_ = 0;
    }
    return *this;
}
void Framebuffer::bind(int width, int height) const {
    glBindFramebuffer(GL_FRAMEBUFFER, id_);
    glViewport(0, 0, width, height);
}

const Framebuffer& FramebufferCache::get(const std::vector<Framebuffer::Attachment>& colors,
                                         std::optional<Framebuffer::Attachment> depth) {
    std::vector<GLint> key;
    auto add = [&key](const Framebuffer::Attachment& a) {
        key.insert(key.end(), {GLint(a.texture ? a.texture->id() : 0u), a.level, a.layer});
    };
    for (const Framebuffer::Attachment& c : colors) add(c);
    key.push_back(-2);  // between the colours and the depth
    if (depth) add(*depth);
    if (!fbo_.id() || key != key_) {
        fbo_ = Framebuffer(colors, depth);
        key_ = std::move(key);
    }
    return fbo_;
}

const Framebuffer& FramebufferCache::get(const std::vector<const Texture*>& colors, const Texture* depth) {
    return get(wholeLevels(colors), depth ? std::optional<Framebuffer::Attachment>(Framebuffer::Attachment{depth, 0, -1})
                                          : std::nullopt);
}

// ---- read-back and upload --------------------------------------------------------------------------
// GL's row 0 is the bottom of the picture; Image's row 0 is the top.
template <class T>
static void flipRows(const T* from, T* to, int width, int height, int channels) {
    size_t row = size_t(width) * channels;
    for (int y = 0; y < height; ++y) std::copy_n(from + size_t(height - 1 - y) * row, row, to + size_t(y) * row);
}

void resetPackState() {
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
}

Image readTexture(const Texture& texture, int channels) {
    GLenum format = channels == 1 ? GL_RED : channels == 2 ? GL_RG : channels == 3 ? GL_RGB : GL_RGBA;
    Image raw(texture.width(), texture.height(), channels);
    resetPackState();
    glGetTextureImage(texture.id(), 0, format, GL_FLOAT, GLsizei(raw.data.size() * sizeof(float)), raw.data.data());
    Image image(raw.width, raw.height, channels);
    flipRows(raw.data.data(), image.data.data(), raw.width, raw.height, channels);
    return image;
}

static void checkLevelLayer(const Texture& texture, int level, int layer, const char* what) {
    if (!texture || level < 0 || level >= texture.levels() || layer < 0 || layer >= texture.layers())
        throw InternalError(std::string(what) + ": level " + std::to_string(level) + " layer " + std::to_string(layer) +
                            " outside a texture of " + std::to_string(texture.levels()) + " levels, " +
                            std::to_string(texture.layers()) + " layers");
}

static GLenum pixelFormat(int channels, bool integer) {
    static const GLenum floats[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
    static const GLenum integers[] = {GL_RED_INTEGER, GL_RG_INTEGER, GL_RGB_INTEGER, GL_RGBA_INTEGER};
    return integer ? integers[channels - 1] : floats[channels - 1];
}

// One level and layer into `out` (GL row order) as (format, type).
static void readLevel(const Texture& texture, int level, int layer, GLenum format, GLenum type, void* out,
                      size_t bytes) {
    resetPackState();
    glGetTextureSubImage(texture.id(), level, 0, 0, layer, texture.width(level), texture.height(level), 1, format,
                         type, GLsizei(bytes), out);
}

std::vector<uint32_t> readTextureUint(const Texture& texture, int level, int layer) {
    checkLevelLayer(texture, level, layer, "readTextureUint");
    Format format = texture.textureFormat();
    if (!formatIsInteger(format))
        throw InternalError(std::string("readTextureUint: ") + formatName(format) + " is not an integer format");
    int channels = formatChannels(format);
    std::vector<uint32_t> values(size_t(texture.width(level)) * texture.height(level) * channels);
    GLenum type = format == Format::R32I ? GL_INT : GL_UNSIGNED_INT;
    readLevel(texture, level, layer, pixelFormat(channels, true), type, values.data(), values.size() * 4);
    return values;
}

Image readTextureLevel(const Texture& texture, int level, int layer) {
    checkLevelLayer(texture, level, layer, "readTextureLevel");
    Format format = texture.textureFormat();
    int w = texture.width(level), h = texture.height(level), channels = formatChannels(format);
    std::vector<float> raw(size_t(w) * h * channels);
    if (formatIsInteger(format)) {
        std::vector<uint32_t> values = readTextureUint(texture, level, layer);
        for (size_t i = 0; i < values.size(); ++i)
            raw[i] = format == Format::R32I ? float(int32_t(values[i])) : float(values[i]);
    } else if (formatIsDepth(format)) {
        readLevel(texture, level, layer, GL_DEPTH_COMPONENT, GL_FLOAT, raw.data(), raw.size() * 4);
    } else {
        readLevel(texture, level, layer, pixelFormat(channels, false), GL_FLOAT, raw.data(), raw.size() * 4);
    }
    Image image(w, h, channels);
    flipRows(raw.data(), image.data.data(), w, h, channels);
    return image;
}

std::vector<uint8_t> readStencil(const Texture& texture) {
    checkLevelLayer(texture, 0, 0, "readStencil");
    if (!formatHasStencil(texture.textureFormat()))
        throw InternalError(std::string("readStencil: ") + texture.formatName() + " has no stencil");
    std::vector<uint8_t> values(size_t(texture.width()) * texture.height());
    readLevel(texture, 0, 0, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, values.data(), values.size());
    return values;
}

void uploadTexture(const Texture& texture, int level, int layer, const Image& image) {
    checkLevelLayer(texture, level, layer, "uploadTexture");
    Format format = texture.textureFormat();
    int w = texture.width(level), h = texture.height(level), channels = formatChannels(format);
    if (formatIsInteger(format) || formatHasStencil(format))
        throw InternalError(std::string("uploadTexture: ") + formatName(format) + " is not a float format");
    if (image.width != w || image.height != h || image.channels != channels)
        throw InternalError("uploadTexture: a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                            "x" + std::to_string(image.channels) + " image into level " + std::to_string(level) +
                            " of " + formatName(format) + ", which is " + std::to_string(w) + "x" +
                            std::to_string(h) + "x" + std::to_string(channels));
    std::vector<float> raw(image.data.size());
    flipRows(image.data.data(), raw.data(), w, h, channels);
    GLenum pixel = formatIsDepth(format) ? GL_DEPTH_COMPONENT : pixelFormat(channels, false);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (texture.isArray())
        glTextureSubImage3D(texture.id(), level, 0, 0, layer, w, h, 1, pixel, GL_FLOAT, raw.data());
    else
        glTextureSubImage2D(texture.id(), level, 0, 0, w, h, pixel, GL_FLOAT, raw.data());
}

void bindImage(GLuint unit, const Texture& texture, int level, GLenum access, int layer) {
    checkLevelLayer(texture, level, std::max(layer, 0), "bindImage");
    if (formatIsDepth(texture.textureFormat()))
        throw InternalError(std::string("bindImage: ") + texture.formatName() + " cannot be an image");
    bool layered = layer < 0 && texture.isArray();
    glBindImageTexture(unit, texture.id(), level, layered ? GL_TRUE : GL_FALSE, std::max(layer, 0), access,
                       texture.format());
}

}  // namespace shadowlab
