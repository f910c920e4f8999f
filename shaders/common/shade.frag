// The frame's visibility buffer and shading in one pass (DESIGN.md section 3):
//   v     = sum_l v_l E_l / sum_l E_l   (E_l: the unshadowed direct light of light l; with one light
//                                        v is that light's visibility exactly)
//   image = albedo * (ambient + sum_l v_l * max(n.l, 0) * radiance_l), linear RGB.
// Background and objects that receive no shadows get v = 1. Each pixel reads only what it needs:
// a background pixel reads its position and nothing else.
#include "gbuffer_access.glsl"
#include "lights.glsl"
uniform float ambient;
uniform sampler2D gShadingNormal;  // the interpolated normal; gNormal is the geometric one (gbuffer.frag)
layout(location = 0) out float visibility;
layout(location = 1) out vec4 color;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(gPosition, pixel, 0);
    if (position.w == 0.0) {
        visibility = 1.0;
        color = vec4(0.05, 0.06, 0.08, 1.0);
        return;
    }
    vec3 p = position.xyz;
    vec3 n = texelFetch(gShadingNormal, pixel, 0).xyz;
    bool receives = texelFetch(gNormal, pixel, 0).w != 0.0;
    vec3 albedo = texelFetch(gMaterial, pixel, 0).rgb;
    vec3 light = vec3(ambient);
    float weighted = 0.0, weights = 0.0, plain = 0.0;
#if LIGHT_COUNT > 0
    for (int i = 0; i < LIGHT_COUNT; ++i) {  // unrolled: LIGHT_COUNT is a compile-time constant
        float v = receives ? texelFetch(lightVisibility[i], min(pixel, textureSize(lightVisibility[i], 0) - 1), 0).r : 1.0;
        vec3 toLight = normalize(lightPositions[i] - p);
        float cosine = max(dot(n, toLight), 0.0);
        float e = directWeight(cosine, lightRadiance[i]);
        weighted += v * e;
        weights += e;
        plain += v;
        light += v * cosine * lightRadiance[i];
    }
    // A receiver facing away from every light: the plain mean keeps v defined.
    visibility = !receives ? 1.0 : weights > 0.0 ? weighted / weights : plain / float(LIGHT_COUNT);
#else
    visibility = 1.0;
#endif
    color = vec4(albedo * light, 1.0);
}
