// Test-only: evaluates shaders/shared/backprojection.glsl on a grid of inputs, one pixel each, so
// tests/techniques/test_backprojection_gpu.cpp can compare the GPU's results with the same functions in C++.
// Edge inputs come from a texture the test fills, so both sides start from the same bits.
#include "../shared/backprojection.glsl"
uniform sampler2D edges;  // (a.x, a.y, b.x, b.y) per pixel
layout(location = 0) out vec4 outRule;      // contourEdge(mask, t, which)
layout(location = 1) out vec4 outArea;      // edgeOccludedArea square, disk; rectOccludedArea disk; inside test
layout(location = 2) out vec4 outProject;   // backprojectToLight (x, y), hsmKernelTexels, receiverPlaneDepth
layout(location = 3) out vec4 outSweep;     // radialSweep square, disk; clipSegmentToDisk (s0, s1)

void main() {
    ivec2 c = ivec2(gl_FragCoord.xy);
    int mask = c.x % 16;
    int which = (c.x / 16) % 2;
    float t = -1.0f + 2.0f * float(c.y % 9) / 8.0f;
    outRule = which < contourRule(mask).x ? contourEdge(mask, t, which) : vec4(-9.0f);
    vec4 e = texelFetch(edges, c, 0);
    vec2 a = vec2(e.x, e.y);
    vec2 b = vec2(e.z, e.w);
    vec4 rect = vec4(min(a.x, b.x), min(a.y, b.y), max(a.x, b.x), max(a.y, b.y));
    bool inside = contourCentreOccluded(mask, t, cross2(a, b), cross2(b, a + vec2(0.1f, 0.0f)));
    outArea = vec4(edgeOccludedArea(BP_LIGHT_SQUARE, a, b), edgeOccludedArea(BP_LIGHT_DISK, a, b),
                   rectOccludedArea(BP_LIGHT_DISK, rect), inside ? 1.0f : 0.0f);
    vec3 receiver = vec3(a.x, a.y, 3.0f + b.x);
    vec2 texel = vec2(float(c.x) * 4.0f + 0.5f, float(c.y) * 4.0f + 0.25f);
    vec2 l = backprojectToLight(receiver, texel, 1.0f + 0.5f * b.y, 256.0f, 0.75f, 0.5f);
    vec3 n = receiverNormalTowardLight(normalize(vec3(b.x, b.y, 1.0f)), receiver);
    outProject = vec4(l.x, l.y, hsmKernelTexels(1.0f, 256.0f, 0.75f, 1.0f + 0.5f * b.y, receiver.z),
                      receiverPlaneDepth(n, receiver, texel, 256.0f, 0.75f));
    vec2 clip = clipSegmentToDisk(a, b);
    outSweep = vec4(radialSweep(BP_LIGHT_SQUARE, a, b, edgeTurn(a, b)), radialSweep(BP_LIGHT_DISK, a, b, edgeTurn(a, b)),
                    clip.x, clip.y);
}
