// Test-only: writes the vertex count of a DrawArraysIndirectCommand on the GPU: three vertices (one
// full-screen triangle) per value above `threshold`.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Values { float values[]; };
layout(std430, binding = 1) buffer DrawArgs { uint vertexCount; uint instanceCount; uint first; uint baseInstance; };
uniform float threshold;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < uint(values.length()) && values[i] > threshold) atomicAdd(vertexCount, 3u);
}
