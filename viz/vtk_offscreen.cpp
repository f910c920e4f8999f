#include "vtk_offscreen.h"

#include <vtkContextView.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLShaderCache.h>
#include <vtkOutputWindow.h>
#include <vtkPDFExporter.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkSVGExporter.h>
#include <vtkSmartPointer.h>

#include <cstdio>
#include <filesystem>

#include "error.h"
#include "gl/loader.h"

namespace shadowlab {

// ---- VTK messages ---------------------------------------------------------------------------------
VtkMessages& vtkMessages() {
    static VtkMessages messages;
    return messages;
}

namespace {

class FilteredOutputWindow : public vtkOutputWindow {
public:
    static FilteredOutputWindow* New();
    vtkTypeMacro(FilteredOutputWindow, vtkOutputWindow);

    void DisplayText(const char* text) override { std::fprintf(stderr, "%s", text); }
    void DisplayErrorText(const char* text) override {
        // VTK's GLEW initialises GLX too and fails there under EGL (GLEW_ERROR_NO_GLX_DISPLAY = 4,
        // printed as "Unknown error") after it has loaded every GL function (DESIGN.md section 7).
        std::string t = text ? text : "";
        if (t.find("GLEW could not be initialized") != std::string::npos) return;
        ++vtkMessages().errors;
        vtkMessages().last = t;
        std::fprintf(stderr, "shadowlab: VTK error: %s", text);
    }
    void DisplayWarningText(const char* text) override {
        ++vtkMessages().warnings;
        vtkMessages().last = text ? text : "";
        std::fprintf(stderr, "shadowlab: VTK warning: %s", text);
    }
    void DisplayGenericWarningText(const char* text) override { DisplayWarningText(text); }
    void DisplayDebugText(const char*) override {}
};
vtkStandardNewMacro(FilteredOutputWindow);

// The GL state VTK may change and the program's passes rely on. vtkGenericOpenGLRenderWindow
// restores part of it itself (SaveGLState/RestoreGLState); this saves the rest and then some.
class GLStateGuard {
public:
    GLStateGuard() {
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFbo_);
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo_);
        glGetIntegerv(GL_VIEWPORT, viewport_);
        glGetIntegerv(GL_SCISSOR_BOX, scissor_);
        glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
        glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
        glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &arrayBuffer_);
        glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &packBuffer_);
        glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpackBuffer_);
        glGetIntegerv(GL_UNIFORM_BUFFER_BINDING, &uniformBuffer_);
        glGetIntegerv(GL_RENDERBUFFER_BINDING, &renderbuffer_);
        glGetIntegerv(GL_ACTIVE_TEXTURE, &activeTexture_);
        for (int unit = 0; unit < kUnits; ++unit) {
            glActiveTexture(GLenum(GL_TEXTURE0 + unit));
            glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture2D_[unit]);
            glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &texture2DArray_[unit]);
            glGetIntegerv(GL_TEXTURE_BINDING_1D, &texture1D_[unit]);
            glGetIntegerv(GL_TEXTURE_BINDING_BUFFER, &textureBuffer_[unit]);
        }
        glActiveTexture(GLenum(activeTexture_));
        for (int p : {GL_PACK_ALIGNMENT, GL_UNPACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_UNPACK_ROW_LENGTH})
            glGetIntegerv(GLenum(p), &pixelStore_[pixelStoreIndex(p)]);
        for (size_t i = 0; i < std::size(kCaps); ++i) enabled_[i] = glIsEnabled(kCaps[i]);
        glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask_);
        glGetBooleanv(GL_COLOR_WRITEMASK, colorMask_);
        glGetIntegerv(GL_DEPTH_FUNC, &depthFunc_);
        glGetIntegerv(GL_BLEND_SRC_RGB, &blend_[0]);
        glGetIntegerv(GL_BLEND_DST_RGB, &blend_[1]);
        glGetIntegerv(GL_BLEND_SRC_ALPHA, &blend_[2]);
        glGetIntegerv(GL_BLEND_DST_ALPHA, &blend_[3]);
        glGetIntegerv(GL_BLEND_EQUATION_RGB, &blendEquation_[0]);
        glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &blendEquation_[1]);
        glGetIntegerv(GL_CULL_FACE_MODE, &cullFace_);
        glGetIntegerv(GL_FRONT_FACE, &frontFace_);
        glGetFloatv(GL_COLOR_CLEAR_VALUE, clearColor_);
        glGetFloatv(GL_DEPTH_CLEAR_VALUE, &clearDepth_);
        glGetIntegerv(GL_POLYGON_MODE, polygonMode_);
        glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &polygonOffset_[0]);
        glGetFloatv(GL_POLYGON_OFFSET_UNITS, &polygonOffset_[1]);
        glGetFloatv(GL_LINE_WIDTH, &lineWidth_);
    }
    ~GLStateGuard() {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(drawFbo_));
        glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(readFbo_));
        glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
        glScissor(scissor_[0], scissor_[1], scissor_[2], scissor_[3]);
        glUseProgram(GLuint(program_));
        glBindVertexArray(GLuint(vao_));
        glBindBuffer(GL_ARRAY_BUFFER, GLuint(arrayBuffer_));
        glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(packBuffer_));
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(unpackBuffer_));
        glBindBuffer(GL_UNIFORM_BUFFER, GLuint(uniformBuffer_));
        glBindRenderbuffer(GL_RENDERBUFFER, GLuint(renderbuffer_));
        for (int unit = 0; unit < kUnits; ++unit) {
            glActiveTexture(GLenum(GL_TEXTURE0 + unit));
            glBindTexture(GL_TEXTURE_2D, GLuint(texture2D_[unit]));
            glBindTexture(GL_TEXTURE_2D_ARRAY, GLuint(texture2DArray_[unit]));
            glBindTexture(GL_TEXTURE_1D, GLuint(texture1D_[unit]));
            glBindTexture(GL_TEXTURE_BUFFER, GLuint(textureBuffer_[unit]));
        }
        glActiveTexture(GLenum(activeTexture_));
        for (int p : {GL_PACK_ALIGNMENT, GL_UNPACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_UNPACK_ROW_LENGTH})
            glPixelStorei(GLenum(p), pixelStore_[pixelStoreIndex(p)]);
        for (size_t i = 0; i < std::size(kCaps); ++i) {
            if (enabled_[i]) glEnable(kCaps[i]);
            else glDisable(kCaps[i]);
        }
        glDepthMask(depthMask_);
        glColorMask(colorMask_[0], colorMask_[1], colorMask_[2], colorMask_[3]);
        glDepthFunc(GLenum(depthFunc_));
        glBlendFuncSeparate(GLenum(blend_[0]), GLenum(blend_[1]), GLenum(blend_[2]), GLenum(blend_[3]));
        glBlendEquationSeparate(GLenum(blendEquation_[0]), GLenum(blendEquation_[1]));
        glCullFace(GLenum(cullFace_));
        glFrontFace(GLenum(frontFace_));
        glClearColor(clearColor_[0], clearColor_[1], clearColor_[2], clearColor_[3]);
        glClearDepth(clearDepth_);
        glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygonMode_[0]));
        glPolygonOffset(polygonOffset_[0], polygonOffset_[1]);
        glLineWidth(lineWidth_);
    }

