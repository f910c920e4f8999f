// What the spsm look-up's steps share (lecocq2014, "At the rendering stage"; lookup.comp, lookup_texel.frag):
// the maps, the lists, and the receiver's preparation: background, facing away from the light centre
// and outside the light's frustum are decided before any stored triangle is read.
#ifndef SHADOWLAB_SPSM_LOOKUP_COMMON_GLSL
#define SHADOWLAB_SPSM_LOOKUP_COMMON_GLSL
#include "../common/gbuffer_access.glsl"
#include "../common/shadow_lookup.glsl"
#include "../shared/tangent_plane.glsl"
#include "../shared/spsm.glsl"
#include "branches.glsl"

// counts: [0] list 1's length, [1..3] step 3's dispatch, [4] list 2's length, [5..7] step 5's
// (64 invocations a group, groups in rows of SPSM_ROW: a 4K frame's list exceeds the 65535 groups
// one row allows).
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) buffer List1 { uint list1[]; };  // x | y << 16
layout(std430, binding = 2) buffer List2 { uint list2[]; };
uniform usampler2D spsmMap;

uint packPixel(ivec2 pixel) { return uint(pixel.x) | (uint(pixel.y) << 16u); }

// A receiver as the look-up sees it: decided (v, branch) before any triangle, or its texel
// coordinate x in SPSM space, its texel t, its light-view depth and its bias.
struct SpsmReceiver {
    bool decided;
    float v;
    float branch;
    vec2 x;
    ivec2 t;
    int last;  // the map's last texel index
    float z;
    float bias;  // the triangle tests add each triangle's packing error
};

SpsmReceiver spsmPrepareReceiver(ivec2 pixel) {
    SpsmReceiver q;
    q.decided = true;
    q.v = 1.0;
    q.branch = SPSM_BRANCH_NONE;
    q.x = vec2(0.0);
    q.t = ivec2(0);
    q.last = int(shadowMapSize) - 1;
    q.z = 0.0;
    q.bias = 0.0;
    if (isBackground(pixel)) return q;
    vec3 p = worldPosition(pixel);
    vec3 n = worldNormal(pixel);
    if (!inFrontOfTangentPlane(p, n, lightPosition)) {  // the visibility convention at the light centre
        q.v = 0.0;
        q.branch = SPSM_BRANCH_FACING_AWAY;
        return q;
    }
    ShadowReceiver r = prepareShadowReceiver(p, n);
    if (r.coord.w == 0.0) {  // outside the light's frustum: lit, as for `hard`
        q.branch = SPSM_BRANCH_EMPTY;
        return q;
    }
    q.decided = false;
    q.x = r.coord.xy * shadowMapSize;
    q.t = clamp(ivec2(floor(q.x)), ivec2(0), ivec2(q.last));
    q.z = r.coord.z;
    q.bias = r.bias;
    return q;
}
#endif
