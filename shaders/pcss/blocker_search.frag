// PCSS step 1, blocker search (Fernando 2005; buades2015 sec. 2 and 4.1, Fig. 2): the mean depth of
// the shadow-map texels in front of the receiver, over the region the light and the receiver define
// (blockerSearchWidthTexels, capped at n = blocker_kernel); then eq. 1 gives the penumbra width and
// the PCF kernel of step 2 (capped at m = filter_kernel).
// Output: (z_avg (-1: no blocker), blocker count, search width (texels), filter kernel (texels)).
#include "../common/gbuffer_access.glsl"
#include "pcss_common.glsl"
uniform float blockerKernel;  // n (texels)
uniform float filterKernel;   // m (texels)
layout(location = 0) out vec4 blockers;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (isBackground(pixel)) {
        blockers = vec4(-1.0, 0.0, 0.0, 0.0);
        return;
    }
    ShadowReceiver receiver = prepareShadowReceiver(worldPosition(pixel), worldNormal(pixel));
    TapPlane plane = tapPlane(receiver, worldPosition(pixel), worldNormal(pixel));
    if (receiver.coord.w == 0.0) {  // outside the light's frustum: lit
        blockers = vec4(-1.0, 0.0, 0.0, 0.0);
        return;
    }
    float d = receiver.coord.z;
    float searchWidth = blockerSearchWidthTexels(lightWidthWorld, d, lightNearZ, lightTanHalfFov, shadowMapSize, blockerKernel);
    vec2 acc = vec2(0.0);  // blocker_sum, blocker_count
    if (pattern == PATTERN_POISSON) {
        float radius = 0.5 * searchWidth;
        for (int i = 0; i < POISSON_COUNT; ++i) {
            vec2 offset = poissonDisk[i] * radius;
            acc = accumulateBlocker(acc, storedDepthOffset(receiver, offset), d, tapBias(receiver, plane, offset));
        }
    } else {
        // Every texel of the searchWidth x searchWidth square; the loop bound is this pixel's width.
        int r = kernelRadius(searchWidth);
        for (int dy = -r; dy <= r; ++dy)
            for (int dx = -r; dx <= r; ++dx) {
                vec2 offset = vec2(dx, dy);
                acc = accumulateBlocker(acc, storedDepthOffset(receiver, offset), d, tapBias(receiver, plane, offset));
            }
    }
    float zAvg = averageBlockerDepth(acc);
    float penumbra = penumbraWidth(lightWidthWorld, d, zAvg);  // eq. 1
    float kernel = zAvg < 0.0 ? 0.0 : penumbraKernelTexels(penumbra, d, lightTanHalfFov, shadowMapSize, filterKernel);
    blockers = vec4(zAvg, acc.y, searchWidth, kernel);
}
