// SSSM step 3 (buades2015 sec. 4.2, Table 1 "Step3"): the vertical blur. Row t of the m x m kernel
// reuses the horizontal blur of step 2 at (x, y + t) when that pixel's camera depth, adjusted by
// this pixel's normal (its tangent plane), is within beta; otherwise the row is filtered again from
// the hard shadows, and from the shadow map where the screen does not show this surface.
#include "sssm_blur.glsl"
uniform sampler2D penumbras;    // step 2: (z_avg, w_penumbra, kernel x, kernel y)
uniform sampler2D horizontals;  // step 2: horizontal blur
layout(location = 0) out float visibility;
layout(location = 1) out float reuse;  // fraction of the rows taken from step 2 (-1: no filtering)

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    visibility = 1.0;
    reuse = -1.0;
    vec4 pen = texelFetch(penumbras, pixel, 0);
    if (pen.y <= 0.0) {  // no penumbra (or background, where step 1 wrote 1): the hard shadow
        visibility = texelFetch(hardShadows, pixel, 0).r;
        return;
    }
    Surface s = surfaceAt(pixel, texelFetch(hardShadows, pixel, 0).r);
    float kx = pen.z, ky = pen.w;
    int ry = kernelRadius(ky);
    float sum = 0.0, weights = 0.0;
    int reused = 0;
    uvec4 missed = uvec4(0u);  // rows filtered again after the loop (see blurRow)
    for (int t = -ry; t <= ry; ++t) {
        float w = kernelWeight(float(t), ky, filterKind, sigma);
        weights += w;
        ivec2 q = pixel + ivec2(0, t);
        bool ok = false;
        if (onScreen(q)) {
            if (showsSurface(s, q, texelFetch(hardShadows, q, 0).g, beta)) {
                sum += w * texelFetch(horizontals, q, 0).r;
                ok = true;
                ++reused;
            }
        }
        if (!ok) missed = markBit(missed, t + ry);
    }
    for (int word = 0; word < 4; ++word) {
        uint bits = missed[word];
        while (bits != 0u) {
            int t = word * 32 + findLSB(bits) - ry;
            bits &= bits - 1u;
            sum += kernelWeight(float(t), ky, filterKind, sigma) * blurRow(s, pixel + ivec2(0, t), kx);
        }
    }
    visibility = sum / weights;
    reuse = float(reused) / float(2 * ry + 1);
}
