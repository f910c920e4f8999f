// C++ prologue for the shared GLSL/C++ math (STYLE.md 4). The .glsl files in this folder are
// written in the common subset of GLSL 4.50 and C++20 with GLM: no out parameters, float literals
// with an f suffix, uint literals with a u suffix, functions marked SHARED_FN. Shaders include
// them through the include expander; C++ includes this header and calls them as
// shadowlab::shared::function(...), so unit tests run exactly the code the shaders run.
#pragma once
#include <cstdint>
#include <glm/glm.hpp>

namespace shadowlab::shared {
using namespace glm;
using uint = std::uint32_t;
#define SHARED_FN inline
#include "shared/backprojection.glsl"
#include "shared/discontinuity.glsl"
#include "shared/light_sampling.glsl"
#include "shared/penumbra.glsl"
#include "shared/penumbra_mask.glsl"
#include "shared/penumbra_volumes.glsl"
#include "shared/pull_push.glsl"
#include "shared/screen_selection.glsl"
#include "shared/shadow_projection.glsl"
#include "shared/soft_shadow_volumes.glsl"
#include "shared/spsm.glsl"
#include "shared/square_occluder.glsl"
#include "shared/tangent_plane.glsl"
#undef SHARED_FN
}  // namespace shadowlab::shared
