// spsm look-up (lecocq2014, "At the rendering stage"): the receiver p projected into SPSM space
// (x = its texel coordinate, z its light-view depth).
// Without NEIGHBOURS (first draw, every pixel): the texel's stored triangle decides when it covers
// x (on it or behind p: lit; in front of p: the ray to the light hits it, shadowed); an empty
// texel is lit (conservative rasterization: no caster touches it). The others write depth 0, so the
// second draw (NEIGHBOURS) runs only on them (early depth test: a CPU rasterizer skips the blocks
// with nothing left): the triangles of the k x k neighbourhood (a hit: shadowed; one covering x
// behind p: lit), then the shadow edge reconstructed from the 3x3 neighbourhood (spsmReconstructEdge),
// then the fallback, the depth comparison with the receiver's own texel.
#include "../common/gbuffer_access.glsl"
#include "../common/shadow_lookup.glsl"
#include "../shared/tangent_plane.glsl"
#include "../shared/spsm.glsl"
#include "branches.glsl"

uniform usampler2D spsmMap;
#ifdef NEIGHBOURS
uniform int neighbourhood;   // k: odd, 3 (the paper) to 7 (Dai et al. 2008)
uniform int reconstruction;  // 1: reconstruct the shadow edge (the paper); 0: Dai et al. 2008
#endif
layout(location = 0) out float visibility;
layout(location = 1) out float branch;

#ifdef NEIGHBOURS
layout(early_fragment_tests) in;  // the depth test of the first draw's marks runs before the shader
#endif

void decide(float v, float b) {
    visibility = v;
    branch = b;
#ifndef NEIGHBOURS
    gl_FragDepth = 1.0;
#endif
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (isBackground(pixel)) {
        decide(1.0, SPSM_BRANCH_NONE);
        return;
    }
    vec3 p = worldPosition(pixel);
    vec3 n = worldNormal(pixel);
    if (!inFrontOfTangentPlane(p, n, lightPosition)) {  // the visibility convention at the light centre
        decide(0.0, SPSM_BRANCH_FACING_AWAY);
        return;
    }
    ShadowReceiver r = prepareShadowReceiver(p, n);
    if (r.coord.w == 0.0) {  // outside the light's frustum: lit, as for `hard`
        decide(1.0, SPSM_BRANCH_EMPTY);
        return;
    }
    vec2 x = r.coord.xy * shadowMapSize;
    int last = int(shadowMapSize) - 1;
    ivec2 t = clamp(ivec2(floor(x)), ivec2(0), ivec2(last));
    float bias = r.bias;  // the triangle tests add each triangle's packing error
#ifndef NEIGHBOURS
    uvec4 w = texelFetch(spsmMap, t, 0);
    float v = 1.0;
    float b = SPSM_BRANCH_EMPTY;
    float depth = 1.0;
    // The test runs in a loop of 0 or 1 iterations rather than under an `if`: llvmpipe runs both
    // sides of an `if` for its 8 pixels in lock-step, but leaves a loop as soon as no pixel needs
    // another iteration, so a group whose texels are all empty (most of a frame) skips the unpack
    // and the test (measured: 6-10% of the look-up on square-occluder and contact; the same trick
    // for the second draw's steps cost more than it saved).
    int tests = spsmEmpty(w) ? 0 : 1;
    for (int i = 0; i < tests; ++i) {
        int test = spsmTriangleTest(spsmUnpack(w, shadowMapSize), x, r.coord.z, bias);
        v = test == 2 ? 0.0 : 1.0;
        b = test == 1 ? SPSM_BRANCH_ON_TRIANGLE : (test == 2 ? SPSM_BRANCH_HIT : SPSM_BRANCH_UNDECIDED);
        depth = test == 0 ? 0.0 : 1.0;
    }
    visibility = v;
    branch = b;
    gl_FragDepth = depth;
#else
    int radius = neighbourhood / 2;
    bool hit = false;
    bool covered = false;
    for (int dy = -radius; dy <= radius; ++dy) {
        for (int dx = -radius; dx <= radius; ++dx) {
            ivec2 q = t + ivec2(dx, dy);
            if ((dx != 0 || dy != 0) && all(greaterThanEqual(q, ivec2(0))) && all(lessThanEqual(q, ivec2(last)))) {
                uvec4 w = texelFetch(spsmMap, q, 0);
                if (!spsmEmpty(w)) {
                    int test = spsmTriangleTest(spsmUnpack(w, shadowMapSize), x, r.coord.z, bias);
                    hit = hit || test == 2;
                    covered = covered || test == 1;
                }
            }
        }
    }
    if (hit) {
        visibility = 0.0;
        branch = SPSM_BRANCH_NEIGHBOUR_HIT;
        return;
    }
    if (covered) {
        visibility = 1.0;
        branch = SPSM_BRANCH_NEIGHBOUR_COVER;
        return;
    }
    SpsmTriangle tris[9];
    uint occluding = 0u;
    for (int k = 0; k < 9; ++k) {
        ivec2 q = clamp(t + ivec2(k % 3 - 1, k / 3 - 1), ivec2(0), ivec2(last));
        uvec4 w = texelFetch(spsmMap, q, 0);
        tris[k] = spsmUnpack(w, shadowMapSize);
        if (!spsmEmpty(w) && spsmOccludesByDepth(tris[k], vec2(q) + 0.5, r.coord.z, bias))
            occluding |= 1u << uint(k);
    }
    if (reconstruction == 1 && occluding != 0u && occluding != 511u) {
        SpsmEdge e = spsmReconstructEdge(tris, occluding, x, vec2(t) + 0.5);
        if (e.decided == 1) {
            visibility = 1.0 - e.shadowed;
            branch = SPSM_BRANCH_EDGE;
            return;
        }
    }
    // Fallback: the depth comparison with p's own texel; without reconstruction (Dai et al. 2008)
    // a ray that met no stored triangle is lit (their false negatives where triangles were lost).
    visibility = reconstruction == 1 && ((occluding >> 4u) & 1u) != 0u ? 0.0 : 1.0;
    branch = SPSM_BRANCH_FALLBACK;
#endif
}
