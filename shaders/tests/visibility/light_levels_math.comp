// Test-only: the light-space multi-resolution functions of shaders/shared/backprojection.glsl
// (guennebaud2007 sec. 5.1: eq. 2, eq. 3, the blending pseudo-code, the occluder depth hint, the
// per-level occlusion test and the atlas offsets) on a list of cases, compared with the same source compiled as C++ by
// LightLevelsGpu.SharedMathAgreesWithCpu (tests/techniques/test_light_levels.cpp).
layout(local_size_x = 64) in;
#include "../../shared/backprojection.glsl"

struct Case {
    vec4 kernel;    // w_k, smooth w~_k, t_k, beta
    vec4 depths;    // four min depths (00, 10, 11, 01)
    vec4 hint;      // f.x, f.y, zLimit, zMin
    vec4 receiver;  // light-frame position xyz, bias
    vec4 normal;    // light-frame normal xyz, zSample
    ivec4 ints;     // topLevel, level, texel x, y
};
struct Result {
    vec4 levels;    // lightLevelForKernel, lightLevelContinuous, hint, occludes
    vec4 blend;     // lightLevelBlend(lambda, beta, top)
    ivec4 atlas;    // hsmLevelAtlasX(level, 7 x + 1), hsmLevelAtlasX(level, 8192)
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
uniform uint count;

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= count) return;
    Case c = cases[k];
    Result r;
    int top = c.ints.x;
    float lambda = lightLevelContinuous(c.kernel.y, c.kernel.x, c.kernel.z, top);
    BpReceiver rec;
    rec.inside = 1.0;
    rec.position = c.receiver.xyz;
    rec.normal = c.normal.xyz;
    rec.centre = vec2(0.0);
    rec.bias = c.receiver.w;
    bool occ = bpLevelSampleOccludes(rec, c.ints.y, c.ints.zw, c.normal.w, 512.0, 0.6);
    r.levels = vec4(float(lightLevelForKernel(c.kernel.x, c.kernel.z, top)), lambda,
                    occluderDepthHint(c.depths, c.hint.xy, c.hint.z, c.hint.w), occ ? 1.0 : 0.0);
    r.blend = lightLevelBlend(lambda, c.kernel.w, top).xyzz;
    r.atlas = ivec4(hsmLevelAtlasX(c.ints.y, 7 * c.ints.z + 1), hsmLevelAtlasX(c.ints.y, 8192), 0, 0);
    results[k] = r;
}
