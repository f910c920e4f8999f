// Stencil marks (no colour output): the fragment survives, and the draw's stencil op marks the pixel,
// where there is something for a later draw to do. MARK_GEOMETRY: pixels showing geometry. Else:
// pixels whose `marks` texel has channel MARK_CHANNEL above `markAbove`. Later draws test the mark
// before shading, so a CPU rasteriser skips the groups of pixels that have nothing to do (a discard
// or return inside the shader would still run the group's loops, masked).
#include "../common/gbuffer_access.glsl"
#ifndef MARK_GEOMETRY
uniform sampler2D marks;
uniform float markAbove;
#endif

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
#ifdef MARK_GEOMETRY
    if (isBackground(pixel)) discard;
#else
    if (texelFetch(marks, pixel, 0)[MARK_CHANNEL] <= markAbove) discard;
#endif
}
