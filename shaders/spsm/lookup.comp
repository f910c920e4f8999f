// spsm look-up (lecocq2014, "At the rendering stage"): the receiver p projected into SPSM space
// (x = its texel coordinate, z its light-view depth), in five steps (LOOKUP_STEP):
//  1 every pixel (lookup_texel.frag, a fragment shader; under refineFrame, every pixel of the band):
//    the texel's stored triangle decides when it covers x (on it or behind p: lit; in front of p: the
//    ray to the light hits it, shadowed); an empty texel is lit (conservative rasterization: no
//    caster touches it). The others are appended to list 1.
//  2, 4 one invocation writes the next step's dispatch arguments from its list's length.
//  3 list 1's pixels (an indirect dispatch, 64 per group): the triangles of the k x k
//    neighbourhood; a hit: shadowed; one covering x behind p: lit.
//    Neither, and the 3x3 depth comparisons (of the reconstruction) disagree: appended to list 2;
//    they agree: the fallback, the depth comparison with the receiver's own texel.
//  5 list 2's pixels: the shadow edge reconstructed from the 3x3 neighbourhood
//    (spsmReconstructEdge), else the fallback.
// Why lists: each step's work per pixel is many times the one before, for fewer pixels (on plant
// at 512x512 with a 256^2 map: all 262144, then about 14700, then about 5300). llvmpipe runs 8 pixels in
// lock-step through both sides of every branch, so a step under an `if` costs as if every pixel
// ran it; packed, every lane does useful work (the ssm-contour `pack` idea, with an atomic append:
// the lists' order does not matter, each entry writes its own pixel).
const uint SPSM_GROUP = 64u;
const uint SPSM_ROW = 4096u;
#if LOOKUP_STEP == 2 || LOOKUP_STEP == 4
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(local_size_x = 1) in;
void main() {
    const uint at = LOOKUP_STEP == 2 ? 0u : 4u;
    uint groups = (counts[at] + SPSM_GROUP - 1u) / SPSM_GROUP;
    counts[at + 1u] = groups == 0u ? 0u : min(groups, SPSM_ROW);
    counts[at + 2u] = max((groups + SPSM_ROW - 1u) / SPSM_ROW, 1u);
    counts[at + 3u] = 1u;
}
#else
#include "lookup_common.glsl"
layout(r32f, binding = 0) uniform writeonly image2D visibilityImage;
layout(r32f, binding = 1) uniform writeonly image2D branchImage;
layout(local_size_x = 64) in;
#if LOOKUP_STEP == 3
uniform int neighbourhood;   // k: odd, 3 (the paper) to 7 (Dai et al. 2008); 1 the texel alone
uniform int reconstruction;  // 1: reconstruct the shadow edge (the paper); 0: Dai et al. 2008
#endif

void decide(ivec2 pixel, float v, float b) {
    imageStore(visibilityImage, pixel, vec4(v));
    imageStore(branchImage, pixel, vec4(b));
}

// The reconstruction's 3x3 depth comparisons (bit k: neighbour (k % 3 - 1, k / 3 - 1) is in front
// of the receiver; texels beyond the map's border repeat the border's).
uint spsmOccludingNeighbours(SpsmTriangle tris[9], bool stored[9], ivec2 t, int last, float z, float bias) {
    uint occluding = 0u;
    for (int k = 0; k < 9; ++k) {
        ivec2 q = clamp(t + ivec2(k % 3 - 1, k / 3 - 1), ivec2(0), ivec2(last));
        if (stored[k] && spsmOccludesByDepth(tris[k], vec2(q) + 0.5, z, bias)) occluding |= 1u << uint(k);
    }
    return occluding;
}

