// What `pcss` shares with `sssm`: the light's width as eq. 1 uses it, and the Poisson disk.
#pragma once
#include <array>
#include <glm/glm.hpp>

#include <string>

#include "technique.h"
#include "scene.h"

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

}  // namespace shadowlab
