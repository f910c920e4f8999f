// What `pcss` shares with `sssm`: the light's width as eq. 1 uses it, and the Poisson disk.
#pragma once
#include <array>
#include <glm/glm.hpp>

#include <string>

#include "graph/technique.h"
#include "scene/scene.h"

namespace shadowlab {

// w_light of buades2015 eq. 1 in world units: a square light's width, a disk's or sphere's
// diameter; 0 for a point light.
float lightWidthWorld(const Light& light);

// 32 points of a Poisson disk in the unit disk (minimum distance 0.25), made once by dart throwing
// with a fixed hash sequence (shaders/shared/light_sampling.glsl), so every run uses the same set.
const std::array<glm::vec2, 32>& poissonDisk32();

// The kernel caps of buades2015 (n for the blocker search, m for the filter), one table row each.
ParamDesc blockerKernelParam();
ParamDesc filterKernelParam(const std::string& unit);
// The shadow-map parameters of pcss and sssm: shadowMapParams() with sm_size 512 (see pcss.cpp).
std::vector<ParamDesc> filteringShadowMapParams();
// PCSS's capped kernel: the filter kernel m of eq. 1 (TechniqueDesc::kernelCaps).
KernelCapDesc pcssFilterKernelCap();

}  // namespace shadowlab

namespace shadowlab {

// Stencil marks shared by pcss and sssm (shaders/pcss/mark.frag): a frame-size DEPTH32F_STENCIL8
// resource whose stencil says which pixels a draw has work for, tested before shading so that a CPU
// rasteriser skips whole groups of pixels (a branch inside the shader would not).
ResourceDesc markResource(const std::string& name, const std::string& doc);
// Draws mark.frag into the bound framebuffer (whose depth-stencil is the mark resource), colour
// writes off. where < 0: the stencil becomes 1 where the shader keeps the pixel; else, where the
// stencil equals `where` and the shader keeps the pixel, it becomes where + 1. channel < 0: keep
// pixels showing geometry; else pixels whose `marks` texel (bound to unit 4) has that channel above
// `above`.
void drawStencilMarks(PassContext& ctx, int where, int channel = -1, float above = 0.0f);
// Until endStencilTest(): draws shade only the pixels whose stencil equals `value`.
void beginStencilTest(int value);
void endStencilTest();

}  // namespace shadowlab
