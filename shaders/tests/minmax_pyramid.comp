// Test-only: one level of a min/max depth pyramid (the hierarchical-depth structure that blocker
// searches walk). Texel p of level k holds the min (r) and max (g) of the level k-1 texels it covers:
// 2x2, widened to the end of the row or column on the last texel when level k-1 has an odd size, so
// that no source texel is left out (37 -> 18 covers 34, 35 and 36 in its last texel).
layout(local_size_x = 8, local_size_y = 8) in;
layout(rg32f, binding = 0) uniform readonly image2D source;        // level k-1
layout(rg32f, binding = 1) uniform writeonly image2D destination;  // level k

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 destinationSize = imageSize(destination);
    if (any(greaterThanEqual(p, destinationSize))) return;
    ivec2 sourceSize = imageSize(source);
    ivec2 lo = 2 * p;
    ivec2 hi = min(2 * p + 1, sourceSize - 1);
    if (p.x == destinationSize.x - 1) hi.x = sourceSize.x - 1;
    if (p.y == destinationSize.y - 1) hi.y = sourceSize.y - 1;
    vec2 range = vec2(1e30, -1e30);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            vec2 texel = imageLoad(source, ivec2(x, y)).rg;
            range = vec2(min(range.x, texel.x), max(range.y, texel.y));
        }
    imageStore(destination, p, vec4(range, 0.0, 0.0));
}
