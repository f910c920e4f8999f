// SSSM step 2 (buades2015 sec. 4.1-4.2, Table 1 "Step2", Fig. 4): the blocker average, reusing the
// horizontal partial sums of step 1 row by row when |d - d_t| < alpha and reading the n texels of
// the row from the depth map otherwise; the penumbra size (eq. 1) as a screen-space kernel; and
// the horizontal blur of the hard shadows with that kernel (Gaussian or mean, sec. 4.4): that is
// step2_blur.frag, a second draw of this pass over the pixels with a penumbra only.
#include "sssm_common.glsl"
uniform sampler2D hardShadows;  // step 1: (hard shadow, camera depth)
uniform sampler2D blockerRows;  // step 1: (d, partial sum, partial count, search width)
uniform mat4 cameraClipFromWorld;
uniform vec3 lightUpWorld;      // world direction of the shadow map's +v axis
uniform float alpha;            // step-2 reuse threshold (light-depth units)
layout(location = 0) out vec2 penumbra;    // (z_avg (-1: no blocker), w_penumbra (world))
layout(location = 1) out vec2 kernel;      // (1, 1) here; step2_blur.frag writes the penumbra's kernel
layout(location = 2) out float horizontal;  // the hard shadow here; step2_blur.frag blurs it
layout(location = 3) out float reuse;       // fraction of the n rows taken from step 1 (-1: no receiver)



void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 own = texelFetch(blockerRows, pixel, 0);
    // Background or outside the light frustum (step 1's marker): lit, the pass's clear values
    // (penumbra (-1, 0), kernel 1, horizontal 1, reuse -1) stay.
    if (own.x < 0.0) discard;
    penumbra = vec2(-1.0, 0.0);
    kernel = vec2(1.0);
    horizontal = texelFetch(hardShadows, pixel, 0).r;
    reuse = -1.0;
    float d = own.x;
    vec3 p = worldPosition(pixel);
    ShadowReceiver receiver = prepareShadowReceiver(p, worldNormal(pixel));
    TapPlane plane = tapPlane(receiver, p, worldNormal(pixel));

    // Blocker average: for each row t of the n x n search, p_t is the point at the same light depth
    // t texels along the map's v axis (its clip position is affine in t); its step-1 row serves if
    // the surface seen there is at a light depth within alpha, else the row's n texels are read
    // from the depth map.
    int r = kernelRadius(own.w);
    vec2 acc = vec2(0.0);
    int reused = 0;
    vec4 clip0 = cameraClipFromWorld * vec4(p, 1.0);
    vec4 clipStep = cameraClipFromWorld * vec4(receiver.texelWorld * lightUpWorld, 0.0);
    // Rows that cannot be reused are marked in a 128-bit set (n <= 127) and read from the depth map
    // afterwards (takeLowestBit).
    uvec4 missed = uvec4(0u);
    for (int t = -r; t <= r; ++t) {
        vec4 clip = clip0 + float(t) * clipStep;
        bool ok = false;
        if (clip.w > 0.0) {
            ivec2 q = ivec2(floor((clip.xy / clip.w * 0.5 + 0.5) * viewportSize));
            if (onScreen(q)) {
                vec4 row = texelFetch(blockerRows, q, 0);
                if (reuseBlockerRow(d, row.x, alpha)) {
                    acc += row.yz;
                    ok = true;
                    ++reused;
                }
            }
        }
        if (!ok) {
            missed = markBit(missed, t + r);
        }
    }
    while (any(notEqual(missed, uvec4(0u)))) {
        int t = takeLowestBit(missed) - r;
        for (int x = -r; x <= r; ++x) {
            vec2 offset = vec2(x, t);
            acc = accumulateBlocker(acc, storedDepthOffset(receiver, offset), d, tapBias(receiver, plane, offset));
        }
    }
    reuse = float(reused) / float(2 * r + 1);
    float zAvg = averageBlockerDepth(acc);
    float wPenumbra = penumbraWidth(lightWidthWorld, d, zAvg);  // eq. 1
    // "if (penumbra == 0) soft_shadow_value = hard_shadow_value": then the blur draw skips the pixel.
    penumbra = vec2(zAvg, wPenumbra);
}
