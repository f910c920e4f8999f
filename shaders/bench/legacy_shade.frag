// BASELINE for benchmarks/fixed_cost.cpp: the shade pass as it was before core stage two.
// Shading (DESIGN.md section 3): albedo * (ambient + sum_l v_l * direct_l), linear RGB.
#include "../common/gbuffer_access.glsl"
#include "legacy_lights.glsl"
uniform float ambient;
layout(location = 0) out vec4 color;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (isBackground(pixel)) {
        color = vec4(0.05, 0.06, 0.08, 1.0);
        return;
    }
    vec3 p = worldPosition(pixel);
    vec4 n = texelFetch(gNormal, pixel, 0);
    vec3 albedo = texelFetch(gMaterial, pixel, 0).rgb;
    vec3 light = vec3(ambient);
    for (int i = 0; i < MAX_LIGHTS; ++i) {  // constant bound: see combine.frag
        if (i >= lightCount) break;
        float v = n.w == 0.0 ? 1.0 : lightVisibilityAt(i, pixel);
        vec3 toLight = normalize(lightPositions[i] - p);
        light += v * max(dot(n.xyz, toLight), 0.0) * lightRadiance[i];
    }
    color = vec4(albedo * light, 1.0);
}
