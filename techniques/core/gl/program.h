// Shader programs built from files with an include expander (graphics and compute), the uniform
// name check, dispatch and indirect draws, and the per-context program cache.
#pragma once
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "gl/buffer.h"
#include "gl/loader.h"

namespace shadowlab {

// Expands #include "file" (relative to the including file, then to shaders/) and emits
// "#line N F" so that compile errors name the file: F indexes `files`. Each file is included once.
std::string expandShaderIncludes(const std::string& path, std::vector<std::string>& files);

// Uniform name check (off by default; the tests turn it on). When on, ShaderProgram::set() throws
// InternalError naming the program's files when the uniform is not declared in any stage's source.
// A declared uniform that the compiler removed (unused, or only used under an #ifdef that is off)
// is accepted: it is a legitimate no-op, while an undeclared name is a typo.
void setUniformNameCheck(bool on);
bool uniformNameCheck();
// A known offender the check lets pass: `uniform` (base name) set on the program whose
// ShaderProgram::describe() is `program`. For call sites awaiting a fix; each one says which.
void allowUndeclaredUniform(const std::string& program, const std::string& uniform);

// The names declared by `uniform <type> <name>[N], <name2>;` lines of a GLSL source (comments
// skipped; uniform blocks are not plain uniforms and are left out).
std::set<std::string> declaredUniformNames(const std::string& source);

class ShaderProgram {
public:
    ShaderProgram() = default;
    // Paths relative to <root>/shaders; empty geometry path = none. defines: "NAME" or "NAME VALUE".
    ShaderProgram(const std::string& vertexPath, const std::string& fragmentPath,
                  const std::vector<std::string>& defines = {}, const std::string& geometryPath = "");
    // A compute program from one .comp file.
    static ShaderProgram compute(const std::string& computePath, const std::vector<std::string>& defines = {});
    ~ShaderProgram();
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;

    GLuint id() const { return id_; }
    void use() const { glUseProgram(id_); }
    // "a.vert + b.frag": the files named in errors.
    std::string describe() const;
    // Whether any stage declares a uniform of this (base) name.
    bool declares(const std::string& name) const { return declared_.count(name) > 0; }
    // -1 when the uniform is not active; with uniformNameCheck() on, throws when it is not declared.
    // "lights[3]" and "lights[3].color" are checked by their base name "lights".
    GLint location(const char* name) const;
    void set(const char* name, float v) const { glProgramUniform1f(id_, location(name), v); }
    void set(const char* name, int v) const { glProgramUniform1i(id_, location(name), v); }
    void set(const char* name, unsigned v) const { glProgramUniform1ui(id_, location(name), v); }
    void set(const char* name, const glm::vec2& v) const { glProgramUniform2f(id_, location(name), v.x, v.y); }
    void set(const char* name, const glm::vec3& v) const { glProgramUniform3f(id_, location(name), v.x, v.y, v.z); }
    void set(const char* name, const glm::vec4& v) const { glProgramUniform4f(id_, location(name), v.x, v.y, v.z, v.w); }
    void set(const char* name, const glm::ivec2& v) const { glProgramUniform2i(id_, location(name), v.x, v.y); }
    void set(const char* name, const glm::ivec4& v) const { glProgramUniform4i(id_, location(name), v.x, v.y, v.z, v.w); }
    void set(const char* name, const glm::uvec2& v) const { glProgramUniform2ui(id_, location(name), v.x, v.y); }
    void set(const char* name, const glm::mat3& m) const { glProgramUniformMatrix3fv(id_, location(name), 1, GL_FALSE, &m[0][0]); }
    void set(const char* name, const glm::mat4& m) const { glProgramUniformMatrix4fv(id_, location(name), 1, GL_FALSE, &m[0][0]); }

    // Compute programs: use() and glDispatchCompute. The caller puts the memory barriers that the
    // next reader needs (memoryBarrier below).
    void dispatch(GLuint groupsX, GLuint groupsY = 1, GLuint groupsZ = 1) const;
    // The group counts come from a DispatchIndirectCommand at `offset` in `args` (a GPU-written
    // count: put memoryBarrier(GL_COMMAND_BARRIER_BIT) between the writer and this call).
    void dispatchIndirect(const Buffer& args, GLintptr offset = 0) const;

private:
    void link(const std::vector<GLuint>& stages);
    GLuint id_ = 0;
    std::vector<std::string> files_;     // one per stage, as given
    std::set<std::string> declared_;     // uniform names declared in any stage (with its includes)
    mutable std::map<std::string, GLint> locations_;
};

// glDrawArraysIndirect with a DrawArraysIndirectCommand at `offset` in `args`; a program and a
// vertex array (even an empty one) must be bound.
void drawArraysIndirect(GLenum mode, const Buffer& args, GLintptr offset = 0);
// A shader storage buffer at binding `index` (layout(std430, binding = index) buffer ...).
void bindStorage(GLuint index, const Buffer& buffer);
// glMemoryBarrier: makes shader writes visible to the readers named by `bits` (e.g.
// GL_SHADER_IMAGE_ACCESS_BARRIER_BIT before imageLoad of what a dispatch stored,
// GL_COMMAND_BARRIER_BIT before an indirect command a shader wrote, GL_TEXTURE_FETCH_BARRIER_BIT
// before sampling, GL_BUFFER_UPDATE_BARRIER_BIT / GL_TEXTURE_UPDATE_BARRIER_BIT before read-back).
void memoryBarrier(GLbitfield bits);

// Compiled programs of one GL context, built on first use and kept until the context dies.
class ProgramCache {
public:
    const ShaderProgram& get(const std::string& vertex, const std::string& fragment,
                             const std::vector<std::string>& defines = {}, const std::string& geometry = "");
    const ShaderProgram& compute(const std::string& path, const std::vector<std::string>& defines = {});
    int compileCount() const { return compileCount_; }  // programs built so far (a hit builds none)
    size_t size() const { return programs_.size(); }

private:
    std::map<std::string, std::unique_ptr<ShaderProgram>> programs_;
    int compileCount_ = 0;
};

// The program cache of the GL context current on this thread (InternalError when none is). The
// context owns it and destroys it, while still current, just before the context itself
// (defined in gl_context.cpp).
ProgramCache& programCache();

}  // namespace shadowlab
