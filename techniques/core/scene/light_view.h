// The light's view: the frustum of a shadow map rendered from a point of the light, fitted to the
// scene's bounds (reversed depth, see fitLightView).
#pragma once
#include <glm/glm.hpp>

#include "scene/scene.h"

namespace shadowlab {

// The frustum of a shadow map rendered from `position` with the light's orientation, fitted to the
// world bounds of the scene: symmetric, half-angle atan(tanHalfFov) at most 80 degrees, depth range
// [nearZ, farZ] in world units along the light's axis.
struct LightView {
    glm::vec3 position{0.0f};
    glm::mat4 viewFromWorld{1.0f};
    glm::mat4 clipFromView{1.0f};
    float tanHalfFov = 1.0f;
    float nearZ = 0.1f;
    float farZ = 100.0f;
};
LightView fitLightView(const Light& light, const glm::vec3& position, const Bounds& bounds);

}  // namespace shadowlab
