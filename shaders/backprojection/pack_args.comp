// The visibility pass's indirect dispatch over the list entries of blocks firstBlock .. endBlock - 1
// (row-major, pack.comp): 64 entries per group, in counts[1..3].
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 2) readonly buffer Offsets { uint offsets[]; };
uniform int firstBlock, endBlock, blockCount;
void main() {
    uint first = firstBlock < blockCount ? offsets[firstBlock] : counts[0];
    uint end = endBlock < blockCount ? offsets[endBlock] : counts[0];
    counts[1] = end > first ? (end - first + 63u) / 64u : 0u;
    counts[2] = 1u;
    counts[3] = 1u;
}
