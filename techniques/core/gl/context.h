// OpenGL 4.5 core contexts (DESIGN.md section 3): headless EGL surfaceless (default), OSMesa
// (--gl osmesa) and, from app/, a GLFW window. All render through the same code into FBOs.
#pragma once
#include <memory>
#include <string>

namespace shadowlab {

enum class GLBackend { Egl, OSMesa, Glfw };

// KHR_debug: every GL error message is counted and printed to stderr (synchronous output, so a
// debugger breaks at the call). Tests fail when the count grows; the CLI exits 1 at the end of a
// command that raised one. (No exception is thrown from the callback: it runs inside the driver.)
struct GLDebugState {
    int errors = 0;
    std::string lastError;
};
GLDebugState& glDebugState();
// Installs the debug callback on the current context (needs a debug context for all messages).
void installGLDebugCallback();

class GLContext {
public:
    virtual ~GLContext() = default;
    virtual void makeCurrent() = 0;
    GLBackend backend() const { return backend_; }
    std::string renderer() const;  // GL_RENDERER
    std::string version() const;   // GL_VERSION
    // True on Mesa's llvmpipe/softpipe, whose timer queries time one tile: time on the CPU there.
    bool isSoftwareRasterizer() const;

protected:
    // Subclasses call these: makeCurrent() records the context as current on this thread (the key
    // of programCache()); the destructor, with the context still current, destroys the objects the
    // context owns (its ProgramCache) before the context goes.
    void markCurrent();
    void releaseContextObjects(bool isCurrent);  // not current: the objects are leaked, not deleted

    GLBackend backend_ = GLBackend::Egl;
};

// Creates a headless context (Egl or OSMesa), makes it current and loads the GL functions.
// Throws InternalError with the reason when the platform cannot give OpenGL 4.5 core.
std::unique_ptr<GLContext> createHeadlessContext(GLBackend backend);
// Called by createHeadlessContext before it opens anything, when set. The command-line fuzz target
// (tests/fuzz/fuzz_cli.cpp) sets one that throws, so a fuzzed command line stops where it would
// start rendering: what it fuzzes is everything checked before that point. Unset in the program.
void setBeforeHeadlessContext(void (*hook)());

// For contexts made elsewhere (GLFW): loads GL functions through `loader`, installs debug output,
// and makes the current context the key of programCache() from now on on this thread. Its cache
// lives until releaseExternalContextObjects() (call it before destroying that context) or the end
// of the process (then it is never destroyed: no GL call runs after the context is gone).
void initializeGLForCurrentContext(void* (*loader)(const char*));
void releaseExternalContextObjects();

GLBackend parseBackend(const std::string& name);  // "egl" | "osmesa"; InputError otherwise

}  // namespace shadowlab
