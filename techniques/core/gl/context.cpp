#include "gl/context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <vector>

#include "error.h"
#include "gl/loader.h"
#include "gl/program.h"

namespace shadowlab {

GLDebugState& glDebugState() {
    static GLDebugState state;
    return state;
}

static void APIENTRY onGLDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei,
                                        const GLchar* message, const void*) {
    (void)source;
    (void)id;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    if (type != GL_DEBUG_TYPE_ERROR) {
        // Performance and portability remarks are not errors; llvmpipe emits few of them.
        return;
    }
    GLDebugState& state = glDebugState();
    ++state.errors;
    state.lastError = message;
    std::fprintf(stderr, "shadowlab: GL error: %s\n", message);
}

void installGLDebugCallback() {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(onGLDebugMessage, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

std::string GLContext::renderer() const {
    const GLubyte* s = glGetString(GL_RENDERER);
    return s ? reinterpret_cast<const char*>(s) : "";
}
std::string GLContext::version() const {
    const GLubyte* s = glGetString(GL_VERSION);
    return s ? reinterpret_cast<const char*>(s) : "";
}
bool GLContext::isSoftwareRasterizer() const {
    std::string r = renderer();
    return r.find("llvmpipe") != std::string::npos || r.find("softpipe") != std::string::npos;
}

static void checkVersion() {
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 45) {
        throw InternalError("OpenGL 4.5 core is required, the context gives " + std::to_string(major) + "." +
                            std::to_string(minor));
    }
}

static void initializeGL(void* (*loader)(const char*)) {
    loadGLFunctions(loader);
    if (!glGetString || !glDebugMessageCallback) throw InternalError("cannot load OpenGL functions");
    checkVersion();
    installGLDebugCallback();
}

// ---- objects owned per context ---------------------------------------------------------------------
// Keyed by the GLContext (or, for a context made elsewhere, by a token of its own). The map is
// never destroyed: entries go with their context, and an external context's entry may outlive it
// only until the process ends, when no destructor must call GL.
namespace {
struct ContextObjects {
    ProgramCache programs;
};
std::map<const void*, std::unique_ptr<ContextObjects>>& contextObjects() {
    static auto* objects = new std::map<const void*, std::unique_ptr<ContextObjects>>();
    return *objects;
}
thread_local const void* t_currentContext = nullptr;
const void* t_externalContext = nullptr;
}  // namespace

ProgramCache& programCache() {
    if (!t_currentContext) throw InternalError("programCache(): no GL context is current on this thread");
    std::unique_ptr<ContextObjects>& objects = contextObjects()[t_currentContext];
    if (!objects) objects = std::make_unique<ContextObjects>();
    return objects->programs;
}

void GLContext::markCurrent() { t_currentContext = this; }

void GLContext::releaseContextObjects(bool isCurrent) {
    auto it = contextObjects().find(this);
    if (it != contextObjects().end()) {
        // Without the context current its objects cannot be deleted: leak them rather than delete
        // names of whichever context is current.
        if (!isCurrent) (void)it->second.release();
        contextObjects().erase(it);
    }
    if (t_currentContext == this) t_currentContext = nullptr;
}

void initializeGLForCurrentContext(void* (*loader)(const char*)) {
    initializeGL(loader);
    static char tokens[64];  // distinct keys for successive external contexts
    static int next = 0;
    t_externalContext = &tokens[next++ % 64];
    t_currentContext = t_externalContext;
}

void releaseExternalContextObjects() {
    if (!t_externalContext) return;
    contextObjects().erase(t_externalContext);
    if (t_currentContext == t_externalContext) t_currentContext = nullptr;
    t_externalContext = nullptr;
}

// ---- EGL surfaceless ---------------------------------------------------------------------------
// libEGL is opened with dlopen so that a process using OSMesa never loads it.
namespace {

void* openLibrary(const char* const* names) {
    for (const char* const* n = names; *n; ++n) {
        if (void* h = dlopen(*n, RTLD_NOW | RTLD_LOCAL)) return h;
    }
    return nullptr;
}

struct EglApi {
    void* lib = nullptr;
    PFNEGLGETPROCADDRESSPROC getProcAddress = nullptr;
};
EglApi g_egl;

void* eglLoader(const char* name) {
    return reinterpret_cast<void*>(g_egl.getProcAddress(name));
}

class EglContext : public GLContext {
public:
    EglContext() {
        backend_ = GLBackend::Egl;
        static const char* const names[] = {"libEGL.so.1", "libEGL.so", nullptr};
        g_egl.lib = openLibrary(names);
        if (!g_egl.lib) throw InternalError("EGL: cannot open libEGL.so.1 (install libegl1 and libegl-mesa0)");
        g_egl.getProcAddress = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(g_egl.lib, "eglGetProcAddress"));
        auto getPlatformDisplay =
            reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(g_egl.getProcAddress("eglGetPlatformDisplayEXT"));
        auto initialize = reinterpret_cast<PFNEGLINITIALIZEPROC>(g_egl.getProcAddress("eglInitialize"));
        auto bindApi = reinterpret_cast<PFNEGLBINDAPIPROC>(g_egl.getProcAddress("eglBindAPI"));
        auto chooseConfig = reinterpret_cast<PFNEGLCHOOSECONFIGPROC>(g_egl.getProcAddress("eglChooseConfig"));
        auto createContext = reinterpret_cast<PFNEGLCREATECONTEXTPROC>(g_egl.getProcAddress("eglCreateContext"));
        makeCurrent_ = reinterpret_cast<PFNEGLMAKECURRENTPROC>(g_egl.getProcAddress("eglMakeCurrent"));
        terminate_ = reinterpret_cast<PFNEGLTERMINATEPROC>(g_egl.getProcAddress("eglTerminate"));
        destroyContext_ = reinterpret_cast<PFNEGLDESTROYCONTEXTPROC>(g_egl.getProcAddress("eglDestroyContext"));
        if (!getPlatformDisplay || !initialize || !createContext || !makeCurrent_)
            throw InternalError("EGL: eglGetPlatformDisplayEXT is missing (EGL_EXT_platform_base)");
        display_ = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display_ == EGL_NO_DISPLAY) throw InternalError("EGL: no surfaceless display (EGL_MESA_platform_surfaceless)");
        EGLint major = 0, minor = 0;
        if (!initialize(display_, &major, &minor)) throw InternalError("EGL: eglInitialize failed");
        if (!bindApi(EGL_OPENGL_API)) throw InternalError("EGL: eglBindAPI(EGL_OPENGL_API) failed");
        const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        chooseConfig(display_, configAttribs, &config, 1, &count);
        const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE, EGL_NONE};
        // EGL_KHR_no_config_context: a surfaceless context needs no config.
        context_ = createContext(display_, count > 0 ? config : EGLConfig(nullptr), EGL_NO_CONTEXT, contextAttribs);
        if (context_ == EGL_NO_CONTEXT) throw InternalError("EGL: cannot create an OpenGL 4.5 core context");
        makeCurrent();
        initializeGL(eglLoader);
    }
    ~EglContext() override {
        releaseContextObjects(context_ != EGL_NO_CONTEXT &&
                              makeCurrent_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_));
        if (display_ != EGL_NO_DISPLAY) {
            makeCurrent_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            if (context_ != EGL_NO_CONTEXT) destroyContext_(display_, context_);
            terminate_(display_);
        }
    }
    void makeCurrent() override {
        if (!makeCurrent_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            throw InternalError("EGL: eglMakeCurrent (surfaceless) failed");
        markCurrent();
    }

private:
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    PFNEGLMAKECURRENTPROC makeCurrent_ = nullptr;
    PFNEGLTERMINATEPROC terminate_ = nullptr;
    PFNEGLDESTROYCONTEXTPROC destroyContext_ = nullptr;
};

