// TEMPORARY: stands in for the GPU-feature API (Format, PipelineState) until it lands in gl_util.h.
#pragma once
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gl_util.h"

namespace shadowlab {
struct PipelineState {
    bool depthTest = false;
    GLenum depthFunc = GL_LESS;
    bool blend = false;
    bool clipZeroToOne = false;
    void apply() const {
        if (depthTest) glEnable(GL_DEPTH_TEST); else glDisable(GL_DEPTH_TEST);
        glDepthFunc(depthFunc);
        if (blend) glEnable(GL_BLEND); else glDisable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFunc(GL_ONE, blend ? GL_ONE : GL_ZERO);
        glDisable(GL_CULL_FACE);
        glClipControl(GL_LOWER_LEFT, clipZeroToOne ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    }
    static PipelineState fullscreen() { return {}; }
    static PipelineState depthGreaterReversed() { PipelineState s; s.depthTest = true; s.depthFunc = GL_GREATER; s.clipZeroToOne = true; return s; }
    static PipelineState additiveBlend() { PipelineState s; s.blend = true; return s; }
    nlohmann::json describe() const { return {{"depth_test", depthTest}, {"blend", blend}}; }
};
}  // namespace shadowlab
