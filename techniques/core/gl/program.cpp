#include "gl/program.h"

#include <atomic>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "error.h"
#include "scene/scene.h"

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

// ---- uniform declarations ------------------------------------------------------------------------
static std::atomic<bool> g_uniformNameCheck{false};
void setUniformNameCheck(bool on) { g_uniformNameCheck = on; }
bool uniformNameCheck() { return g_uniformNameCheck; }

static std::set<std::pair<std::string, std::string>>& exemptions() {
    static std::set<std::pair<std::string, std::string>> known;
    return known;
}
void allowUndeclaredUniform(const std::string& program, const std::string& uniform) {
    exemptions().insert({program, uniform});
}

static std::string withoutComments(const std::string& source) {
    std::string out;
    out.reserve(source.size());
    for (size_t i = 0; i < source.size(); ++i) {
        if (source.compare(i, 2, "//") == 0) {
            while (i < source.size() && source[i] != '\n') ++i;
            out += '\n';
        } else if (source.compare(i, 2, "/*") == 0) {
            size_t end = source.find("*/", i + 2);
            i = end == std::string::npos ? source.size() : end + 1;
            out += ' ';
        } else {
            out += source[i];
        }
    }
    return out;
}

static bool isIdentChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// The last identifier of one declarator ("vec3 name[4]", "name = vec3(1.0)", "float[2] name").
static std::string declaratorName(std::string text) {
    text = text.substr(0, text.find('='));
    std::string clean;
    int depth = 0;
    for (char c : text) {  // drop array sizes, which may name constants
        if (c == '[') ++depth;
        else if (c == ']') --depth;
        else if (depth == 0) clean += c;
    }
    size_t end = clean.size();
    while (end > 0 && !isIdentChar(clean[end - 1])) --end;
    size_t begin = end;
    while (begin > 0 && isIdentChar(clean[begin - 1])) --begin;
    return clean.substr(begin, end - begin);
}

std::set<std::string> declaredUniformNames(const std::string& source) {
    std::set<std::string> names;
    std::string text = withoutComments(source);
    for (size_t at = text.find("uniform"); at != std::string::npos; at = text.find("uniform", at + 7)) {
        bool wordStart = at == 0 || !isIdentChar(text[at - 1]);
        bool wordEnd = at + 7 >= text.size() || !isIdentChar(text[at + 7]);
        if (!wordStart || !wordEnd) continue;
        size_t end = text.find_first_of(";{", at);
        if (end == std::string::npos) break;
        if (text[end] == '{') continue;  // a uniform block: its members have no locations
        // Split the declarators at top-level commas: "float a[3], b" -> "float a[3]", " b".
        std::string declaration = text.substr(at + 7, end - at - 7);
        int depth = 0;
        size_t start = 0;
        for (size_t i = 0; i <= declaration.size(); ++i) {
            char c = i < declaration.size() ? declaration[i] : ',';
            if (c == '(' || c == '[') ++depth;
            else if (c == ')' || c == ']') --depth;
            else if (c == ',' && depth == 0) {
                std::string name = declaratorName(declaration.substr(start, i - start));
                if (!name.empty()) names.insert(name);
                start = i + 1;
            }
        }
    }
    return names;
}

// ---- compiling -----------------------------------------------------------------------------------
struct CompiledStage {
    GLuint shader = 0;
    std::set<std::string> uniforms;
};

static CompiledStage compileStage(GLenum stage, const std::string& path, const std::vector<std::string>& defines) {
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
    return {shader, declaredUniformNames(body)};
}

void ShaderProgram::link(const std::vector<GLuint>& stages) {
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
        glDeleteProgram(id_);
        id_ = 0;
        throw InternalError("program " + describe() + " does not link:\n" + log);
    }
}

