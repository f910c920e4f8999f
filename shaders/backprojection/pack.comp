// guennebaud2007 sec. 6, pass two ("packs the selected penumbra pixels") with the per-block
// classification of its last paragraph: one invocation per block of BP_BLOCK x BP_BLOCK pixels
// counts its selected pixels (eq. 6 or forced); a block over BP_BLOCK_WHOLE of its pixels is
// processed whole (appended to the whole-block list; its skipped penumbra pixels become SEL_BLOCK),
// an empty one is skipped, and the selected pixels of the others are compacted into the pixel list
// in scan order: the block's count is its prefix sum, one atomic add reserves its range. In place of
// the paper's geometry shader and transform feedback. (One invocation walks its block: on llvmpipe
// a work group per block with a shared-memory scan costs more in barriers than it saves.)
#include "../shared/screen_selection.glsl"
layout(local_size_x = 8, local_size_y = 8) in;

layout(r32f, binding = 0) uniform image2D selection;
layout(r32f, binding = 1) uniform writeonly image2D occupancy;  // selected / block pixels
// counts: [0] pixels listed, [1..3] their dispatch, [4] whole blocks, [5..7] their dispatch,
// [8] compacted blocks, [9] skipped (empty) blocks, [10] selected pixels (eq. 6 or forced).
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) writeonly buffer PixelList { uint pixels[]; };       // x | y << 16
layout(std430, binding = 2) writeonly buffer BlockList { uint wholeBlocks[]; };  // block index

bool selectedCode(int code) { return code == SEL_SELECTED || code == SEL_FORCED; }

void main() {
    ivec2 size = imageSize(selection);
    ivec2 blocks = imageSize(occupancy);
    ivec2 b = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(b, blocks))) return;
    ivec2 lo = b * BP_BLOCK;
    ivec2 hi = min(lo + BP_BLOCK, size);
    uint selected = 0u;
    for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x)
            if (selectedCode(int(imageLoad(selection, ivec2(x, y)).r))) selected += 1u;
    int pixelsInBlock = (hi.x - lo.x) * (hi.y - lo.y);
    int cls = blockClass(int(selected), pixelsInBlock);
    imageStore(occupancy, b, vec4(float(selected) / float(pixelsInBlock)));
    atomicAdd(counts[10], selected);
    if (cls == 0) {
        atomicAdd(counts[9], 1u);
        return;
    }
    if (cls == 2) {
        wholeBlocks[atomicAdd(counts[4], 1u)] = uint(b.y * blocks.x + b.x);
        for (int y = lo.y; y < hi.y; ++y)
            for (int x = lo.x; x < hi.x; ++x)
                if (int(imageLoad(selection, ivec2(x, y)).r) == SEL_SKIPPED) imageStore(selection, ivec2(x, y), vec4(float(SEL_BLOCK)));
        return;
    }
    atomicAdd(counts[8], 1u);
    uint next = atomicAdd(counts[0], selected);
    for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x)
            if (selectedCode(int(imageLoad(selection, ivec2(x, y)).r))) {
                pixels[next] = uint(x) | (uint(y) << 16u);
                next += 1u;
            }
}
