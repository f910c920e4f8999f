// The screen-space discontinuity buffer of guennebaud2007 sec. 5.2, step 2: "the discontinuity
// lines are increased such that their width is greater than the maximum allowed pixel spacing": a
// max filter over a square of (2 r + 1)^2 pixels, run separably, one dispatch along the rows
// (ALONG_Y undefined) and one along the columns (ALONG_Y). Math: shaders/shared/discontinuity.glsl;
// host: DiscontinuityBuffer (techniques/core/visibility/discontinuities.cpp).
layout(local_size_x = 8, local_size_y = 8) in;
#include "../shared/discontinuity.glsl"

uniform int radiusPixels;  // r
layout(r32f, binding = 0) uniform readonly image2D source;
layout(r32f, binding = 1) uniform writeonly image2D destination;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(destination);
    if (any(greaterThanEqual(p, size))) return;
    float mark = 0.0;
#ifdef ALONG_Y
    ivec2 range = dilationRange(p.y, radiusPixels, size.y);
    for (int y = range.x; y <= range.y; ++y) mark = max(mark, imageLoad(source, ivec2(p.x, y)).r);
#else
    ivec2 range = dilationRange(p.x, radiusPixels, size.x);
    for (int x = range.x; x <= range.y; ++x) mark = max(mark, imageLoad(source, ivec2(x, p.y)).r);
#endif
    imageStore(destination, p, vec4(mark, 0.0, 0.0, 0.0));
}
