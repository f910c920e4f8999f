// Test-only, step 2 of 3: turns the compacted count into a DispatchIndirectCommand, one group per
// `groupSize` compacted pixels, so the next dispatch runs over them alone.
layout(local_size_x = 1) in;
layout(std430, binding = 2) readonly buffer Count { uint compactedCount; };  // the atomic counter's buffer
layout(std430, binding = 3) writeonly buffer DispatchArgs { uint numGroups[3]; };
uniform uint groupSize;

void main() {
    numGroups[0] = (compactedCount + groupSize - 1u) / groupSize;
    numGroups[1] = 1u;
    numGroups[2] = 1u;
}
