// Test-only: evaluates the shared GLSL/C++ math (shaders/shared/) on a list of inputs, hard cases
// included, so that tests/hard_cases/test_hard_cases.cpp compares the GPU with the same source run in C++.
layout(local_size_x = 64) in;
#include "../shared/light_sampling.glsl"
#include "../shared/shadow_projection.glsl"
#include "../shared/square_occluder.glsl"

struct Case {
    vec4 a;   // p.xyz, occluderHalf
    vec4 b;   // occluderY, lightY, lightWidth, cosTheta
    vec4 c;   // texelWorld, constTexels, slopeTexels, offsetTexels
    uvec4 d;  // sample i, sample n, seed, hash input
};
struct Result {
    vec4 closedForm;  // squareOccluderVisibility, shadowDepthBias, receiverPlaneBias, intervalOverlap
    vec4 coord;       // shadowMapCoord(lightViewFromWorld, lightClipFromView, p)
    vec4 sampleUvw;   // stratifiedSample(i, n, seed), w = shadowTexelWorldSize(p.y, c.x, 1024)
    vec4 disk;        // concentricSquareToDisk(sample.uv), lightSampleOffset(disk, lightWidth, sample.uv)
    uvec4 hash;       // pcgHash(d.w), strataRows(n)
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
uniform mat4 lightViewFromWorld;
uniform mat4 lightClipFromView;
uniform uint count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) {
        return;
    }
    Case k = cases[i];
    Result r;
    r.closedForm = vec4(squareOccluderVisibility(k.a.xyz, k.a.w, k.b.x, k.b.y, k.b.z),
                        shadowDepthBias(k.c.x, k.c.y, k.c.z, k.b.w), receiverPlaneBias(k.c.x, k.b.w, k.c.w),
                        intervalOverlap(k.a.x, k.a.y, -0.5f * k.b.z, 0.5f * k.b.z));
    r.coord = shadowMapCoord(lightViewFromWorld, lightClipFromView, k.a.xyz);
    vec3 s = stratifiedSample(k.d.x, k.d.y, k.d.z);
    r.sampleUvw = vec4(s, shadowTexelWorldSize(k.a.y, k.c.x, 1024.0f));
    r.disk = vec4(concentricSquareToDisk(s.xy), lightSampleOffset(LIGHT_SHAPE_DISK, k.b.z, s.xy));
    r.hash = uvec4(pcgHash(k.d.w), strataRows(k.d.y), 0u, 0u);
    results[i] = r;
}
