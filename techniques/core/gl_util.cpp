#include "gl_util.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "error.h"
#include "scene.h"

namespace fs = std::filesystem;

namespace shadowlab {

static std::string shaderRoot() { return projectRoot() + "/shaders"; }

static std::string readTextFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InternalError("cannot read shader file " + path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

static void expandInto(const fs::path& path, std::vector<std::string>& files, std::set<std::string>& seen,
                       std::ostringstream& out) {
    std::string canonical = fs::weakly_canonical(path).string();
    if (seen.count(canonical)) return;
    seen.insert(canonical);
    int fileIndex = int(files.size());
    files.push_back(fs::relative(canonical, shaderRoot()).string());
    std::istringstream in(readTextFile(canonical));
    std::string line;
    int lineNo = 0;
    static const std::regex includeRe(R"(^\s*#\s*include\s+\"([^\"]+)\"\s*$)");
    out << "#line 1 " << fileIndex << "\n";
    while (std::getline(in, line)) {
        ++lineNo;
        std::smatch m;
        if (std::regex_match(line, m, includeRe)) {
            fs::path target = path.parent_path() / m[1].str();
            if (!fs::exists(target)) target = fs::path(shaderRoot()) / m[1].str();
            if (!fs::exists(target))
                throw InternalError(files[fileIndex] + ":" + std::to_string(lineNo) + ": cannot find included file " +
                                    m[1].str());
            expandInto(target, files, seen, out);
            out << "#line " << (lineNo + 1) << " " << fileIndex << "\n";
        } else {
            out << line << "\n";
        }
    }
}

std::string expandShaderIncludes(const std::string& path, std::vector<std::string>& files) {
    std::ostringstream out;
    std::set<std::string> seen;
    expandInto(fs::path(shaderRoot()) / path, files, seen, out);
    return out.str();
}

// Mesa reports "F:L(C): error: ..."; replace the source-string number F by the file's name.
static std::string nameFilesInLog(const std::string& log, const std::vector<std::string>& files) {
    static const std::regex re(R"((^|\n)(\d+):(\d+)\()");
    std::string result;
    auto begin = std::sregex_iterator(log.begin(), log.end(), re);
    size_t last = 0;
    for (auto it = begin; it != std::sregex_iterator(); ++it) {
        const std::smatch& m = *it;
        result += log.substr(last, m.position(0) - last);
        size_t index = std::stoul(m[2].str());
        std::string name = index < files.size() ? files[index] : m[2].str();
        result += m[1].str() + name + ":" + m[3].str() + "(";
        last = m.position(0) + m.length(0);
    }
    result += log.substr(last);
    return result;
}

static GLuint compileStage(GLenum stage, const std::string& path, const std::vector<std::string>& defines) {
    std::vector<std::string> files;
    std::string body = expandShaderIncludes(path, files);
    std::string source = "#version 450 core\n#define SHARED_FN\n";
    for (const std::string& d : defines) {
        std::string def = d;
        size_t eq = def.find('=');
        if (eq != std::string::npos) def[eq] = ' ';
        source += "#define " + def + "\n";
    }
    source += body;
    GLuint shader = glCreateShader(stage);
    const char* src = source.c_str();
    glShaderSource(shader, 1, &src, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(size_t(std::max(length, 1)), '\0');
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        throw InternalError("shader " + path + " does not compile:\n" + nameFilesInLog(log, files));
    }
    return shader;
}

ShaderProgram::ShaderProgram(const std::string& vertexPath, const std::string& fragmentPath,
                             const std::vector<std::string>& defines, const std::string& geometryPath) {
    std::vector<GLuint> stages;
    stages.push_back(compileStage(GL_VERTEX_SHADER, vertexPath, defines));
    if (!geometryPath.empty()) stages.push_back(compileStage(GL_GEOMETRY_SHADER, geometryPath, defines));
    stages.push_back(compileStage(GL_FRAGMENT_SHADER, fragmentPath, defines));
    id_ = glCreateProgram();
    for (GLuint s : stages) glAttachShader(id_, s);
    glLinkProgram(id_);
    for (GLuint s : stages) {
        glDetachShader(id_, s);
        glDeleteShader(s);
    }
    GLint ok = 0;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
        std::string log(size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(id_, length, nullptr, log.data());
        throw InternalError("program " + vertexPath + " + " + fragmentPath + " does not link:\n" + log);
    }
}

ShaderProgram::~ShaderProgram() {
    if (id_) glDeleteProgram(id_);
}
ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept : id_(other.id_), locations_(std::move(other.locations_)) {
    other.id_ = 0;
}
ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteProgram(id_);
        id_ = other.id_;
        locations_ = std::move(other.locations_);
        other.id_ = 0;
    }
    return *this;
}

