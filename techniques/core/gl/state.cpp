#include "gl/state.h"

#include <string>

namespace shadowlab {

static void enable(GLenum capability, bool on) {
    if (on)
        glEnable(capability);
    else
        glDisable(capability);
}

void PipelineState::apply() const {
    enable(GL_DEPTH_TEST, depthTest);
    glDepthFunc(depthFunc);
    glDepthMask(depthWrite ? GL_TRUE : GL_FALSE);

    enable(GL_STENCIL_TEST, stencilTest);
    glStencilFuncSeparate(GL_FRONT, front.func, front.ref, front.readMask);
    glStencilFuncSeparate(GL_BACK, back.func, back.ref, back.readMask);
    glStencilMaskSeparate(GL_FRONT, front.writeMask);
    glStencilMaskSeparate(GL_BACK, back.writeMask);
    glStencilOpSeparate(GL_FRONT, front.stencilFail, front.depthFail, front.depthPass);
    glStencilOpSeparate(GL_BACK, back.stencilFail, back.depthFail, back.depthPass);

    enable(GL_BLEND, blend);
    glBlendEquation(blendEquation);
    glBlendFunc(blendSrc, blendDst);

    enable(GL_CULL_FACE, cull);
    glCullFace(cullFace);
    glFrontFace(frontFace);

    glColorMask(colorMask[0], colorMask[1], colorMask[2], colorMask[3]);
    glClipControl(GL_LOWER_LEFT, clipZeroToOne ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    enable(GL_DEPTH_CLAMP, depthClamp);
}

static std::string enumName(GLenum value) {
    switch (value) {
#define NAME(e) \
    case e: return #e;
        NAME(GL_NEVER) NAME(GL_LESS) NAME(GL_EQUAL) NAME(GL_LEQUAL) NAME(GL_GREATER) NAME(GL_NOTEQUAL)
        NAME(GL_GEQUAL) NAME(GL_ALWAYS) NAME(GL_KEEP) NAME(GL_ZERO) NAME(GL_REPLACE) NAME(GL_INCR)
        NAME(GL_DECR) NAME(GL_INVERT) NAME(GL_INCR_WRAP) NAME(GL_DECR_WRAP) NAME(GL_ONE)
        NAME(GL_SRC_COLOR) NAME(GL_ONE_MINUS_SRC_COLOR) NAME(GL_SRC_ALPHA) NAME(GL_ONE_MINUS_SRC_ALPHA)
        NAME(GL_DST_ALPHA) NAME(GL_ONE_MINUS_DST_ALPHA) NAME(GL_DST_COLOR) NAME(GL_ONE_MINUS_DST_COLOR)
        NAME(GL_CONSTANT_COLOR) NAME(GL_FUNC_ADD) NAME(GL_FUNC_SUBTRACT) NAME(GL_FUNC_REVERSE_SUBTRACT)
        NAME(GL_MIN) NAME(GL_MAX) NAME(GL_FRONT) NAME(GL_BACK) NAME(GL_FRONT_AND_BACK) NAME(GL_CW) NAME(GL_CCW)
#undef NAME
        default: return std::to_string(value);
    }
}

static nlohmann::json describeFace(const PipelineState::StencilFace& f) {
    return {{"func", enumName(f.func)},          {"ref", f.ref},
            {"readMask", f.readMask},            {"writeMask", f.writeMask},
            {"stencilFail", enumName(f.stencilFail)}, {"depthFail", enumName(f.depthFail)},
            {"depthPass", enumName(f.depthPass)}};
}

nlohmann::json PipelineState::describe() const {
    nlohmann::json j;
    j["depthTest"] = depthTest;
    j["depthFunc"] = enumName(depthFunc);
    j["depthWrite"] = depthWrite;
    j["stencilTest"] = stencilTest;
    j["stencilFront"] = describeFace(front);
    j["stencilBack"] = describeFace(back);
    j["blend"] = blend;
    j["blendEquation"] = enumName(blendEquation);
    j["blendSrc"] = enumName(blendSrc);
    j["blendDst"] = enumName(blendDst);
    j["cull"] = cull;
    j["cullFace"] = enumName(cullFace);
    j["frontFace"] = enumName(frontFace);
    j["colorMask"] = {colorMask[0], colorMask[1], colorMask[2], colorMask[3]};
    j["clipZeroToOne"] = clipZeroToOne;
    j["depthClamp"] = depthClamp;
    return j;
}

PipelineState PipelineState::fullscreen() { return PipelineState{}; }

PipelineState PipelineState::depthGreaterReversed() {
    PipelineState s;
    s.depthTest = true;
    s.depthFunc = GL_GREATER;
    s.clipZeroToOne = true;
    return s;
}

PipelineState PipelineState::depthLess() {
    PipelineState s;
    s.depthTest = true;
    s.depthFunc = GL_LESS;
    return s;
}

PipelineState PipelineState::additiveBlend() {
    PipelineState s;
    s.blend = true;
    s.blendSrc = GL_ONE;
    s.blendDst = GL_ONE;
    return s;
}

}  // namespace shadowlab
