// Test-only: the soft-shadow-volume shared functions (shaders/shared/soft_shadow_volumes.glsl) on a
// list of cases, compared with the same source compiled as C++ by SsvMathGpu.AgreesWithCpuOnAGrid
// (tests/techniques/test_ssv.cpp).
layout(local_size_x = 64) in;
#include "../../shared/soft_shadow_volumes.glsl"

struct Case {
    vec4 receiver;  // p.xyz (light frame), light shape (as a float)
    vec4 normal;    // n.xyz, light half size
    vec4 x0;        // edge start .xyz
    vec4 x1;        // edge end .xyz
    vec4 extra;     // ssvClipLinear's f0, f1; ssvVisibility's count, coverage sum
};
struct Result {
    vec4 edge;      // ssvProjectedEdge
    vec4 values;    // ssvEdgeCoverage, ssvVisibility, ssvOccludingRange
    vec4 more;      // ssvClipLinear range, ssvProjectToLight(x0)
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
    int shape = int(c.receiver.w);
    float halfSize = c.normal.w;
    vec3 p = c.receiver.xyz;
    Result r;
    r.edge = ssvProjectedEdge(p, c.normal.xyz, c.x0.xyz, c.x1.xyz, halfSize);
    vec2 range = ssvOccludingRange(p, c.normal.xyz, c.x0.xyz, c.x1.xyz);
    r.values = vec4(ssvEdgeCoverage(shape, p, c.normal.xyz, c.x0.xyz, c.x1.xyz, halfSize),
                    ssvVisibility(c.extra.z, c.extra.w, shape), range.x, range.y);
    vec2 clip = ssvClipLinear(vec2(0.0, 1.0), c.extra.x, c.extra.y);
    vec2 q = c.x0.z < p.z ? ssvProjectToLight(p, c.x0.xyz, halfSize) : vec2(0.0);
    r.more = vec4(clip.x, clip.y, q.x, q.y);
    results[i] = r;
}
