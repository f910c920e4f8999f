#include "window/camera_control.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace shadowlab {

Camera orbitCamera(const Camera& camera, float yaw, float pitch) {
    Camera c = camera;
    glm::vec3 offset = camera.position - camera.target;
    float radius = glm::length(offset);
    if (radius <= 0.0f) return c;
    float theta = std::atan2(offset.x, offset.z) - yaw;          // azimuth about +y
    float phi = std::acos(std::clamp(offset.y / radius, -1.0f, 1.0f)) - pitch;  // from +y
    phi = std::clamp(phi, 0.05f, 3.09f);
    c.position = camera.target + radius * glm::vec3(std::sin(phi) * std::sin(theta), std::cos(phi),
                                                    std::sin(phi) * std::cos(theta));
    c.up = glm::vec3(0, 1, 0);
    return c;
}

Camera panCamera(const Camera& camera, float dxFraction, float dyFraction) {
    Camera c = camera;
    glm::vec3 forward = camera.target - camera.position;
    float distance = glm::length(forward);
    if (distance <= 0.0f) return c;
    forward /= distance;
    glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
    glm::vec3 up = glm::cross(right, forward);
    float viewHeight = 2.0f * distance * std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    glm::vec3 shift = (-dxFraction * right + dyFraction * up) * viewHeight;
    c.position += shift;
    c.target += shift;
    return c;
}

Camera zoomCamera(const Camera& camera, float factor) {
    Camera c = camera;
    glm::vec3 offset = camera.position - camera.target;
    float distance = glm::length(offset);
    if (distance <= 0.0f || !(factor > 0.0f)) return c;
    float next = std::clamp(distance * factor, 0.05f, 1000.0f);
    c.position = camera.target + offset * (next / distance);
    return c;
}

Ray cameraRay(const Camera& camera, float aspect, glm::vec2 point, glm::vec2 size) {
    glm::mat4 clipFromWorld = camera.clipFromView(aspect) * camera.viewFromWorld();
    glm::mat4 worldFromClip = glm::inverse(clipFromWorld);
    float nx = 2.0f * point.x / size.x - 1.0f;
    float ny = 1.0f - 2.0f * point.y / size.y;
    glm::vec4 a = worldFromClip * glm::vec4(nx, ny, -0.5f, 1.0f);
    glm::vec4 b = worldFromClip * glm::vec4(nx, ny, 0.5f, 1.0f);
    glm::vec3 pa = glm::vec3(a) / a.w, pb = glm::vec3(b) / b.w;
    Ray r;
    r.origin = camera.position;
    r.direction = glm::normalize(pb - pa);
    if (glm::dot(r.direction, camera.target - camera.position) < 0.0f) r.direction = -r.direction;
    return r;
}

std::optional<glm::vec2> projectToWindow(const Camera& camera, float aspect, const glm::vec3& world, glm::vec2 size) {
    glm::vec4 v = camera.viewFromWorld() * glm::vec4(world, 1.0f);
    if (v.z > -1e-4f) return std::nullopt;  // behind the camera (view space looks down -z)
    glm::vec4 clip = camera.clipFromView(aspect) * v;
    glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return glm::vec2((ndc.x * 0.5f + 0.5f) * size.x, (0.5f - ndc.y * 0.5f) * size.y);
}

std::optional<glm::vec3> intersectPlane(const Ray& ray, const glm::vec3& point, const glm::vec3& normal) {
    float denom = glm::dot(ray.direction, normal);
    if (std::abs(denom) < 1e-6f) return std::nullopt;
    float t = glm::dot(point - ray.origin, normal) / denom;
    if (t <= 0.0f) return std::nullopt;
    return ray.origin + t * ray.direction;
}

std::vector<glm::vec3> lightOutline(const Light& light) {
    std::vector<glm::vec3> points;
    if (light.isPoint()) return points;
    glm::vec3 right = light.right(), up = light.up;
    if (light.shape == LightShape::Square) {
        float h = 0.5f * light.size;
        for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
            points.push_back(light.position + h * (c.x * right + c.y * up));
    } else {
        for (int i = 0; i < 32; ++i) {
            float a = 6.2831853f * float(i) / 32.0f;
            points.push_back(light.position + light.size * (std::cos(a) * right + std::sin(a) * up));
        }
    }
    return points;
}

std::vector<glm::vec3> frustumCorners(const glm::vec3& apex, const Light& light, float tanHalfFov, float nearZ, float farZ) {
    std::vector<glm::vec3> corners;
    glm::vec3 right = light.right(), up = light.up, dir = light.direction;
    for (float z : {nearZ, farZ})
        for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
            corners.push_back(apex + z * dir + z * tanHalfFov * (c.x * right + c.y * up));
    return corners;
}

}  // namespace shadowlab
