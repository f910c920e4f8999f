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
// Camera view space to the light: lightClipFromView * lightViewFromWorld * cameraWorldFromView, and
// minus the z row of lightViewFromWorld * cameraWorldFromView (a point's light depth z = dot(row, h)
// for a homogeneous h with w = 1).
uniform mat4 lightClipFromCameraView;
uniform vec4 lightDepthFromCameraView;

float cameraDepth(vec3 world) { return -(cameraViewFromWorld * vec4(world, 1.0)).z; }

vec2 pixelNdc(vec2 pixelCentre) { return pixelCentre / viewportSize * 2.0 - 1.0; }

bool onScreen(ivec2 q) { return q.x >= 0 && q.y >= 0 && q.x < int(viewportSize.x) && q.y < int(viewportSize.y); }

// The shaded pixel's surface: its point and normal, and its tangent plane as functions of the pixel
// q = (x, y, 1). The plane's inverse camera depth is affine in q (planeInverseDepth), so the plane
// point under q has the homogeneous view position h(q) = (ray direction(q), 1 / depth(q)), linear in
// q; its light clip position and light depth are then linear in q too (a homography). Each tap of a
// kernel gets the plane's depth, or its shadow-map look-up, with a few multiply-adds.
struct Surface {
    ivec2 pixel;
    vec3 world;
    vec3 normal;               // world
    vec3 invDepthFromPixel;    // 1 / plane depth = dot(this, q)
    mat3x4 lightClipFromPixel; // light clip position of the plane point under q (homogeneous)
    vec3 lightDepthFromPixel;  // light depth times 1 / camera depth, = dot(this, q)
    float bias;                // the pixel's depth bias (world), for the plane's look-ups
    float hard;                // the pixel's own hard shadow
};

Surface surfaceAt(ivec2 pixel, float hard) {
    Surface s;
    s.pixel = pixel;
    s.world = worldPosition(pixel);
    s.normal = worldNormal(pixel);
    s.hard = hard;
    vec3 pView = (cameraViewFromWorld * vec4(s.world, 1.0)).xyz;
    vec3 nView = normalize(mat3(cameraViewFromWorld) * s.normal);
    vec2 ndc0 = pixelNdc(vec2(pixel) + 0.5);
    vec3 inv = planeInverseDepth(pView, nView, ndc0, cameraTanHalfFovY, cameraAspect);
    vec2 invStep = inv.yz * 2.0 / viewportSize;  // d ndc / d pixel = 2 / size
    s.invDepthFromPixel = vec3(invStep, inv.x - dot(invStep, vec2(pixel)));
    s.bias = 0.0;
    s.lightClipFromPixel = mat3x4(0.0);
    s.lightDepthFromPixel = vec3(0.0);
    return s;
}

// What hardShadowOnPlane needs besides the plane: the pixel's bias and the homography from pixels
// to the light.
Surface withLightLookups(Surface s) {
    s.bias = prepareShadowReceiver(s.world, s.normal).bias;
    // Ray direction under pixel q (centre q + 0.5): (ndc.x tan aspect, ndc.y tan, -1), affine in q.
    float tx = cameraTanHalfFovY * cameraAspect, ty = cameraTanHalfFovY;
    mat3x4 hFromPixel = mat3x4(vec4(2.0 * tx / viewportSize.x, 0.0, 0.0, s.invDepthFromPixel.x),
                               vec4(0.0, 2.0 * ty / viewportSize.y, 0.0, s.invDepthFromPixel.y),
                               vec4(tx * (1.0 / viewportSize.x - 1.0), ty * (1.0 / viewportSize.y - 1.0), -1.0,
                                    s.invDepthFromPixel.z));
    s.lightClipFromPixel = lightClipFromCameraView * hFromPixel;
    s.lightDepthFromPixel = lightDepthFromCameraView * hFromPixel;
    return s;
}

// Camera depth of the surface's tangent plane under pixel q (-1: the plane is behind that ray).
float planeDepth(Surface s, ivec2 q) {
    float inv = dot(s.invDepthFromPixel, vec3(vec2(q), 1.0));
    return inv > 0.0 ? 1.0 / inv : -1.0;
}

