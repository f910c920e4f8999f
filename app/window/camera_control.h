// Camera and light manipulation in the window: orbit, pan and zoom about the camera's target, and
// rays through window pixels (for dragging the light and picking). Pure math, no GL, no GLFW.
#pragma once
#include <glm/glm.hpp>
#include <optional>

#include "scene/scene.h"

namespace shadowlab {

// Orbit about camera.target: dx, dy in radians (yaw about world up, pitch clamped short of the poles).
Camera orbitCamera(const Camera& camera, float yaw, float pitch);
// Pan: moves position and target in the view plane by fractions of the view's height at the target.
Camera panCamera(const Camera& camera, float dxFraction, float dyFraction);
// Zoom: scales the distance to the target by `factor` (> 0), kept in [0.05, 1000].
Camera zoomCamera(const Camera& camera, float factor);

struct Ray {
    glm::vec3 origin;
    glm::vec3 direction;  // unit
};
// The ray through the window point (x, y from the top-left, in [0,w] x [0,h]).
Ray cameraRay(const Camera& camera, float aspect, glm::vec2 point, glm::vec2 size);
// Where a world point lands in the window (x, y from the top-left); nullopt behind the camera.
std::optional<glm::vec2> projectToWindow(const Camera& camera, float aspect, const glm::vec3& world, glm::vec2 size);
// Intersection of a ray with the plane through `point` with normal `normal`; nullopt if parallel or behind.
std::optional<glm::vec3> intersectPlane(const Ray& ray, const glm::vec3& point, const glm::vec3& normal);

// The light's outline in world space: 4 corners of a square, 32 points of a disk (sphere: its
// silhouette disk facing the light's direction); empty for a point light.
std::vector<glm::vec3> lightOutline(const Light& light);
// The 8 corners of a light frustum (near then far, in the order -x-y, +x-y, +x+y, -x+y).
std::vector<glm::vec3> frustumCorners(const glm::vec3& apex, const Light& light, float tanHalfFov, float nearZ, float farZ);

}  // namespace shadowlab
