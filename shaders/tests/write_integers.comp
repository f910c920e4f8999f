// Test-only: integer images written by imageStore, to be read back exactly. Pixel i = x + y * size.x.
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32ui, binding = 0) uniform writeonly uimage2D single;    // 0xFFFFFF at i = 0, else (i * 123456) mod 2^24
layout(rgba32ui, binding = 1) uniform writeonly uimage2D quad;   // (x, y, 123456, 0xFFFFFF - i)
layout(r32i, binding = 2) uniform writeonly iimage2D signedValues;  // -1000 i - 1
uniform uvec2 size;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, size))) return;
    uint i = p.x + p.y * size.x;
    imageStore(single, ivec2(p), uvec4(i == 0u ? 0xFFFFFFu : (i * 123456u) & 0xFFFFFFu));
    imageStore(quad, ivec2(p), uvec4(p.x, p.y, 123456u, 0xFFFFFFu - i));
    imageStore(signedValues, ivec2(p), ivec4(-1000 * int(i) - 1));
}
