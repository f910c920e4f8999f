// Test-only, step 1 of 3: stream compaction. Every pixel above `threshold` appends its coordinates
// to `pixels` at a slot taken from an atomic counter (order is arbitrary).
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = 0) uniform readonly image2D values;
layout(binding = 0) uniform atomic_uint compactedCount;
layout(std430, binding = 1) writeonly buffer Compacted { uint pixels[]; };  // x | y << 16
uniform float threshold;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(values)))) return;
    if (imageLoad(values, p).r > threshold) {
        uint slot = atomicCounterIncrement(compactedCount);
        pixels[slot] = uint(p.x) | (uint(p.y) << 16);
    }
}