private:
    static constexpr int kUnits = 16;
    static constexpr GLenum kCaps[] = {GL_DEPTH_TEST,         GL_BLEND,          GL_CULL_FACE,
                                       GL_SCISSOR_TEST,       GL_STENCIL_TEST,   GL_MULTISAMPLE,
                                       GL_LINE_SMOOTH,        GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE,
                                       GL_PROGRAM_POINT_SIZE, GL_FRAMEBUFFER_SRGB, GL_TEXTURE_CUBE_MAP_SEAMLESS,
                                       GL_DEPTH_CLAMP,        GL_SAMPLE_ALPHA_TO_COVERAGE, GL_PRIMITIVE_RESTART};
    static int pixelStoreIndex(int p) {
        return p == GL_PACK_ALIGNMENT ? 0 : p == GL_UNPACK_ALIGNMENT ? 1 : p == GL_PACK_ROW_LENGTH ? 2 : 3;
    }
    GLint drawFbo_ = 0, readFbo_ = 0, viewport_[4] = {}, scissor_[4] = {}, program_ = 0, vao_ = 0;
    GLint arrayBuffer_ = 0, packBuffer_ = 0, unpackBuffer_ = 0, uniformBuffer_ = 0, renderbuffer_ = 0;
    GLint activeTexture_ = GL_TEXTURE0;
    GLint texture2D_[kUnits] = {}, texture2DArray_[kUnits] = {}, texture1D_[kUnits] = {}, textureBuffer_[kUnits] = {};
    GLint pixelStore_[4] = {};
    GLboolean enabled_[std::size(kCaps)] = {};
    GLboolean depthMask_ = GL_TRUE, colorMask_[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
    GLint depthFunc_ = GL_LESS, blend_[4] = {}, blendEquation_[2] = {}, cullFace_ = GL_BACK, frontFace_ = GL_CCW;
    GLfloat clearColor_[4] = {}, clearDepth_ = 1.0f;
    GLint polygonMode_[2] = {GL_FILL, GL_FILL};
    GLfloat polygonOffset_[2] = {}, lineWidth_ = 1.0f;
};

}  // namespace