// View-space point of the tangent plane under a pixel centre (the surface's own point when the
// plane is behind that ray).
vec3 tangentPlaneView(Surface s, ivec2 q) {
    float depth = planeDepth(s, q);
    if (depth < 0.0) return (cameraViewFromWorld * vec4(s.world, 1.0)).xyz;
    vec2 ndc = pixelNdc(vec2(q) + 0.5);
    return vec3(ndc.x * cameraTanHalfFovY * cameraAspect, ndc.y * cameraTanHalfFovY, -1.0) * depth;
}

// World length one pixel step along `axis` covers on the surface's tangent plane.
float worldPerPixel(Surface s, ivec2 axis) {
    return 0.5 * length(tangentPlaneView(s, s.pixel + axis) - tangentPlaneView(s, s.pixel - axis));
}

// The beta criterion (reuseShadowRow): pixel q shows geometry whose camera depth (`depth`, step 1's
// hard_shadow.g, <= 0 on background) is within beta of the surface's tangent plane there.
bool showsSurface(Surface s, ivec2 q, float depth, float beta) {
    float plane = planeDepth(s, q);
    return depth > 0.0 && plane > 0.0 && reuseShadowRow(depth, plane, beta);
}

// Hard shadow of the surface's tangent plane under pixel q, from the shadow map: what the screen
// does not hold (another object in front, the viewport's border) is "directly sampled" there. The
// plane point's light depth is exact, so the pixel's own bias serves (no receiver-plane term).
// A plane point outside the light's frustum reads the map's border texel, as PCF's taps do: the
// frustum holds every caster unless its angle is capped (80 degrees, scene/light_view.cpp), and
// when it is (a caster almost at the light) the border texel continues the shadow that "lit"
// there would cut off. A wide blur's taps reach far along a receding plane: with "lit", m = 127
// gave the occluder-at-the-light hard case RMSE 0.081 against 0.0076 with the border texel.
float hardShadowOnPlane(Surface s, ivec2 q) {
    vec3 qh = vec3(vec2(q), 1.0);
    float inv = dot(s.invDepthFromPixel, qh);
    if (inv <= 0.0) return s.hard;  // the plane is behind this ray: keep the pixel's own value
    vec4 clip = s.lightClipFromPixel * qh;
    if (clip.w <= 0.0) return 1.0;  // behind the light: lit, as shadowMapCoord
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float z = dot(s.lightDepthFromPixel, qh) / inv;
    int last = int(shadowMapSize) - 1;
    ivec2 texel = clamp(ivec2(floor(uv * shadowMapSize)), ivec2(0), ivec2(last));
    return shadowDepthTest(z, texelFetch(shadowMap, texel, 0).r, s.bias);
}

// Marks bit i (0 <= i < 128) of a 128-bit set. Selects, not set[i >> 5]: an index that differs
// between the pixels of a group is slow on a CPU rasteriser.
uvec4 markBit(uvec4 set, int i) {
    uint bit = 1u << uint(i & 31);
    int w = i >> 5;
    return set | uvec4(w == 0 ? bit : 0u, w == 1 ? bit : 0u, w == 2 ? bit : 0u, w == 3 ? bit : 0u);
}

// Removes the lowest bit of a non-empty set and returns its index. Walking a set with
// `while (any(notEqual(set, uvec4(0u)))) i = takeLowestBit(set);` costs a group of pixels on a CPU
// rasteriser (which runs all branches of a group) as many turns as its fullest set, where
// `if (missed) work` inside a loop would cost one turn per element any pixel missed.
int takeLowestBit(inout uvec4 set) {
    bool inX = set.x != 0u;
    bool inY = !inX && set.y != 0u;
    bool inZ = !inX && !inY && set.z != 0u;
    bool inW = !inX && !inY && !inZ;
    uint bits = inX ? set.x : (inY ? set.y : (inZ ? set.z : set.w));
    int base = inX ? 0 : (inY ? 32 : (inZ ? 64 : 96));
    uint rest = bits & (bits - 1u);
    set = uvec4(inX ? rest : set.x, inY ? rest : set.y, inZ ? rest : set.z, inW ? rest : set.w);
    return base + findLSB(bits);
}
#endif
