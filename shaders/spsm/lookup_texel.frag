// spsm look-up, step 1 (lecocq2014, "At the rendering stage"; the other steps: lookup.comp): every
// pixel (under refineFrame, the band its scissor leaves) against the stored triangle of its texel:
// on it or behind p: lit; in front of p: the ray to the light hits it, shadowed; an empty texel is
// lit (conservative rasterization: no caster touches it). The others are appended to list 1.
// A fragment shader, as hard's depth test is, not a compute step: its two results leave through the
// render targets, which llvmpipe writes a block of pixels at a time, where a compute shader's
// imageStore writes lane by lane (on contact at 512x512 the branch image's store alone took 2.5-3 ms
// of a 9-10 ms step; techniques/spsm/README.md).
#include "lookup_common.glsl"
// 0 with neighbourhood 1 and reconstruction off (the texel's triangle alone, as Dai et al. 2008's rule
// has it: a ray that meets no stored triangle is lit): nothing is listed, this step decides every pixel.
uniform int listUndecided;
layout(location = 0) out float visibility;
layout(location = 1) out float branch;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    SpsmReceiver q = spsmPrepareReceiver(pixel);
    float v = q.v;
    float b = q.branch;
    uvec4 w = texelFetch(spsmMap, q.t, 0);
    // The test runs in a loop of 0 or 1 iterations rather than under an `if`: llvmpipe runs both
    // sides of an `if` for its pixels in lock-step, but leaves a loop as soon as no pixel needs
    // another iteration, so a block whose texels are all empty (most of a frame) skips the unpack
    // and the test.
    int tests = q.decided || spsmEmpty(w) ? 0 : 1;
    if (!q.decided) b = SPSM_BRANCH_EMPTY;
    for (int i = 0; i < tests; ++i) {
        int test = spsmTriangleTest(spsmUnpack(w, shadowMapSize), q.x, q.z, q.bias);
        v = test == 2 ? 0.0 : 1.0;
        b = test == 1 ? SPSM_BRANCH_ON_TRIANGLE : (test == 2 ? SPSM_BRANCH_HIT : SPSM_BRANCH_UNDECIDED);
    }
    if (b == SPSM_BRANCH_UNDECIDED && listUndecided == 0) {
        v = 1.0;
        b = SPSM_BRANCH_FALLBACK;
    }
    visibility = v;
    branch = b;
    if (b == SPSM_BRANCH_UNDECIDED) list1[atomicAdd(counts[0], 1u)] = packPixel(pixel);
}
