// ssv, pass wedges (assarsson2004, "Fragment shaders"): the point of the pixel (from the
// G-buffer), the silhouette edge in its projection space, clipped in homogeneous space, divided,
// clipped to the light, and its signed coverage computed analytically
// (shared/soft_shadow_volumes.glsl), added to the V-buffer by additive blending.
#include "../common/gbuffer_access.glsl"
#include "../shared/soft_shadow_volumes.glsl"
layout(std430, binding = 0) readonly buffer SsvEdges {
    vec4 ssvEdges[];  // per edge: (a, weight), (b, 0) in the light frame
};
uniform mat4 lightViewFromWorld;  // the sub-light's frame
uniform int lightShape;       // BP_LIGHT_SQUARE or BP_LIGHT_DISK
uniform float lightHalfSize;  // w_l / 2 or r
uniform int vbufferDivisor;  // k: this texel of the reduced V-buffer is the frame's pixel k i + k / 2
flat in int edgeIndex;
layout(location = 0) out vec4 coverage;  // the colour mask keeps the sub-light's channel

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy) * vbufferDivisor + vbufferDivisor / 2;
    if (isBackground(pixel)) discard;
    vec4 v = lightViewFromWorld * vec4(worldPosition(pixel), 1.0);
    vec3 p = vec3(v.x, v.y, -v.z);
    vec3 nw = mat3(lightViewFromWorld) * worldNormal(pixel);
    vec3 n = vec3(nw.x, nw.y, -nw.z);
    vec4 a = ssvEdges[2 * edgeIndex];
    vec4 b = ssvEdges[2 * edgeIndex + 1];
    coverage = vec4(a.w * ssvEdgeCoverage(lightShape, p, n, a.xyz, b.xyz, lightHalfSize));
}
