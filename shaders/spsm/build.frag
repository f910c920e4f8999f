// spsm build: writes the packed triangle, with as its depth the triangle's plane at the texel's
// centre, extrapolated where the triangle does not cover the centre (1/z is affine, so that is
// exact for the plane): the depth test keeps, per texel, the triangle whose plane is nearest at the
// centre among those touching the texel. For a triangle that covers the centre this is the usual
// depth test; for one that only touches the texel it ranks the triangle by where its plane would
// be, so a steep triangle at an occluder's silhouette (whose nearest point is where it joins the
// face-on triangles) keeps the texels it extends into instead of losing them to its neighbours
// (techniques/spsm/README.md, "which triangle a texel keeps", measures both rules). With
// conservative rasterization (CONSERVATIVE, or the driver's) a fragment whose texel the triangle
// does not touch (spsmTouchesTexel: the separating-axis test) is dropped;
// without it, the fragments are the rasterizer's centre samples.
#include "../shared/spsm.glsl"
flat in uvec4 packedTriangle;
uniform float smSize;
uniform float nearZ;
layout(location = 0) out uvec4 stored;

void main() {
    SpsmTriangle t = spsmUnpack(packedTriangle, smSize);
#if defined(CONSERVATIVE) || defined(HARDWARE_CONSERVATIVE)
    if (!spsmTouchesTexel(t, floor(gl_FragCoord.xy))) discard;
#endif
    float w = spsmInverseDepthAt(t, floor(gl_FragCoord.xy) + 0.5);
    // Reversed depth: nearZ / z, 1 at the near plane (the depth test keeps the greatest); a plane
    // that passes behind the light at the centre ranks last.
    gl_FragDepth = w > 0.0 ? clamp(nearZ * w, 1e-30, 1.0) : 1e-30;
    stored = packedTriangle;
}
