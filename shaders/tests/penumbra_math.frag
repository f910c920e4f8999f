// Test-only: evaluates shaders/shared/penumbra.glsl on a grid, one pixel each, so that
// tests/techniques/test_pcss.cpp can compare the GPU's results with the same functions in C++.
#include "../shared/penumbra.glsl"
layout(location = 0) out vec4 outA;  // z_avg, penumbra width, search width, PCF kernel
layout(location = 1) out vec4 outB;  // alpha and beta criteria, kernel weight, tangent-plane depth

void main() {
    ivec2 c = ivec2(gl_FragCoord.xy);
    int x = c.x, y = c.y;
    float zr = 0.5f + 0.1f * float(y);
    float zb = 0.05f * float(x) - 0.2f;
    float lw = 0.02f * float(x % 16);
    vec2 acc = accumulateBlocker(accumulateBlocker(vec2(0.0f), zb, zr, 0.01f), zb + 0.3f, zr, 0.01f);
    float zAvg = averageBlockerDepth(acc);
    outA = vec4(zAvg, penumbraWidth(lw, zr, zAvg),
                blockerSearchWidthTexels(lw, zr, 0.3f + 0.01f * float(x), 0.8f, 64.0f + float(y), 29.0f),
                penumbraKernelTexels(penumbraWidth(lw, zr, zAvg), zr, 0.8f, 256.0f, 41.0f));
    outB = vec4(reuseBlockerRow(zr, zb, 0.02f * float(x % 8)) ? 1.0f : 0.0f,
                reuseShadowRow(zr, zb, 0.03f * float(y % 8)) ? 1.0f : 0.0f,
                kernelWeight(float(x % 21 - 10), 0.5f + 0.3f * float(y), y % 2, 0.5f),
                tangentPlaneDepth(vec3(0.1f, -1.0f, -4.0f), normalize(vec3(0.2f, 1.0f, 0.1f)),
                                  vec2(float(x) / 32.0f - 1.0f, float(y) / 32.0f - 1.0f), 0.4f, 1.3f));
}
