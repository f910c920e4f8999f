// The visibility pass over the pixels sec. 6 packed (screen_adaptive on): a compute shader, run
// twice, over the whole blocks (WHOLE_BLOCKS: one work group of BP_BLOCK x BP_BLOCK per listed
// block, its evaluated pixels) and over the compacted pixel list (64 per group). Each evaluated
// pixel runs pixelVisibility (visibility_levels.glsl) and stores (v, 1) at its own place in the
// sparse v-buffer: the paper's fourth pass ("unpacks the data at their original position") is this
// store. Only pixels inside `band` (x0, y0, x1, y1; refineFrame's rows) are evaluated. The
// technique's main file includes visibility_common.glsl and its area file before this one.
#include "../shared/screen_selection.glsl"
#ifdef WHOLE_BLOCKS
layout(local_size_x = BP_BLOCK, local_size_y = BP_BLOCK) in;
#else
layout(local_size_x = 64) in;
#endif
uniform sampler2D selectionCodes;
uniform ivec4 band;
layout(rg32f, binding = 0) uniform writeonly image2D sparse;
#ifdef LIGHT_MULTIRES
layout(rgba32f, binding = 1) uniform writeonly image2D lightLevelsImage;
#endif
layout(std430, binding = 0) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 1) readonly buffer PixelList { uint pixels[]; };
layout(std430, binding = 2) readonly buffer BlockList { uint wholeBlocks[]; };

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
#ifdef WHOLE_BLOCKS
    uint block = wholeBlocks[gl_WorkGroupID.x];
    ivec2 size = textureSize(selectionCodes, 0);
    int blocksX = (size.x + BP_BLOCK - 1) / BP_BLOCK;
    ivec2 p = ivec2(int(block) % blocksX, int(block) / blocksX) * BP_BLOCK + ivec2(gl_LocalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y) return;
    if (!selectionEvaluated(int(texelFetch(selectionCodes, p, 0).r))) return;
    evaluate(p);
#else
    uint i = gl_GlobalInvocationID.x;
    if (i >= counts[0]) return;
    uint entry = pixels[i];
    evaluate(ivec2(int(entry & 0xffffu), int(entry >> 16u)));
#endif
}