void installVtkMessageFilter() {
    static bool installed = false;
    if (installed) return;
    // VTK also logs errors straight to stderr through its logger: only our window prints them.
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
    vtkNew<FilteredOutputWindow> window;
    vtkOutputWindow::SetInstance(window);
    installed = true;
}

// ---- the bridge ----------------------------------------------------------------------------------
struct VtkOffscreen::Impl {
    vtkSmartPointer<vtkGenericOpenGLRenderWindow> window;
};

VtkOffscreen::VtkOffscreen(int width, int height) : width_(width), height_(height), impl_(new Impl) {
    if (width < 1 || height < 1 || width > 8192 || height > 8192)
        throw InputError("view size: expected 1..8192 pixels a side, got " + std::to_string(width) + "x" +
                         std::to_string(height));
    installVtkMessageFilter();
    GLStateGuard keep;
    auto& w = impl_->window;
    w = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
    // The context is ours and current: VTK only renders into it (the generic window's events for
    // MakeCurrent / IsCurrent / SupportsOpenGL are answered by these fixed values).
    w->SetOwnContext(false);
    w->SetIsCurrent(true);
    w->SetSupportsOpenGL(1);
    w->SetIsDirect(1);
    w->SetMapped(1);
    w->SetMultiSamples(0);  // 5x slower on llvmpipe (DESIGN.md section 7)
    w->SetFrameBlitModeToBlitToCurrent();  // into our frame, bound around Render()
    w->SetSize(width, height);
    w->InitializeFromCurrentContext();
    allocateFrame();
}

VtkOffscreen::~VtkOffscreen() {
    {
        GLStateGuard keep;
        // Frees VTK's GL objects while our context is still current.
        impl_->window->Finalize();
        releaseFrame();
        releaseRetired();
    }
    delete impl_;
}

vtkGenericOpenGLRenderWindow* VtkOffscreen::window() const { return impl_->window; }

vtkRenderer* VtkOffscreen::addRenderer() {
    vtkNew<vtkRenderer> renderer;
    impl_->window->AddRenderer(renderer);
    return renderer;  // the window holds the reference
}

void VtkOffscreen::attach(vtkContextView* view) { view->SetRenderWindow(impl_->window); }