void main() {
    uint index = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * SPSM_GROUP + gl_LocalInvocationIndex;
#if LOOKUP_STEP == 3
    if (index >= counts[0]) return;
    uint entry = list1[index];
#else
    if (index >= counts[4]) return;
    uint entry = list2[index];
#endif
    ivec2 pixel = ivec2(int(entry & 0xFFFFu), int(entry >> 16u));
    // A listed pixel was undecided in step 1: its receiver is in the map's frustum, facing the light.
    SpsmReceiver receiver = spsmPrepareReceiver(pixel);
    vec2 x = receiver.x;
    ivec2 t = receiver.t;
    int last = receiver.last;
    float bias = receiver.bias;
#if LOOKUP_STEP == 3
    // The 3x3 neighbourhood is unpacked once: its triangles are the ray tests' (k = 3) and the
    // depth comparisons' that decide whether the reconstruction has an edge to find.
    SpsmTriangle tris[9];
    bool stored[9];
    for (int k = 0; k < 9; ++k) {
        ivec2 q = clamp(t + ivec2(k % 3 - 1, k / 3 - 1), ivec2(0), ivec2(last));
        uvec4 w = texelFetch(spsmMap, q, 0);
        tris[k] = spsmUnpack(w, shadowMapSize);
        stored[k] = !spsmEmpty(w);
    }
    bool hit = false;
    bool covered = false;
    for (int k = 0; k < 9; ++k) {
        ivec2 q = t + ivec2(k % 3 - 1, k / 3 - 1);
        bool inMap = all(greaterThanEqual(q, ivec2(0))) && all(lessThanEqual(q, ivec2(last)));
        if (k != 4 && neighbourhood >= 3 && inMap && stored[k]) {  // neighbourhood 1: the texel alone
            int test = spsmTriangleTest(tris[k], x, receiver.z, bias);
            hit = hit || test == 2;
            covered = covered || test == 1;
        }
    }
    // Dai et al. 2008's larger neighbourhoods: the rings beyond the 3x3.
    int radius = neighbourhood / 2;
    for (int dy = -radius; dy <= radius; ++dy) {
        for (int dx = -radius; dx <= radius; ++dx) {
            ivec2 q = t + ivec2(dx, dy);
            if (max(abs(dx), abs(dy)) > 1 && all(greaterThanEqual(q, ivec2(0))) && all(lessThanEqual(q, ivec2(last)))) {
                uvec4 w = texelFetch(spsmMap, q, 0);
                if (!spsmEmpty(w)) {
                    int test = spsmTriangleTest(spsmUnpack(w, shadowMapSize), x, receiver.z, bias);
                    hit = hit || test == 2;
                    covered = covered || test == 1;
                }
            }
        }
    }
    uint occluding = spsmOccludingNeighbours(tris, stored, t, last, receiver.z, bias);
    if (hit) {
        decide(pixel, 0.0, SPSM_BRANCH_NEIGHBOUR_HIT);
    } else if (covered) {
        decide(pixel, 1.0, SPSM_BRANCH_NEIGHBOUR_COVER);
    } else if (reconstruction == 1 && occluding != 0u && occluding != 511u) {
        decide(pixel, 1.0, SPSM_BRANCH_UNDECIDED);
        list2[atomicAdd(counts[4], 1u)] = packPixel(pixel);
    } else {
        // The fallback: the depth comparison with p's own texel (all 3x3 comparisons alike: no
        // edge to reconstruct); without reconstruction (Dai et al. 2008) a ray that met no stored
        // triangle is lit (their false negatives where triangles were lost).
        decide(pixel, reconstruction == 1 && ((occluding >> 4u) & 1u) != 0u ? 0.0 : 1.0, SPSM_BRANCH_FALLBACK);
    }
#else
    SpsmTriangle tris[9];
    bool stored[9];
    for (int k = 0; k < 9; ++k) {
        ivec2 q = clamp(t + ivec2(k % 3 - 1, k / 3 - 1), ivec2(0), ivec2(last));
        uvec4 w = texelFetch(spsmMap, q, 0);
        tris[k] = spsmUnpack(w, shadowMapSize);
        stored[k] = !spsmEmpty(w);
    }
    uint occluding = spsmOccludingNeighbours(tris, stored, t, last, receiver.z, bias);  // neither 0 nor 511
    SpsmEdge e = spsmReconstructEdge(tris, occluding, x, vec2(t) + 0.5);
    if (e.decided == 1) {
        decide(pixel, 1.0 - e.shadowed, SPSM_BRANCH_EDGE);
        return;
    }
    // Fallback (no tangent or no usable vertex): the depth comparison with p's own texel.
    decide(pixel, ((occluding >> 4u) & 1u) != 0u ? 0.0 : 1.0, SPSM_BRANCH_FALLBACK);
#endif
}
#endif
