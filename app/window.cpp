// The window: the rendered image of the current scene and technique, switched with keys.
//   T / Shift+T  next / previous technique      S / Shift+S  next / previous scene
//   Esc or Q     quit
// The panels, parameters and VTK views of later issues go here.
#include "gl_loader.h"  // before GLFW, which must not include GL/gl.h
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <chrono>
#include <cstdio>
#include <memory>

#include "cli.h"
#include "error.h"
#include "gl_context.h"
#include "gl_loader.h"
#include "image.h"
#include "renderer.h"
#include "scene.h"
#include "technique.h"

namespace shadowlab {

namespace {

struct WindowState {
    std::vector<std::string> scenes;
    std::vector<std::string> techniques;
    size_t sceneIndex = 0;
    size_t techniqueIndex = 0;
    bool rebuild = true;            // a new scene: a new renderer
    bool techniqueChanged = false;  // the live setter: the G-buffer and shared passes stay cached
};

void onKey(GLFWwindow* window, int key, int, int action, int mods) {
    if (action != GLFW_PRESS) return;
    auto* state = static_cast<WindowState*>(glfwGetWindowUserPointer(window));
    int step = (mods & GLFW_MOD_SHIFT) ? -1 : 1;
    if (key == GLFW_KEY_ESCAPE || key == GLFW_KEY_Q) glfwSetWindowShouldClose(window, GLFW_TRUE);
    if (key == GLFW_KEY_T) {
        state->techniqueIndex = (state->techniqueIndex + state->techniques.size() + step) % state->techniques.size();
        state->techniqueChanged = true;
    }
    if (key == GLFW_KEY_S) {
        state->sceneIndex = (state->sceneIndex + state->scenes.size() + step) % state->scenes.size();
        state->rebuild = true;
    }
}

void* glfwLoader(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

size_t indexOf(const std::vector<std::string>& list, const std::string& value, const std::string& flag) {
    for (size_t i = 0; i < list.size(); ++i)
        if (list[i] == value) return i;
    throw InputError("window: " + flag + ": unknown value '" + value + "'");
}

}  // namespace

int runWindow(const std::vector<std::string>& args) {
    Options opts("window", args, 0, {"--scene", "--technique", "--size", "--screenshot", "--frames"}, {});
    WindowState state;
    state.scenes = listScenes();
    for (const TechniqueDesc* d : allTechniques())
        if (d->id != "raytraced") state.techniques.push_back(d->id);  // the CPU tracer is far from interactive
    if (state.scenes.empty()) throw InputError("window: no scenes in " + projectRoot() + "/assets/scenes");
    state.sceneIndex = indexOf(state.scenes, opts.get("--scene", "square-occluder"), "--scene");
    state.techniqueIndex = indexOf(state.techniques, opts.get("--technique", "pcf"), "--technique");
    int width = 768, height = 768;
    if (opts.has("--size")) parseSize(opts.get("--size"), width, height);
    std::string screenshot = opts.get("--screenshot");
    int maxFrames = opts.getInt("--frames", screenshot.empty() ? 0 : 2, 0, 1000000);

    if (!glfwInit()) {
        std::fprintf(stderr, "shadowlab: cannot open a window (no display?). Headless use: shadowlab render ...\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
    GLFWwindow* window = glfwCreateWindow(width, height, "shadowlab", nullptr, nullptr);
    if (!window) {
        glfwTerminate();
        throw InternalError("GLFW: cannot create an OpenGL 4.5 core window");
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    initializeGLForCurrentContext(glfwLoader);
    glfwSetWindowUserPointer(window, &state);
    glfwSetKeyCallback(window, onKey);
    const GLubyte* rendererName = glGetString(GL_RENDERER);
    bool software = rendererName && (std::string(reinterpret_cast<const char*>(rendererName)).find("llvmpipe") !=
                                     std::string::npos);

    int result = 0;
    {
        std::unique_ptr<Scene> scene;
        std::unique_ptr<Renderer> renderer;
        ShaderProgram present("common/fullscreen.vert", "common/present.frag");
        int frame = 0;
        for (int shown = 0; !glfwWindowShouldClose(window); ++shown) {
            if (state.rebuild) {
                renderer.reset();
                scene = std::make_unique<Scene>(loadScene(state.scenes[state.sceneIndex]));
                RenderOptions options;
                options.width = width;
                options.height = height;
                options.technique = state.techniques[state.techniqueIndex];
                options.cpuClock = software;
                renderer = std::make_unique<Renderer>(*scene, options);
                std::string title = "shadowlab - " + scene->name + " - " + options.technique +
                                    "   (T: technique, S: scene, Esc: quit)";
                glfwSetWindowTitle(window, title.c_str());
                state.rebuild = false;
                state.techniqueChanged = false;
                frame = 0;
            }
            if (state.techniqueChanged) {
                renderer->setTechnique(state.techniques[state.techniqueIndex]);
                std::string title = "shadowlab - " + scene->name + " - " + state.techniques[state.techniqueIndex] +
                                    "   (T: technique, S: scene, Esc: quit)";
                glfwSetWindowTitle(window, title.c_str());
                state.techniqueChanged = false;
            }
            renderer->renderFrame(frame++, {"image"});
            int fbWidth = 0, fbHeight = 0;
            glfwGetFramebufferSize(window, &fbWidth, &fbHeight);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glViewport(0, 0, fbWidth, fbHeight);
            glDisable(GL_DEPTH_TEST);
            present.use();
            glBindTextureUnit(0, renderer->imageTexture().id());
            present.set("image", 0);
            drawFullscreenTriangle();
            if (maxFrames > 0 && shown + 1 >= maxFrames) {
                if (!screenshot.empty()) {
                    Image shot(fbWidth, fbHeight, 3);
                    std::vector<unsigned char> rgb(size_t(fbWidth) * fbHeight * 3);
                    glPixelStorei(GL_PACK_ALIGNMENT, 1);
                    glReadBuffer(GL_BACK);
                    glReadPixels(0, 0, fbWidth, fbHeight, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
                    for (int y = 0; y < fbHeight; ++y)
                        for (int x = 0; x < fbWidth; ++x)
                            for (int c = 0; c < 3; ++c)
                                shot.at(x, y, c) = rgb[(size_t(fbHeight - 1 - y) * fbWidth + x) * 3 + c] / 255.0f;
                    OutputSet outputs;
                    writePNG(outputs.stage(screenshot), shot);
                    outputs.commit();
                }
                glfwSetWindowShouldClose(window, GLFW_TRUE);
            }
            glfwSwapBuffers(window);
            glfwPollEvents();
        }
        if (glDebugState().errors > 0) result = 1;
    }
    glfwDestroyWindow(window);
    glfwTerminate();
    return result;
}

}  // namespace shadowlab
