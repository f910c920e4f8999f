// What the three SSSM steps share (buades2015 sec. 4): the camera, the receiver's tangent plane
// (the beta criterion and the shadow-map fallback of the screen-space blur), the light's size.
#ifndef SHADOWLAB_SSSM_COMMON_GLSL
#define SHADOWLAB_SSSM_COMMON_GLSL
#include "../common/gbuffer_access.glsl"
#include "../pcss/pcss_common.glsl"

uniform mat4 cameraViewFromWorld;
uniform mat4 cameraWorldFromView;
uniform float cameraTanHalfFovY;
uniform float cameraAspect;
uniform vec2 viewportSize;  // pixels

float cameraDepth(vec3 world) { return -(cameraViewFromWorld * vec4(world, 1.0)).z; }

vec2 pixelNdc(vec2 pixelCentre) { return pixelCentre / viewportSize * 2.0 - 1.0; }

bool onScreen(ivec2 q) { return q.x >= 0 && q.y >= 0 && q.x < int(viewportSize.x) && q.y < int(viewportSize.y); }

// The shaded pixel's surface: its point and normal, in world and view space.
struct Surface {
    vec3 world;
    vec3 normal;  // world
    vec3 pView;
    vec3 nView;
};

Surface surfaceAt(ivec2 pixel) {
    Surface s;
    s.world = worldPosition(pixel);
    s.normal = worldNormal(pixel);
    s.pView = (cameraViewFromWorld * vec4(s.world, 1.0)).xyz;
    s.nView = normalize(mat3(cameraViewFromWorld) * s.normal);
    return s;
}

// View-space point of the surface's tangent plane seen through a pixel centre (the surface's own
// point when the plane is grazing there).
vec3 tangentPlaneView(Surface s, vec2 pixelCentre) {
    vec2 ndc = pixelNdc(pixelCentre);
    float t = tangentPlaneDepth(s.pView, s.nView, ndc, cameraTanHalfFovY, cameraAspect);
    if (t < 0.0) return s.pView;
    return vec3(ndc.x * cameraTanHalfFovY * cameraAspect, ndc.y * cameraTanHalfFovY, -1.0) * t;
}

// World length one pixel step along `axis` covers on the surface's tangent plane.
float worldPerPixel(Surface s, ivec2 pixel, vec2 axis) {
    vec2 c = vec2(pixel) + 0.5;
    return length(tangentPlaneView(s, c + 0.5 * axis) - tangentPlaneView(s, c - 0.5 * axis));
}

// The beta criterion (reuseShadowRow): pixel q is on screen, shows geometry, and its camera depth
// is within beta of the depth the surface's tangent plane has there.
bool showsSurface(Surface s, ivec2 q, float beta) {
    if (!onScreen(q) || isBackground(q)) return false;
    vec2 ndc = pixelNdc(vec2(q) + 0.5);
    float plane = tangentPlaneDepth(s.pView, s.nView, ndc, cameraTanHalfFovY, cameraAspect);
    return plane > 0.0 && reuseShadowRow(cameraDepth(worldPosition(q)), plane, beta);
}

// Hard shadow of the surface's tangent plane at a pixel, from the shadow map: what the screen
// does not hold (another object in front, the viewport's border) is "directly sampled" there.
float hardShadowOnPlane(Surface s, vec2 pixelCentre) {
    vec3 world = (cameraWorldFromView * vec4(tangentPlaneView(s, pixelCentre), 1.0)).xyz;
    return shadowTest(world, s.normal);
}
#endif
