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

// A 2D texture owned by the renderer; bytes() feeds the memory figures of --stats.
class Texture {
public:
    Texture() = default;
    Texture(int width, int height, GLenum internalFormat, GLenum filter = GL_NEAREST);
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

// One empty VAO for full-screen triangles (gl_VertexID based).
void drawFullscreenTriangle();

}  // namespace shadowlab
