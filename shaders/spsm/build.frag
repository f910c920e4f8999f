// spsm build: writes the packed triangle, with as its depth its rank (spsmRankInverseDepth): the
// triangle's plane at the texel's centre, extrapolated where the triangle does not cover the centre
// and then moved back by SPSM_RANK_MARGIN of the depth. For a triangle that covers the centre this
// is the usual depth test; one that only touches the texel takes it when its plane there is nearer
// by more than the margin, so a steep triangle at an occluder's silhouette (whose nearest point is
// where it joins the face-on triangles) keeps texels along the silhouette instead of losing them
// all, while the neighbouring facets of a smooth surface (nearer only by their small sagitta) do not
// take a texel from the facet that covers it (techniques/spsm/README.md, "which triangle a texel
// keeps", measures the rules). With
// conservative rasterization (CONSERVATIVE, or the driver's) a fragment whose texel the triangle
// does not touch (spsmTouchesTexel: the separating-axis test) is dropped;
// without it, the fragments are the rasterizer's centre samples.
#include "../shared/spsm.glsl"
flat in uvec4 packedTriangle;
uniform float smSize;
uniform float nearZ;
#ifndef MARGIN
#define MARGIN 0.05
#endif
layout(location = 0) out uvec4 stored;

void main() {
    SpsmTriangle t = spsmUnpack(packedTriangle, smSize);
#if defined(CONSERVATIVE) || defined(HARDWARE_CONSERVATIVE)
    if (!spsmTouchesTexel(t, floor(gl_FragCoord.xy))) discard;
#endif
    float w = spsmRankInverseDepth(t, floor(gl_FragCoord.xy) + 0.5);
    // Reversed depth: nearZ / z, 1 at the near plane (the depth test keeps the greatest); a plane
    // that passes behind the light at the centre ranks last.
    gl_FragDepth = w > 0.0 ? clamp(nearZ * w, 1e-30, 1.0) : 1e-30;
    stored = packedTriangle;
}