// ---- OSMesa --------------------------------------------------------------------------------------
// The few declarations of GL/osmesa.h we need (that header includes GL/gl.h, whose 1.x prototypes
// clash with the loader's glcorearb.h).
struct osmesa_context;
using OSMesaContext = osmesa_context*;
using OSMESAproc = void (*)();
constexpr int OSMESA_FORMAT = 0x22;
constexpr int OSMESA_RGBA = GL_RGBA;
constexpr int OSMESA_DEPTH_BITS = 0x30;
constexpr int OSMESA_PROFILE = 0x33;
constexpr int OSMESA_CORE_PROFILE = 0x34;
constexpr int OSMESA_CONTEXT_MAJOR_VERSION = 0x36;
constexpr int OSMESA_CONTEXT_MINOR_VERSION = 0x37;
using PFNOSMESACREATECONTEXTATTRIBS = OSMesaContext (*)(const int*, OSMesaContext);
using PFNOSMESAMAKECURRENT = GLboolean (*)(OSMesaContext, void*, GLenum, GLsizei, GLsizei);
using PFNOSMESAGETPROCADDRESS = OSMESAproc (*)(const char*);
using PFNOSMESADESTROYCONTEXT = void (*)(OSMesaContext);

PFNOSMESAGETPROCADDRESS g_osmesaGetProcAddress = nullptr;
void* osmesaLoader(const char* name) {
    return reinterpret_cast<void*>(g_osmesaGetProcAddress(name));
}

