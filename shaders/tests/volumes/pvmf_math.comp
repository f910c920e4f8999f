// Test-only: the penumbra-mask shared functions (shaders/shared/penumbra_mask.glsl) on a list of
// cases, compared with the same source compiled as C++ by PvmfMathGpu.AgreesWithCpuOnAGrid
// (tests/techniques/test_pvmf.cpp).
layout(local_size_x = 64) in;
#include "../../shared/penumbra_mask.glsl"

struct Case {
    vec4 e0;      // xyz, light radius r
    vec4 e1;      // xyz, s_e
    vec4 light;   // l.xyz, side (PVM_OUTER or PVM_INNER)
    vec4 filt;    // s_p, d_r, d_o, tan(alpha / 2)
    vec4 ids;     // object id at the centre, at the tap; -, -
    uvec4 seeds;  // seed, x, y, sample index
    uvec4 npcf;   // n_pcf, -, -, -
};
struct Result {
    vec4 moved0;  // pvmfMovedPoint(e0), pvmfEdgeDistance
    vec4 moved1;  // pvmfMovedPoint(e1), pvmfFilterWidth
    vec4 ext0;    // pvmfExtrusion at e^0 (PVMF_START), pvmfBlurWeight
    vec4 ext1;    // pvmfExtrusion at e^1 (PVMF_END), -
    vec4 offsets;  // pvmfSampleOffset.xy, -, -
    uvec4 seed;   // pvmfPixelSeed, -, -, -
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
uniform uint count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) {
        return;
    }
    Case c = cases[i];
    float r = c.e0.w;
    float de = pvmfEdgeDistance(c.e0.xyz, c.e1.xyz, c.light.xyz);
    vec3 a = pvmfMovedPoint(c.e0.xyz, de, c.light.xyz, c.e1.w);
    vec3 b = pvmfMovedPoint(c.e1.xyz, de, c.light.xyz, c.e1.w);
    vec3 n = pvmPlaneNormal(c.e0.xyz, c.e1.xyz, c.light.xyz);
    Result res;
    res.moved0 = vec4(a, de);
    res.moved1 = vec4(b, pvmfFilterWidth(c.filt.x, c.filt.y, c.filt.z, r, c.filt.w));
    res.ext0 = vec4(pvmfExtrusion(a, a, b, n, c.light.xyz, r, PVMF_START, c.light.w), pvmfBlurWeight(c.ids.x, c.ids.y, c.ids.z));
    res.ext1 = vec4(pvmfExtrusion(b, a, b, n, c.light.xyz, r, PVMF_END, c.light.w), 0.0);
    uint seed = pvmfPixelSeed(c.seeds.x, c.seeds.y, c.seeds.z);
    res.offsets = vec4(pvmfSampleOffset(c.seeds.w, c.npcf.x, seed), 0.0, 0.0);
    res.seed = uvec4(seed, uint(pvmfBlurTaps(int(c.npcf.y), int(c.npcf.z))), 0u, 0u);
    results[i] = res;
}
