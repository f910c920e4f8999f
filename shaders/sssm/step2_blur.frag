// SSSM step 2, second draw (buades2015 sec. 4.2, Table 1 "Step2": "Compute Blur HardShadow
// horizontally"): for the pixels with a penumbra (the others are discarded and keep the hard shadow
// the first draw wrote), the penumbra of eq. 1 as a screen-space kernel and the horizontal blur of
// the hard shadows with it (Gaussian or mean, sec. 4.4). A discarded group of pixels costs nothing
// more on a CPU rasteriser, which runs every branch of a group it does run.
#include "sssm_blur.glsl"
uniform sampler2D penumbras;  // first draw: (z_avg, w_penumbra)
uniform float filterKernel;   // m (pixels)
layout(location = 0) out vec2 kernel;       // screen-space kernel width in x and y (pixels)
layout(location = 1) out float horizontal;  // horizontally blurred hard shadow (partial_soft_shadow)

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float wPenumbra = texelFetch(penumbras, pixel, 0).y;
    if (wPenumbra <= 0.0) discard;
    Surface s = withLightLookups(surfaceAt(pixel, texelFetch(hardShadows, pixel, 0).r));
    // The penumbra's width divided by the world length of a pixel step on the pixel's tangent plane.
    kernel = vec2(penumbraKernelPixels(wPenumbra, worldPerPixel(s, ivec2(1, 0)), filterKernel),
                  penumbraKernelPixels(wPenumbra, worldPerPixel(s, ivec2(0, 1)), filterKernel));
    // A tap whose pixel shows another surface (beta) or lies off screen is sampled from the shadow
    // map on this pixel's plane.
    horizontal = blurRow(s, pixel, kernel.x);
}