class OSMesaGLContext : public GLContext {
public:
    OSMesaGLContext() {
        backend_ = GLBackend::OSMesa;
        static const char* const names[] = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so", nullptr};
        lib_ = openLibrary(names);
        if (!lib_) throw InternalError("OSMesa: cannot open libOSMesa.so.8 (install libosmesa6)");
        auto create = reinterpret_cast<PFNOSMESACREATECONTEXTATTRIBS>(dlsym(lib_, "OSMesaCreateContextAttribs"));
        makeCurrent_ = reinterpret_cast<PFNOSMESAMAKECURRENT>(dlsym(lib_, "OSMesaMakeCurrent"));
        destroy_ = reinterpret_cast<PFNOSMESADESTROYCONTEXT>(dlsym(lib_, "OSMesaDestroyContext"));
        g_osmesaGetProcAddress = reinterpret_cast<PFNOSMESAGETPROCADDRESS>(dlsym(lib_, "OSMesaGetProcAddress"));
        if (!create || !makeCurrent_ || !g_osmesaGetProcAddress)
            throw InternalError("OSMesa: OSMesaCreateContextAttribs is missing");
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                               OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                               OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        context_ = create(attribs, nullptr);
        if (!context_) throw InternalError("OSMesa: cannot create an OpenGL 4.5 core context");
        makeCurrent();
        initializeGL(osmesaLoader);
    }
    ~OSMesaGLContext() override {
        releaseContextObjects(context_ && makeCurrent_(context_, buffer_.data(), GL_UNSIGNED_BYTE, 4, 4));
        if (context_ && destroy_) destroy_(context_);
    }
    void makeCurrent() override {
        // OSMesa needs a colour buffer even though everything renders into FBOs.
        if (!makeCurrent_(context_, buffer_.data(), GL_UNSIGNED_BYTE, 4, 4))
            throw InternalError("OSMesa: OSMesaMakeCurrent failed");
        markCurrent();
    }

private:
    void* lib_ = nullptr;
    OSMesaContext context_ = nullptr;
    PFNOSMESAMAKECURRENT makeCurrent_ = nullptr;
    PFNOSMESADESTROYCONTEXT destroy_ = nullptr;
    std::vector<unsigned char> buffer_ = std::vector<unsigned char>(4 * 4 * 4);
};

}  // namespace

namespace {
void (*beforeHeadlessContext)() = nullptr;
}  // namespace

void setBeforeHeadlessContext(void (*hook)()) { beforeHeadlessContext = hook; }

std::unique_ptr<GLContext> createHeadlessContext(GLBackend backend) {
    if (beforeHeadlessContext) beforeHeadlessContext();
    if (backend == GLBackend::OSMesa) return std::make_unique<OSMesaGLContext>();
    if (backend == GLBackend::Egl) return std::make_unique<EglContext>();
    throw InternalError("createHeadlessContext: a GLFW context is made by the window");
}

GLBackend parseBackend(const std::string& name) {
    if (name == "egl") return GLBackend::Egl;
    if (name == "osmesa") return GLBackend::OSMesa;
    throw InputError("--gl: expected egl or osmesa, got '" + name + "'");
}

}  // namespace shadowlab