ShaderProgram::ShaderProgram(const std::string& vertexPath, const std::string& fragmentPath,
                             const std::vector<std::string>& defines, const std::string& geometryPath) {
    std::vector<std::pair<GLenum, std::string>> stagePaths = {{GL_VERTEX_SHADER, vertexPath}};
    if (!geometryPath.empty()) stagePaths.push_back({GL_GEOMETRY_SHADER, geometryPath});
    stagePaths.push_back({GL_FRAGMENT_SHADER, fragmentPath});
    std::vector<GLuint> stages;
    try {
        for (const auto& [stage, path] : stagePaths) {
            CompiledStage compiled = compileStage(stage, path, defines);
            stages.push_back(compiled.shader);
            declared_.insert(compiled.uniforms.begin(), compiled.uniforms.end());
            files_.push_back(path);
        }
    } catch (...) {
        for (GLuint s : stages) glDeleteShader(s);
        throw;
    }
    link(stages);
}

ShaderProgram ShaderProgram::compute(const std::string& computePath, const std::vector<std::string>& defines) {
    ShaderProgram program;
    CompiledStage compiled = compileStage(GL_COMPUTE_SHADER, computePath, defines);
    program.declared_ = std::move(compiled.uniforms);
    program.files_ = {computePath};
    program.link({compiled.shader});
    return program;
}

ShaderProgram::~ShaderProgram() {
    if (id_) glDeleteProgram(id_);
}
ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : id_(other.id_), files_(std::move(other.files_)), declared_(std::move(other.declared_)),
      locations_(std::move(other.locations_)) {
    other.id_ = 0;
}
ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteProgram(id_);
        id_ = other.id_;
        files_ = std::move(other.files_);
        declared_ = std::move(other.declared_);
        locations_ = std::move(other.locations_);
        other.id_ = 0;
    }
    return *this;
}

std::string ShaderProgram::describe() const {
    std::string text;
    for (const std::string& f : files_) text += (text.empty() ? "" : " + ") + f;
    return text;
}

GLint ShaderProgram::location(const char* name) const {
    if (uniformNameCheck()) {
        std::string base(name);
        base = base.substr(0, base.find_first_of("[."));
        if (!declared_.count(base) && !exemptions().count({describe(), base}))
            throw InternalError("uniform '" + std::string(name) + "' is not declared in program " + describe());
    }
    auto it = locations_.find(name);
    if (it != locations_.end()) return it->second;
    GLint loc = glGetUniformLocation(id_, name);
    locations_[name] = loc;  // -1 (optimised away) is silently ignored by glProgramUniform*
    return loc;
}

// ---- compute and indirect commands ---------------------------------------------------------------
void ShaderProgram::dispatch(GLuint groupsX, GLuint groupsY, GLuint groupsZ) const {
    use();
    glDispatchCompute(groupsX, groupsY, groupsZ);
}
void ShaderProgram::dispatchIndirect(const Buffer& args, GLintptr offset) const {
    use();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, args.id());
    glDispatchComputeIndirect(offset);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
}
void drawArraysIndirect(GLenum mode, const Buffer& args, GLintptr offset) {
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, args.id());
    glDrawArraysIndirect(mode, reinterpret_cast<const void*>(offset));
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}
void bindStorage(GLuint index, const Buffer& buffer) { buffer.bindBase(GL_SHADER_STORAGE_BUFFER, index); }
void memoryBarrier(GLbitfield bits) { glMemoryBarrier(bits); }

// ---- program cache -------------------------------------------------------------------------------
static std::string cacheKey(const std::vector<std::string>& parts, const std::vector<std::string>& defines) {
    std::string key;
    for (const std::string& p : parts) key += p + "|";
    for (const std::string& d : defines) key += "|" + d;
    return key;
}

const ShaderProgram& ProgramCache::get(const std::string& vertex, const std::string& fragment,
                                       const std::vector<std::string>& defines, const std::string& geometry) {
    std::string key = cacheKey({vertex, fragment, geometry}, defines);
    auto it = programs_.find(key);
    if (it != programs_.end()) return *it->second;
    auto program = std::make_unique<ShaderProgram>(vertex, fragment, defines, geometry);
    ++compileCount_;
    return *(programs_[key] = std::move(program));
}

const ShaderProgram& ProgramCache::compute(const std::string& path, const std::vector<std::string>& defines) {
    std::string key = cacheKey({"compute", path}, defines);
    auto it = programs_.find(key);
    if (it != programs_.end()) return *it->second;
    auto program = std::make_unique<ShaderProgram>(ShaderProgram::compute(path, defines));
    ++compileCount_;
    return *(programs_[key] = std::move(program));
}

}  // namespace shadowlab
