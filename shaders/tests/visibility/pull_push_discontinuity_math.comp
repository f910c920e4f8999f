// Test-only: every shared function of shaders/shared/pull_push.glsl and discontinuity.glsl
// (guennebaud2007 sec. 5.2: pull-push reconstruction and the discontinuity buffer) on a list of
// cases, compared with the same source compiled as C++ by PullPushSharedMathGpu.AgreesWithCpu
// (tests/core/test_pull_push.cpp). Inputs include the hard cases: 1-texel levels, the last texel of
// an odd level, zero weights, fractional weights, clamped bilinear taps, grazing normals.
layout(local_size_x = 64) in;
#include "../../shared/pull_push.glsl"
#include "../../shared/discontinuity.glsl"

struct Case {
    ivec4 texel;     // x, y, coarse size x, y (also: radius for dilationRange, covered pixel count)
    ivec4 sizes;     // fine size x, y, level, n0
    vec4 values;     // v, w, sum w v, sum w
    vec4 corners;    // c00, c10, c01, c11
    vec4 position;   // world xyz, z at the centre
    vec4 normal;     // world xyz, largest cosine of incidence
    vec4 above;      // a 3x3 row (xyz); w: depth threshold
    vec4 row;        // xyz; w: normal threshold
    vec4 below;      // xyz; w: depth measure
};
struct Result {
    ivec4 block;   // pullBlock
    ivec4 taps;    // pushTaps
    ivec4 ints;    // pullPushLevelSize(level, n0), dilationRange(x, radius, n0).xy, coverageDiscontinuity
    vec4 pull;     // pullAccumulate(sums, (v, w)).xy, pullResult(sums).xy
    vec4 push;     // pushCoarseCoordinate(x, coarse x), pushFractions.xy, pushBilinear
    vec4 blend;    // pushBlend, cameraDepth, cosIncidence, relativeDepthEdge
    vec4 edges;    // sobelGradient(above, row, below).xy, normalEdge, discontinuityMark
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
uniform uint count;
uniform mat4 viewFromWorld;

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= count) return;
    Case c = cases[k];
    Result r;
    ivec2 p = c.texel.xy, coarse = c.texel.zw, fine = c.sizes.xy;
    r.block = pullBlock(p, coarse, fine);
    r.taps = pushTaps(p, coarse);
    ivec2 range = dilationRange(p.x, c.texel.z, c.sizes.w);
    r.ints = ivec4(pullPushLevelSize(c.sizes.z, c.sizes.w), range.x, range.y,
                   int(coverageDiscontinuity(c.texel.w)));
    vec2 acc = pullAccumulate(c.values.zw, c.values.xy);
    vec2 pulled = pullResult(c.values.zw);
    r.pull = vec4(acc, pulled);
    vec2 f = pushFractions(p, coarse);
    r.push = vec4(pushCoarseCoordinate(p.x, coarse.x), f, pushBilinear(c.corners.x, c.corners.y, c.corners.z, c.corners.w, f));
    vec2 g = sobelGradient(c.above.xyz, c.row.xyz, c.below.xyz);
    r.blend = vec4(pushBlend(c.values.xy, c.corners.x), cameraDepth(viewFromWorld, c.position.xyz),
                   cosIncidence(viewFromWorld, c.position.xyz, c.normal.xyz), relativeDepthEdge(g, c.position.w, c.normal.w));
    vec2 g2 = sobelGradient(c.row.xyz, c.below.xyz, c.above.xyz);
    r.edges = vec4(g, normalEdge(g, g2, vec2(c.values.x, c.values.y)),
                   discontinuityMark(c.below.w, c.values.y, c.above.w, c.row.w));
    results[k] = r;
}
