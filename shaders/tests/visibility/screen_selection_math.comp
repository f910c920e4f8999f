// Test-only: the screen-space selection functions of shaders/shared/screen_selection.glsl (eq. 4-6,
// the dither rank, the codes, the block classes) and the row-bit walk of backprojection.glsl
// section 9 on a list of cases, compared with the same source compiled as C++ by
// ScreenSelectionGpu.SharedMathAgreesWithCpu (tests/techniques/test_screen_adaptive.cpp).
layout(local_size_x = 64) in;
#include "../../shared/backprojection.glsl"
#include "../../shared/screen_selection.glsl"

struct Case {
    vec4 sizes;   // w_l, p_z, z_occ, s_min
    vec4 screen;  // eta, z_pe, cos, unused
    ivec4 ints;   // i, j, h, selected (block class)
    uvec4 bits;   // below, above, blocks, bit index
};
struct Result {
    vec4 values;  // s_obj, s_scr, rank, selected
    ivec4 codes;  // selection code (sel, forced), evaluated(code), blockClass(sel, 256), mask
    uvec4 bits;   // contourBlockBits, unused x3
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
uniform uint count;

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= count) return;
    Case c = cases[k];
    Result r;
    float sObj = penumbraObjectSize(c.sizes.x, c.sizes.y, c.sizes.z);
    float sScr = penumbraScreenSize(sObj, c.screen.x, c.screen.y, c.screen.z);
    int rank = ditherRank(c.ints.x, c.ints.y, c.ints.z);
    bool selected = screenSelected(sScr, c.sizes.w, rank, c.ints.z);
    int code = penumbraSelectionCode(selected, (k % 3u) == 0u);
    r.values = vec4(sObj, sScr, float(rank), selected ? 1.0 : 0.0);
    r.codes = ivec4(code, selectionEvaluated(int(k % 7u)) ? 1 : 0, blockClass(c.ints.w, 256),
                    contourBlockMask(c.bits.x, c.bits.y, int(c.bits.w)));
    r.bits = uvec4(contourBlockBits(c.bits.x, c.bits.y, int(c.bits.z)), 0u, 0u, 0u);
    results[k] = r;
}
