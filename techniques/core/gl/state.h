// Fixed-function state declared per pass. apply() sets every field, so nothing one pass sets leaks
// into the next: a pass states what it needs instead of undoing what others did.
#pragma once
#include <nlohmann/json.hpp>

#include "gl/loader.h"

namespace shadowlab {

struct PipelineState {
    // What the stencil test does for one face (front or back).
    struct StencilFace {
        GLenum func = GL_ALWAYS;
        GLint ref = 0;
        GLuint readMask = 0xFF;   // ANDed with ref and the stored value before func compares them
        GLuint writeMask = 0xFF;  // bits the ops may change
        GLenum stencilFail = GL_KEEP;
        GLenum depthFail = GL_KEEP;  // z-fail shadow volumes count here
        GLenum depthPass = GL_KEEP;  // z-pass shadow volumes count here (and every fragment when depth test is off)
    };

    bool depthTest = false;
    GLenum depthFunc = GL_LESS;
    bool depthWrite = true;  // glDepthMask: also masks glClear of the depth buffer
    bool stencilTest = false;
    StencilFace front, back;  // shadow volumes count front and back faces in opposite directions
    bool blend = false;
    GLenum blendEquation = GL_FUNC_ADD;
    GLenum blendSrc = GL_ONE;
    GLenum blendDst = GL_ZERO;
    bool cull = false;
    GLenum cullFace = GL_BACK;
    GLenum frontFace = GL_CCW;
    bool colorMask[4] = {true, true, true, true};
    // false: clip z in [-w, w] (GL's default); true: [0, w], used with reversed depth (glClipControl).
    bool clipZeroToOne = false;
    bool depthClamp = false;

    void apply() const;
    nlohmann::json describe() const;  // every field by name, GL enums as their names

    // Everything off: full-screen passes that write every pixel.
    static PipelineState fullscreen();
    // Reversed depth (depth 1 at the near plane; see fitLightView): test GREATER, clip z in [0, w].
    // Float depth keeps its precision far away when near maps to 1 (reed2015 "depth precision").
    static PipelineState depthGreaterReversed();
    // Ordinary depth-tested geometry: depth test LESS, depth write on.
    static PipelineState depthLess();
    // dst + src, for accumulating per-light or per-sample contributions.
    static PipelineState additiveBlend();
};

}  // namespace shadowlab
