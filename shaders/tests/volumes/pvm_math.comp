// Test-only: the penumbra-volume shared functions (shaders/shared/penumbra_volumes.glsl) on a list
// of cases, compared with the same source compiled as C++ by PvmMathGpu.AgreesWithCpuOnAGrid
// (tests/techniques/test_pvm.cpp).
layout(local_size_x = 64) in;
#include "../../shared/penumbra_volumes.glsl"

struct Case {
    vec4 v0;     // xyz, light radius r
    vec4 v1;     // xyz, side (PVM_OUTER or PVM_INNER)
    vec4 v2;     // xyz, s for pvmDiskFraction
    vec4 p;      // receiver xyz, light shape (1 square, 3 sphere)
    vec4 light;  // l.xyz, light size
};
struct Result {
    vec4 extrusion;  // pvmExtrusion(v0, v1, v2, l, r, side), pvmDiskFraction(s, r)
    vec4 plane;      // pvmCuttingPlane(v1, v2, p)
    vec4 normals;    // pvmPlaneNormal(v1, v2, l), pvmFalloff(k)
    vec4 values;     // pvmVisibility(p, v1, v2, l, r), pvmLightRadius(shape, size), displaced light .xy
    vec4 edgeEnd;    // pvmEdgeEndExtrusion(v0, v1, v2, l, r, side, own edge: 0 for even cases, 1 for odd),
                     // pvmSideVisibility(pvmVisibility(...), centre visible for i % 3 == 0)
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
    float r = c.v0.w;
    Result res;
    float k = pvmDiskFraction(c.v2.w, r);
    res.extrusion = vec4(pvmExtrusion(c.v0.xyz, c.v1.xyz, c.v2.xyz, c.light.xyz, r, c.v1.w), k);
    res.plane = pvmCuttingPlane(c.v1.xyz, c.v2.xyz, c.p.xyz);
    vec3 n = pvmPlaneNormal(c.v1.xyz, c.v2.xyz, c.light.xyz);
    res.normals = vec4(n, pvmFalloff(k));
    vec3 d = pvmDisplacedLight(c.light.xyz, n, r, c.v1.w);
    res.values = vec4(pvmVisibility(c.p.xyz, c.v1.xyz, c.v2.xyz, c.light.xyz, r),
                      pvmLightRadius(int(c.p.w), c.light.w), d.x, d.y);
    res.edgeEnd = vec4(pvmEdgeEndExtrusion(c.v0.xyz, c.v1.xyz, c.v2.xyz, c.light.xyz, r, c.v1.w, float(i % 2u)),
                      pvmSideVisibility(res.values.x, i % 3u == 0u ? 1.0 : 0.0));
    results[i] = res;
}
