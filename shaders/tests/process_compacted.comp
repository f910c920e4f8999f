// Test-only, step 3 of 3: dispatched indirectly over the compacted pixels alone; writes 2 v + 1 at
// each and counts the invocations and groups that did run.
layout(local_size_x = 64) in;
layout(std430, binding = 1) readonly buffer Compacted { uint pixels[]; };
layout(std430, binding = 2) readonly buffer Count { uint compactedCount; };
layout(std430, binding = 4) buffer Work { uint invocationsWithWork; uint groupsRun; };
layout(r32f, binding = 0) uniform readonly image2D values;
layout(r32f, binding = 1) uniform writeonly image2D results;

void main() {
    if (gl_LocalInvocationIndex == 0u) atomicAdd(groupsRun, 1u);
    uint i = gl_GlobalInvocationID.x;
    if (i >= compactedCount) return;
    ivec2 p = ivec2(pixels[i] & 0xFFFFu, pixels[i] >> 16);
    imageStore(results, p, vec4(2.0 * imageLoad(values, p).r + 1.0));
    atomicAdd(invocationsWithWork, 1u);
}
