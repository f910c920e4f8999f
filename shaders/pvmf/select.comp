// pvmf, pass select (cournia2005 sec. 5.2, first paragraph after the equation): which pixels the
// filter runs on. A receiver is filtered when it lies inside a penumbra volume of the mask (the
// mask's depth is nearer the light than the receiver) or fails the depth test against the shadow map;
// every other pixel is lit (the fraction of the light in front of its tangent plane) and never
// touched again. The filtered pixels are appended to a list, which the filter and the blur passes
// dispatch over (glDispatchComputeIndirect): llvmpipe runs both sides of every branch, so a mask
// tested inside the filter would save nothing; a list restricts the work as the dissertation's
// early-out does on its hardware (README.md).
//  PVMF_STEP 1: classify every pixel, write the unfiltered ones' visibility, list the others.
//  PVMF_STEP 2: one invocation writes the filter's dispatch arguments from the list's length.
#include "../common/gbuffer_access.glsl"
#include "../common/light_front.glsl"
#include "../common/shadow_lookup.glsl"
// counts: [0] pixels listed, [1..3] the dispatch (PVMF_GROUP invocations a group, groups in rows of
// PVMF_ROW), [4] geometry pixels, [5] listed because inside a volume, [6] listed only because the
// shadow-map test failed.
layout(std430, binding = 0) buffer Counts { uint counts[]; };
const uint PVMF_GROUP = 64u;
const uint PVMF_ROW = 4096u;
#if PVMF_STEP == 2
layout(local_size_x = 1) in;
void main() {
    uint groups = (counts[0] + PVMF_GROUP - 1u) / PVMF_GROUP;
    counts[1] = min(groups, PVMF_ROW);
    counts[2] = max((groups + PVMF_ROW - 1u) / PVMF_ROW, 1u);
    counts[3] = 1u;
    if (groups == 0u) {
        counts[1] = 0u;
    }
}
#else
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 1) buffer PixelList { uint pixels[]; };  // x | y << 16
layout(r32f, binding = 0) uniform writeonly image2D visibilityRaw;
uniform sampler2D maskMap;  // (volume depth, d_e)
uniform ivec2 frameSize;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, frameSize))) {
        return;
    }
    float v = 1.0;
    if (!isBackground(pixel)) {
        atomicAdd(counts[4], 1u);
        vec3 p = worldPosition(pixel);
        vec3 n = worldNormal(pixel);
        float front = lightFrontFraction(p, n);
        v = front;
        ShadowReceiver r = prepareShadowReceiver(p, n);
        if (front > 0.0 && r.coord.w != 0.0) {
            ivec2 texel = clamp(ivec2(floor(r.coord.xy * shadowMapSize)), ivec2(0), ivec2(int(shadowMapSize) - 1));
            bool inVolume = texelFetch(maskMap, texel, 0).r < r.coord.z;
            bool shadowed = shadowTestOffset(r, vec2(0.0)) == 0.0;
            if (inVolume || shadowed) {
                uint slot = atomicAdd(counts[0], 1u);
                pixels[slot] = uint(pixel.x) | (uint(pixel.y) << 16u);
                atomicAdd(counts[inVolume ? 5 : 6], 1u);
                v = -1.0;  // the filter writes it
            }
        }
    }
    imageStore(visibilityRaw, pixel, vec4(v));
}
#endif
