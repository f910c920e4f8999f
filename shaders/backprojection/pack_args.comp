// The indirect dispatch arguments of the visibility pass from pack.comp's counts: the compacted
// pixels in groups of 64, the whole blocks one group each.
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Counts { uint counts[]; };
void main() {
    counts[1] = (counts[0] + 63u) / 64u;
    counts[2] = 1u;
    counts[3] = 1u;
    counts[5] = counts[4];
    counts[6] = 1u;
    counts[7] = 1u;
}
