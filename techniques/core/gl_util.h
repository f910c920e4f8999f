// Small GL helpers: shader programs built from files with an include expander, textures and
// framebuffers that report their memory, texture read-back into Images.
#pragma once
#include <glm/glm.hpp>
#include <map>
#include <string>
#include <vector>

#include "gl_loader.h"
#include "image.h"

namespace shadowlab {

// Expands #include "file" (relative to the including file, then to shaders/) and emits
// "#line N F" so that compile errors name the file: F indexes `files`. Each file is included once.
std::string expandShaderIncludes(const std::string& path, std::vector<std::string>& files);

class ShaderProgram {
public:
    ShaderProgram() = default;
    // Paths relative to <root>/shaders; empty geometry path = none. defines: "NAME" or "NAME VALUE".
    ShaderProgram(const std::string& vertexPath, const std::string& fragmentPath,
                  const std::vector<std::string>& defines = {}, const std::string& geometryPath = "");
    ~ShaderProgram();
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;

    GLuint id() const { return id_; }
    void use() const { glUseProgram(id_); }
    GLint location(const char* name) const;
    void set(const char* name, float v) const { glProgramUniform1f(id_, location(name), v); }
    void set(const char* name, int v) const { glProgramUniform1i(id_, location(name), v); }
    void set(const char* name, const glm::vec2& v) const { glProgramUniform2f(id_, location(name), v.x, v.y); }
    void set(const char* name, const glm::vec3& v) const { glProgramUniform3f(id_, location(name), v.x, v.y, v.z); }
    void set(const char* name, const glm::vec4& v) const { glProgramUniform4f(id_, location(name), v.x, v.y, v.z, v.w); }
    void set(const char* name, const glm::mat4& m) const { glProgramUniformMatrix4fv(id_, location(name), 1, GL_FALSE, &m[0][0]); }

private:
    GLuint id_ = 0;
    mutable std::map<std::string, GLint> locations_;
};

enum class Format { R32F, RG32F, RGBA32F, R32UI, RG32UI, RGBA32UI, R32I, RGBA8, RGBA16F, DEPTH32F, DEPTH32F_STENCIL8 };
inline GLenum glInternalFormat(Format f) {
    switch (f) {
        case Format::R32F: return GL_R32F;
        case Format::RG32F: return GL_RG32F;
        case Format::RGBA32F: return GL_RGBA32F;
        case Format::R32UI: return GL_R32UI;
        case Format::RG32UI: return GL_RG32UI;
        case Format::RGBA32UI: return GL_RGBA32UI;
        case Format::R32I: return GL_R32I;
        case Format::RGBA8: return GL_RGBA8;
        case Format::RGBA16F: return GL_RGBA16F;
        case Format::DEPTH32F: return GL_DEPTH_COMPONENT32F;
        case Format::DEPTH32F_STENCIL8: return GL_DEPTH32F_STENCIL8;
    }
    return GL_R32F;
}
inline const char* formatName(Format f) {
    static const char* names[] = {"R32F", "RG32F", "RGBA32F", "R32UI", "RG32UI", "RGBA32UI", "R32I", "RGBA8", "RGBA16F", "DEPTH32F", "DEPTH32F_STENCIL8"};
    return names[int(f)];
}
// A 2D texture owned by the renderer; bytes() feeds the memory figures of --stats.
class Texture {
public:
    Texture() = default;
    Texture(int width, int height, GLenum internalFormat, GLenum filter = GL_NEAREST);
    static Texture create2D(int w, int h, Format f, int levels = 1, GLenum filter = GL_NEAREST) {
        (void)levels;
        return Texture(w, h, glInternalFormat(f), filter);
    }
    static Texture createArray(int, int, int, Format, int) { return Texture(); }
    int levels() const { return 1; }
    ~Texture();
    Texture(Texture&& other) noexcept;
    Texture& operator=(Texture&& other) noexcept;
    Texture(const Texture&) = delete;
    Texture& operator=(const Texture&) = delete;

    GLuint id() const { return id_; }
    int width() const { return width_; }
    int height() const { return height_; }
    GLenum format() const { return format_; }
    size_t bytes() const;
    std::string formatName() const;
    explicit operator bool() const { return id_ != 0; }

private:
    GLuint id_ = 0;
    int width_ = 0, height_ = 0;
    GLenum format_ = 0;
};

class Framebuffer {
public:
    Framebuffer() = default;
    // Colour attachments in order, optional depth texture.
    Framebuffer(const std::vector<const Texture*>& colors, const Texture* depth);
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

// Reads a float texture (R32F, RG32F, RGBA32F ...) into an Image with `channels` channels,
// flipping rows so that row 0 is the top of the picture.
Image readTexture(const Texture& texture, int channels);

// TEMPORARY until the GPU-feature API lands: level 0, float formats, channels from the format.
inline Image readTextureLevel(const Texture& t, int level = 0) {
    (void)level;
    GLenum f = t.format();
    int channels = f == GL_RG32F ? 2 : (f == GL_RGBA32F || f == GL_RGBA16F || f == GL_RGBA8) ? 4 : 1;
    if (f == GL_DEPTH_COMPONENT32F) {
        Image img(t.width(), t.height(), 1);
        glGetTextureImage(t.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(img.data.size() * 4), img.data.data());
        return img;
    }
    return readTexture(t, channels);
}

// One empty VAO for full-screen triangles (gl_VertexID based).
void drawFullscreenTriangle();

}  // namespace shadowlab
