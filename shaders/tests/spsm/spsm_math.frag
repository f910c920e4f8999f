// Test-only: shaders/shared/spsm.glsl on a 32 x 32 grid (the cases of spsm_cases.glsl), so that
// tests/techniques/test_spsm.cpp compares the GPU with the same functions in C++.
#include "spsm_cases.glsl"
layout(location = 0) out uvec4 outPacked;
layout(location = 1) out vec4 outA;
layout(location = 2) out vec4 outB;
layout(location = 3) out vec4 outC;
layout(location = 4) out vec4 outD;
layout(location = 5) out vec4 outE;
layout(location = 6) out vec4 outF;
layout(location = 7) out vec4 outG;

uniform int variant;  // 0: packed, a..g; 1: h, i, j, k, l in outA..outE

void main() {
    ivec2 c = ivec2(gl_FragCoord.xy);
    SpsmCaseOut o = spsmCase(c.x, c.y);
    outPacked = o.code;
    outA = variant == 0 ? o.a : o.h;
    outB = variant == 0 ? o.b : o.i;
    outC = variant == 0 ? o.c : o.j;
    outD = variant == 0 ? o.d : o.k;
    outE = variant == 0 ? o.e : o.l;
    outF = o.f;
    outG = o.g;
}
