// Test-only: evaluates the shared GLSL/C++ math on a grid of inputs, one pixel each, so that
// tests/techniques/test_shared_math_gpu.cpp can compare the GPU's results with the same functions in C++.
#include "../shared/light_sampling.glsl"
#include "../shared/shadow_projection.glsl"
#include "../shared/square_occluder.glsl"
uniform mat4 lightViewFromWorld;
uniform mat4 lightClipFromView;
layout(location = 0) out vec4 outSquare;   // closed form at 4 light widths
layout(location = 1) out vec4 outSample;   // stratifiedSample(i = x, n = y + 1, seed 7), disk.x
layout(location = 2) out vec4 outProject;  // shadowMapCoord of a grid point
layout(location = 3) out uint outHash;     // pcgHash(x + 64 y)

void main() {
    ivec2 c = ivec2(gl_FragCoord.xy);
    vec3 p = vec3(-3.0f + 6.0f * float(c.x) / 63.0f, 0.0f, -3.0f + 6.0f * float(c.y) / 63.0f);
    outSquare = vec4(squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 1.0f), squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 0.0f),
                     squareOccluderVisibility(p, 0.5f, 2.0f, 4.0f, 2.5f), squareOccluderVisibility(p, 0.25f, 1.0f, 4.0f, 1e-3f));
    vec3 s = stratifiedSample(uint(c.x), uint(c.y + 1), 7u);
    outSample = vec4(s, concentricSquareToDisk(s.xy).x);
    outProject = shadowMapCoord(lightViewFromWorld, lightClipFromView, p + vec3(0.0f, float(c.x % 3), 0.0f));
    outHash = pcgHash(uint(c.x + 64 * c.y));
}
