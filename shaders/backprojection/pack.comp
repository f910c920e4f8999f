// guennebaud2007 sec. 6, pass two ("packs the selected penumbra pixels") with the per-block
// classification of its last paragraph, in three dispatches (PACK_STEP):
//  1 (COUNT): one invocation per block of BP_BLOCK x BP_BLOCK pixels counts its selected pixels
//    (eq. 6 or forced). A block over BP_BLOCK_WHOLE of its pixels is processed whole: all its
//    penumbra pixels are evaluated (the skipped ones become SEL_BLOCK); an empty block is skipped;
//    the others keep their selected pixels. Each block's number of entries goes to `offsets`.
//  2 (SCAN): one invocation turns the counts into an exclusive prefix sum over the blocks in
//    row-major order (the total in counts[0]).
//  3 (WRITE): each block writes its pixels at its offset, in scan order.
// The list is thus ordered by block rows, so a band of rows (the window's refineFrame) evaluates a
// contiguous range of it. In place of the paper's geometry shader and transform feedback.
#include "../shared/screen_selection.glsl"
#if PACK_STEP == 2
layout(local_size_x = 1) in;
#else
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = 0) uniform image2D selection;
layout(r32f, binding = 1) uniform writeonly image2D occupancy;  // selected / block pixels
#endif
// counts: [0] pixels listed, [1..3] a dispatch's arguments (the visibility pass's), [4] blocks
// processed whole, [8] compacted blocks, [9] skipped (empty) blocks, [10] selected pixels.
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) buffer PixelList { uint pixels[]; };  // x | y << 16
layout(std430, binding = 2) buffer Offsets { uint offsets[]; };   // per block, row-major
uniform ivec2 blocks;  // blocks across and down

bool selectedCode(int code) { return code == SEL_SELECTED || code == SEL_FORCED; }
bool penumbraCode(int code) { return code == SEL_SELECTED || code == SEL_FORCED || code == SEL_SKIPPED || code == SEL_BLOCK; }

void main() {
#if PACK_STEP == 2
    uint sum = 0u;
    int n = blocks.x * blocks.y;
    for (int b = 0; b < n; ++b) {
        uint c = offsets[b];
        offsets[b] = sum;
        sum += c;
    }
    counts[0] = sum;
#else
    ivec2 size = imageSize(selection);
    ivec2 b = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(b, blocks))) return;
    uint index = uint(b.y * blocks.x + b.x);
    ivec2 lo = b * BP_BLOCK;
    ivec2 hi = min(lo + BP_BLOCK, size);
#if PACK_STEP == 1
    uint selected = 0u, penumbra = 0u;
    for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x) {
            int code = int(imageLoad(selection, ivec2(x, y)).r);
            if (selectedCode(code)) selected += 1u;
            if (penumbraCode(code)) penumbra += 1u;
        }
    int pixelsInBlock = (hi.x - lo.x) * (hi.y - lo.y);
    int cls = blockClass(int(selected), pixelsInBlock);
    imageStore(occupancy, b, vec4(float(selected) / float(pixelsInBlock)));
    atomicAdd(counts[10], selected);
    atomicAdd(counts[cls == 2 ? 4 : (cls == 1 ? 8 : 9)], 1u);
    offsets[index] = cls == 2 ? penumbra : (cls == 1 ? selected : 0u);
    if (cls == 2)
        for (int y = lo.y; y < hi.y; ++y)
            for (int x = lo.x; x < hi.x; ++x)
                if (int(imageLoad(selection, ivec2(x, y)).r) == SEL_SKIPPED) imageStore(selection, ivec2(x, y), vec4(float(SEL_BLOCK)));
#else
    uint next = offsets[index];
    for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x)
            if (selectionEvaluated(int(imageLoad(selection, ivec2(x, y)).r))) {
                pixels[next] = uint(x) | (uint(y) << 16u);
                next += 1u;
            }
#endif
#endif
}
