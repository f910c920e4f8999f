// The visibility pass over the pixels sec. 6 packed (screen_adaptive on): a compute shader over a
// range of the packed list (pack.comp: the blocks processed whole and the compacted pixels of the
// others, ordered by blocks in row-major order): blocks firstBlock .. endBlock - 1, the whole frame
// or the blocks of the band of rows refineFrame asks for. Each listed pixel runs pixelVisibility
// (visibility_levels.glsl) and stores (v, 1) at its own place in the sparse v-buffer: the paper's
// fourth pass ("unpacks the data at their original position") is this store. Only pixels inside
// `band` (x0, y0, x1, y1) are evaluated. The technique's main file includes visibility_common.glsl
// and its area file before this one.
#include "../shared/screen_selection.glsl"
layout(local_size_x = 64) in;
uniform ivec4 band;
uniform int firstBlock, endBlock, blockCount;
layout(rg32f, binding = 0) uniform writeonly image2D sparse;
#ifdef LIGHT_MULTIRES
layout(rgba32f, binding = 1) uniform writeonly image2D lightLevelsImage;
#endif
layout(std430, binding = 0) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 1) readonly buffer PixelList { uint pixels[]; };
layout(std430, binding = 2) readonly buffer Offsets { uint offsets[]; };

void evaluate(ivec2 p) {
    if (p.x < band.x || p.y < band.y || p.x >= band.z || p.y >= band.w) return;
    chosenLambda = -1.0;
    chosenLevels = vec3(-1.0, -1.0, 0.0);
    float v = pixelVisibility(p);
    imageStore(sparse, p, vec4(v, 1.0, 0.0, 0.0));
#ifdef LIGHT_MULTIRES
    imageStore(lightLevelsImage, p, vec4(chosenLambda, chosenLevels));
#endif
}

void main() {
    uint first = firstBlock < blockCount ? offsets[firstBlock] : counts[0];
    uint end = endBlock < blockCount ? offsets[endBlock] : counts[0];
    uint i = first + gl_GlobalInvocationID.x;
    if (i >= end) return;
    uint entry = pixels[i];
    evaluate(ivec2(int(entry & 0xffffu), int(entry >> 16u)));
}
