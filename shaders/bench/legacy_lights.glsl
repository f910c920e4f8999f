// BASELINE for benchmarks/fixed_cost.cpp: the light uniforms as they were before core stage two.
// The scene's lights for the frame passes (combine, shade): up to 8, each with its visibility.
#ifndef SHADOWLAB_LEGACY_LIGHTS_GLSL
#define SHADOWLAB_LEGACY_LIGHTS_GLSL
const int MAX_LIGHTS = 8;
uniform int lightCount;
uniform vec3 lightPositions[MAX_LIGHTS];
uniform vec3 lightRadiance[MAX_LIGHTS];   // colour * intensity
uniform sampler2D lightVisibility[MAX_LIGHTS];

// Unshadowed direct light of light i at a receiver (Lambert, from the light's centre).
float directWeight(int i, vec3 p, vec3 n) {
    vec3 toLight = normalize(lightPositions[i] - p);
    vec3 radiance = lightRadiance[i];
    return max(dot(n, toLight), 0.0) * (radiance.r + radiance.g + radiance.b) / 3.0;
}

float lightVisibilityAt(int i, ivec2 pixel) {
    // A light that casts no shadow binds a 1x1 texture holding 1.
    ivec2 size = textureSize(lightVisibility[i], 0);
    return texelFetch(lightVisibility[i], min(pixel, size - 1), 0).r;
}
#endif
