// Test-only: evaluates, on a list of inputs, every shared function (shaders/shared/) that
// hard_cases.comp, shared_math.frag, penumbra_math.frag and backprojection_math.frag do not already
// compare, so that HardCaseGpuEvery.EveryOtherSharedFunctionAgreesWithCpu (tests/hard_cases/test_hard_cases_gpu.cpp)
// compares the GPU with the same source run in C++; HardCaseGpuCoverage.EverySharedFunctionIsComparedOnTheGpu
// checks that no shared function is left out. Inputs include the hard cases: kernels of 0 and of
// more than the map, texels on the map's border, segments on the light's border, through its
// centre and of zero length, samples exactly at the receiver's depth and plane, grazing planes.
layout(local_size_x = 64) in;
#include "../shared/light_sampling.glsl"
#include "../shared/penumbra.glsl"
#include "../shared/shadow_projection.glsl"
#include "../shared/backprojection.glsl"

struct Case {
    vec4 segment;  // a.xy, b.xy: light coordinates (clipping, border position); a.xy also a texel
    vec4 kernel;   // kernelTexels, smSize, tanHalfFov, t
    vec4 depths;   // zSample, zReceiver, zPlane, bias
    vec4 sizes;    // penumbraWorld, worldPerPixel, kernel width, light size
    vec4 world;    // receiver position (world), then the slab's position p
    vec4 normal;   // receiver normal (world), then the slab's direction d
    ivec4 ints;    // light shape (1 square, 2 disk), HSM level, contour mask, which edge
    uvec4 bits;    // hash input, contour sample k, side, occluder end (0: the side's start, 1: its end)
};
struct Result {
    vec4 light;      // bpLightArea, bpLightWidth, bpVisibility(segment.x + 2, shape), hashToUnit
    ivec4 range0;    // kernelTexelRange(segment.xy, kernelTexels, smSize)
    ivec4 rangeL;    // levelTexelRange(range0, level, hsmLevelSize(level, smSize))
    ivec4 levels;    // hsmRefinementLevel(kernelTexels, 9), hsmLevelSize, contourEdgeHolders
    vec4 region;     // levelRegionTexels(rangeL, level, levelSize, smSize)
    vec4 ray;        // texelRay(segment.xy, smSize, tanHalfFov), squareBorderPosition(segment.xy)
    vec4 clip;       // clipSlab((-0.5, 1.5), world.w, normal.w), clipSegmentToSquare
    vec4 clipLight;  // clipSegmentToLight(shape, a, b), contourSamplePosition(k)
    vec4 contour;    // contourCrossing(side, occluder, t), maxKernelForMap, penumbraKernelPixels
    ivec4 tests;     // sampleOccludes, contourEdgeDegenerate, bpSampleOccludes, kernelRadius
    vec4 receiver;   // regionPlaneDepthMin, bpClassify (two bounds), shadowDepthTest
    vec4 samplePos;  // lightSamplePosition(centre, right, up, shape, size, uv).xyz, receiver bias
    vec4 plane;      // planeInverseDepth(world, normal, segment.xy, tanHalfFov, 1.5).xyz, 0
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
uniform mat4 lightViewFromWorld;
uniform mat4 lightClipFromView;
uniform vec3 lightPosition;
uniform uint count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) {
        return;
    }
    Case c = cases[i];
    Result r;
    int shape = c.ints.x;
    int level = c.ints.y;
    int mask = c.ints.z;
    int which = c.ints.w;
    int smSize = int(c.kernel.y);
    vec2 a = vec2(c.segment.x, c.segment.y);
    vec2 b = vec2(c.segment.z, c.segment.w);
    r.light = vec4(bpLightArea(shape), bpLightWidth(shape, c.sizes.w), bpVisibility(c.segment.x + 2.0f, shape),
                   hashToUnit(c.bits.x));
    r.range0 = kernelTexelRange(a, c.kernel.x, smSize);
    int levelSize = hsmLevelSize(level, smSize);
    r.rangeL = levelTexelRange(r.range0, level, levelSize);
    ivec2 holders = contourEdgeHolders(mask, which);
    r.levels = ivec4(hsmRefinementLevel(c.kernel.x, 9), levelSize, holders.x, holders.y);
    r.region = levelRegionTexels(r.rangeL, level, levelSize, smSize);
    vec3 ray = texelRay(a, c.kernel.y, c.kernel.z);
    r.ray = vec4(ray.x, ray.y, ray.z, squareBorderPosition(a));
    vec2 slab = clipSlab(vec2(-0.5f, 1.5f), c.world.w, c.normal.w);
    vec2 square = clipSegmentToSquare(a, b);
    r.clip = vec4(slab.x, slab.y, square.x, square.y);
    vec2 light = clipSegmentToLight(shape, a, b);
    vec2 sampleK = contourSamplePosition(int(c.bits.y));
    r.clipLight = vec4(light.x, light.y, sampleK.x, sampleK.y);
    int side = int(c.bits.z);
    int occluder = c.bits.w == 0u ? side : (side + 1) % 4;
    vec2 crossing = contourCrossing(side, occluder, c.kernel.w);
    r.contour = vec4(crossing.x, crossing.y, maxKernelForMap(c.kernel.y),
                     penumbraKernelPixels(c.sizes.x, c.sizes.y, maxKernelForMap(c.kernel.y)));
    vec3 worldPos = vec3(c.world.x, c.world.y, c.world.z);
    vec3 worldNormal = vec3(c.normal.x, c.normal.y, c.normal.z);
    BpReceiver rec = bpReceiver(lightViewFromWorld, lightClipFromView, worldPos, worldNormal, lightPosition,
                                c.kernel.z, c.kernel.y, 1.0f, 2.0f);
    bool occludes = bpSampleOccludes(rec, vec2(r.region.x + 0.5f, r.region.y + 0.5f), c.depths.x, c.kernel.y, c.kernel.z);
    r.tests = ivec4(sampleOccludes(c.depths.x, c.depths.y, c.depths.z, c.depths.w) ? 1 : 0,
                    contourEdgeDegenerate(mask, c.kernel.w, which) ? 1 : 0, occludes ? 1 : 0, kernelRadius(c.sizes.z));
    float planeMin = regionPlaneDepthMin(rec, r.region, c.kernel.y, c.kernel.z);
    float cls = bpClassify(rec, vec2(c.depths.x, c.depths.y), planeMin) +
                4.0f * bpClassify(rec, vec2(c.depths.x * 0.5f, c.depths.x * 0.9f), planeMin);
    r.receiver = vec4(planeMin, cls, shadowDepthTest(c.depths.y, c.depths.x, c.depths.w), 0.0f);
    vec3 s = lightSamplePosition(lightPosition, vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, -1.0f), shape, c.sizes.w,
                                 vec2(fract(c.segment.z), fract(c.segment.w)));
    r.samplePos = vec4(s.x, s.y, s.z, rec.bias);
    r.plane = vec4(planeInverseDepth(worldPos, worldNormal, a, c.kernel.z, 1.5f), 0.0f);
    results[i] = r;
}
