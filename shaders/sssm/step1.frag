// SSSM step 1 (buades2015 sec. 4.1, Table 1 "Step1", Fig. 3): the hard shadow of every pixel, and
// the horizontal blocker search: partial_blocker_sum and partial_blocker_count over the n x 1 row
// of shadow-map texels centred on the pixel's texel (n: the search width of its light and depth,
// capped at blocker_kernel). "The resulting buffer is filled with three values: light depth, sum
// of blockers and count of blockers" (here a fourth: the search width).
#include "sssm_common.glsl"
uniform float blockerKernel;  // n (texels)
layout(location = 0) out vec2 hardShadow;  // (hard shadow, camera depth; -1 on background)
layout(location = 1) out vec4 blockerRows;  // (d, partial_blocker_sum, partial_blocker_count, width)

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    // Background keeps the pass's clear values: hard shadow 1, camera depth -1, and light depth
    // -1e30, a depth no receiver is within alpha of (discarded: see pcss/blocker_search.frag).
    if (isBackground(pixel)) discard;
    hardShadow = vec2(1.0, -1.0);
    blockerRows = vec4(-1e30, 0.0, 0.0, 0.0);
    // The camera depth rides along, so steps 2 and 3 test beta with the fetch that reads the shadow.
    hardShadow.y = cameraDepth(worldPosition(pixel));
    ShadowReceiver receiver = prepareShadowReceiver(worldPosition(pixel), worldNormal(pixel));
    if (receiver.coord.w == 0.0) return;  // outside the light's frustum: lit
    TapPlane plane = tapPlane(receiver, worldPosition(pixel), worldNormal(pixel));
    hardShadow.x = shadowTestOffset(receiver, vec2(0.0));
    float d = receiver.coord.z;
    float width = blockerSearchWidthTexels(lightWidthWorld, d, lightNearZ, lightTanHalfFov, shadowMapSize, blockerKernel);
    int r = kernelRadius(width);
    vec2 acc = vec2(0.0);
    for (int x = -r; x <= r; ++x) {
        vec2 offset = vec2(x, 0);
        acc = accumulateBlocker(acc, storedDepthOffset(receiver, offset), d, tapBias(receiver, plane, offset));
    }
    blockerRows = vec4(d, acc, width);
}