void VtkOffscreen::allocateFrame() {
    glCreateFramebuffers(1, &fbo_);
    glCreateTextures(GL_TEXTURE_2D, 1, &colorTexture_);
    glTextureStorage2D(colorTexture_, 1, GL_RGBA8, width_, height_);
    glTextureParameteri(colorTexture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(colorTexture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, colorTexture_, 0);
    glCreateRenderbuffers(1, &depthBuffer_);
    glNamedRenderbufferStorage(depthBuffer_, GL_DEPTH24_STENCIL8, width_, height_);
    glNamedFramebufferRenderbuffer(fbo_, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depthBuffer_);
    if (glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw InternalError("VtkOffscreen: the view framebuffer is incomplete");
}

void VtkOffscreen::releaseFrame() {
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (colorTexture_) glDeleteTextures(1, &colorTexture_);
    if (depthBuffer_) glDeleteRenderbuffers(1, &depthBuffer_);
    fbo_ = colorTexture_ = depthBuffer_ = 0;
}

void VtkOffscreen::releaseRetired() {
    if (retiredTexture_) glDeleteTextures(1, &retiredTexture_);
    retiredTexture_ = 0;
}

void VtkOffscreen::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    if (width < 1 || height < 1 || width > 8192 || height > 8192)
        throw InputError("view size: expected 1..8192 pixels a side, got " + std::to_string(width) + "x" +
                         std::to_string(height));
    GLStateGuard keep;
    releaseRetired();
    retiredTexture_ = colorTexture_;  // drawn by a UI's draw list of this frame, perhaps
    colorTexture_ = 0;
    releaseFrame();
    width_ = width;
    height_ = height;
    impl_->window->SetSize(width, height);
    allocateFrame();
}

void VtkOffscreen::renderToTexture() {
    GLStateGuard keep;
    // VTK's shader cache skips glUseProgram when it believes its program is still bound; the
    // program's own passes may have bound another since the last render.
    impl_->window->GetShaderCache()->ReleaseCurrentShader();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, width_, height_);
    const GLfloat clear[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(fbo_, GL_COLOR, 0, clear);
    impl_->window->Render();  // renders into VTK's own frame, then blits it into fbo_ (bound)
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    impl_->window->GetShaderCache()->ReleaseCurrentShader();
}

Image VtkOffscreen::render() {
    renderToTexture();
    std::vector<unsigned char> rgba(size_t(width_) * height_ * 4);
    {
        GLStateGuard keep;
        glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glPixelStorei(GL_PACK_ROW_LENGTH, 0);
        glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    }
    Image image(width_, height_, 4);
    for (int y = 0; y < height_; ++y) {
        const unsigned char* row = rgba.data() + size_t(height_ - 1 - y) * width_ * 4;  // GL: bottom row first
        for (int i = 0; i < width_ * 4; ++i) image.data[size_t(y) * width_ * 4 + i] = row[i] / 255.0f;
        // VTK clears with the renderer's background alpha (0 by default): the picture is opaque.
        for (int x = 0; x < width_; ++x) image.data[(size_t(y) * width_ + x) * 4 + 3] = 1.0f;
    }
    return image;
}

void VtkOffscreen::exportVector(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    GLStateGuard keep;
    impl_->window->GetShaderCache()->ReleaseCurrentShader();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    if (ext == ".svg") {
        vtkNew<vtkSVGExporter> exporter;
        exporter->SetRenderWindow(impl_->window);
        exporter->SetFileName(path.c_str());
        exporter->Write();
    } else if (ext == ".pdf") {
        vtkNew<vtkPDFExporter> exporter;
        exporter->SetRenderWindow(impl_->window);
        exporter->SetFileName(path.c_str());
        exporter->Write();
    } else {
        throw InputError("vector export: expected a .svg or .pdf file, got '" + path + "'");
    }
    impl_->window->GetShaderCache()->ReleaseCurrentShader();
}

}  // namespace shadowlab
