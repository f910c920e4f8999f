// Test-only: the visibility convention's shared functions (shaders/shared/tangent_plane.glsl) on
// a list of cases, compared with the same source compiled as C++ by
// TangentPlaneGpu.AgreesWithCpuOnAGrid (tests/techniques/test_tangent_plane.cpp).
layout(local_size_x = 64) in;
#include "../shared/tangent_plane.glsl"

struct Case {
    vec4 receiver;  // p.xyz, light size
    vec4 normal;    // n.xyz, light shape (as a float)
    vec4 centre;    // the light centre .xyz, then g.x of the 2D forms
    vec4 right;     // the light's right .xyz, then g.y
    vec4 up;        // the light's up .xyz, then d
};
struct Result {
    vec4 fractions;  // lightFractionInFront, squareFractionInFront(g, d), diskFractionInFront(g, d), inFront(centre)
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
    vec3 p = c.receiver.xyz;
    vec3 n = c.normal.xyz;
    vec2 g = vec2(c.centre.w, c.right.w);
    float d = c.up.w;
    Result r;
    r.fractions = vec4(lightFractionInFront(int(c.normal.w), c.centre.xyz, c.right.xyz, c.up.xyz, c.receiver.w, p, n),
                       squareFractionInFront(g, d), diskFractionInFront(g, d),
                       inFrontOfTangentPlane(p, n, c.centre.xyz) ? 1.0 : 0.0);
    results[i] = r;
}