GLint ShaderProgram::location(const char* name) const {
    auto it = locations_.find(name);
    if (it != locations_.end()) return it->second;
    GLint loc = glGetUniformLocation(id_, name);
    locations_[name] = loc;  // -1 (optimised away) is silently ignored by glProgramUniform*
    return loc;
}

// ---- textures ------------------------------------------------------------------------------------
Texture::Texture(int width, int height, GLenum internalFormat, GLenum filter)
    : width_(width), height_(height), format_(internalFormat) {
    glCreateTextures(GL_TEXTURE_2D, 1, &id_);
    glTextureStorage2D(id_, 1, internalFormat, width, height);
    glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, filter);
    glTextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}
Texture::~Texture() {
    if (id_) glDeleteTextures(1, &id_);
}
Texture::Texture(Texture&& o) noexcept : id_(o.id_), width_(o.width_), height_(o.height_), format_(o.format_) { o.id_ = 0; }
Texture& Texture::operator=(Texture&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteTextures(1, &id_);
        id_ = o.id_;
        width_ = o.width_;
        height_ = o.height_;
        format_ = o.format_;
        o.id_ = 0;
    }
    return *this;
}
size_t Texture::bytes() const {
    size_t texel = 4;
    switch (format_) {
        case GL_R32F: case GL_R32I: case GL_R32UI: case GL_DEPTH_COMPONENT32F: case GL_RGBA8: texel = 4; break;
        case GL_RG32F: texel = 8; break;
        case GL_RGBA16F: texel = 8; break;
        case GL_RGBA32F: case GL_RGBA32UI: texel = 16; break;
        default: texel = 4;
    }
    return texel * size_t(width_) * size_t(height_);
}
std::string Texture::formatName() const {
    switch (format_) {
        case GL_R32F: return "R32F";
        case GL_RG32F: return "RG32F";
        case GL_RGBA32F: return "RGBA32F";
        case GL_RGBA16F: return "RGBA16F";
        case GL_RGBA8: return "RGBA8";
        case GL_RGBA32UI: return "RGBA32UI";
        case GL_DEPTH_COMPONENT32F: return "DEPTH32F";
        default: return "other";
    }
}

Framebuffer::Framebuffer(const std::vector<const Texture*>& colors, const Texture* depth) {
    glCreateFramebuffers(1, &id_);
    std::vector<GLenum> buffers;
    for (size_t i = 0; i < colors.size(); ++i) {
        glNamedFramebufferTexture(id_, GLenum(GL_COLOR_ATTACHMENT0 + i), colors[i]->id(), 0);
        buffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
    }
    if (depth) glNamedFramebufferTexture(id_, GL_DEPTH_ATTACHMENT, depth->id(), 0);
    if (buffers.empty())
        glNamedFramebufferDrawBuffer(id_, GL_NONE);
    else
        glNamedFramebufferDrawBuffers(id_, GLsizei(buffers.size()), buffers.data());
    GLenum status = glCheckNamedFramebufferStatus(id_, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) throw InternalError("framebuffer incomplete: " + std::to_string(status));
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

Image readTexture(const Texture& texture, int channels) {
    GLenum format = channels == 1 ? GL_RED : channels == 2 ? GL_RG : channels == 3 ? GL_RGB : GL_RGBA;
    Image raw(texture.width(), texture.height(), channels);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture.id(), 0, format, GL_FLOAT, GLsizei(raw.data.size() * sizeof(float)), raw.data.data());
    // GL's row 0 is the bottom of the picture; Image's row 0 is the top.
    Image image(raw.width, raw.height, channels);
    size_t rowFloats = size_t(raw.width) * channels;
    for (int y = 0; y < raw.height; ++y)
        std::copy_n(&raw.data[size_t(raw.height - 1 - y) * rowFloats], rowFloats, &image.data[size_t(y) * rowFloats]);
    return image;
}

void drawFullscreenTriangle() {
    static GLuint vao = 0;
    if (!vao) glCreateVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace shadowlab
