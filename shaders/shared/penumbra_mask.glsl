// Penumbra volume mask filtering (cournia2005 chapter 5): the simplified per-edge volumes of the
// mask (sec. 5.1), the percentage-closer filter's width (sec. 5.2), its jittered n_pcf x n_pcf
// samples and the object-id-aware blur (sec. 5.3). The math shared by techniques/pvmf/ (CPU volume
// geometry, the per-pixel record), shaders/pvmf/ and the tests. Common GLSL/C++ subset (see
// shaders/shared/shared.h). World space; l is the light's centre; edges run clockwise seen from the
// light as in penumbra_volumes.glsl.
#ifndef SHADOWLAB_PENUMBRA_MASK_GLSL
#define SHADOWLAB_PENUMBRA_MASK_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

#include "light_sampling.glsl"
#include "penumbra_volumes.glsl"

// The ends of an edge's volume: PVMF_START at e0, PVMF_END at e1.
const float PVMF_START = -1.0f;
const float PVMF_END = 1.0f;

// d_e = min(|e0 - l|, |e1 - l|): the distance from the light centre to the edge the mask stores
// beside the volume's depth (sec. 5.1).
SHARED_FN float pvmfEdgeDistance(vec3 e0, vec3 e1, vec3 l) {
    return min(length(e0 - l), length(e1 - l));
}

// An edge end point moved towards the light centre by the same distance for both ends (sec. 5.1):
// e^ = e - d_e (e - l) / |e - l| s_e, s_e in (0, 1] the overestimation; a point at the light stays.
// Written l + (e - l)(1 - d_e s_e / |e - l|): the nearer end with s_e = 1 lands exactly on l (the
// factor is exactly 0), where e - (e - l) would leave a rounding residue whose direction is noise.
SHARED_FN vec3 pvmfMovedPoint(vec3 e, float edgeDistance, vec3 l, float se) {
    float len = length(e - l);
    if (len <= 0.0f) {
        return e;
    }
    return l + (e - l) * (1.0f - edgeDistance * se / len);
}

// The extrusion vector at one end of the moved edge e^0 -> e^1 (sec. 5.1), unit length:
//   v = (e^ - l) + r (end e - side n) / |...|
// with e = (e^1 - e^0) / |e^1 - e^0|, n the edge's hard shadow plane normal (pvmPlaneNormal: away
// from the occluder), side = PVM_OUTER (-1: the outer volume leans along +n, away from the occluder,
// as from pvm's displaced light d^- = l - r n) or PVM_INNER (+1: towards the occluder), end =
// PVMF_START at e^0 and PVMF_END at e^1. n is the caller's pvmPlaneNormal(e0, e1, l) of the edge
// before it moved: the moved points stay on their rays from l, so the plane is the same, and with
// s_e near 1 the nearer end lands on l, where the plane through l, e^0 and e^1 is not defined. Two
// departures from the printed vectors (README.md): e and n are scaled by the light radius r, so that
// the volume opens as the edge's penumbra does (the printed unit vectors open it by about
// 1 / |e^ - l| radians whatever the light's size), and the ends lean outwards along the edge (the
// printed +e at e^0 and -e at e^1 lean inwards, narrowing the volume along the edge and leaving gaps
// outside the silhouette's convex corners). An edge whose line passes through the light (n = 0)
// extrudes away from the light along e alone; one whose both ends moved onto l (e = 0) along -side n.
SHARED_FN vec3 pvmfExtrusion(vec3 eHat, vec3 eHat0, vec3 eHat1, vec3 n, vec3 l, float r, float end, float side) {
    vec3 e = eHat1 - eHat0;
    float len = length(e);
    e = len > 0.0f ? e / len : vec3(0.0f);
    vec3 v = eHat - l + r * (end * e - side * n);
    float vl = length(v);
    return vl > 0.0f ? v / vl : vec3(0.0f);
}

// The percentage-closer filter's width in shadow-map texture coordinates (a fraction of the map's
// width), sec. 5.2: w_pcf = s_p (d_r - d_o) r / (2 d_o d_r tan(alpha / 2)), d_r the receiver's and
// d_o the occluder edges' distance from the light, alpha the light's field of view. 0 when the
// receiver is not beyond the edges (d_r <= d_o) or d_o is unknown (<= 0).
SHARED_FN float pvmfFilterWidth(float sp, float dr, float dO, float r, float tanHalfFov) {
    if (dO <= 0.0f || dr <= dO || tanHalfFov <= 0.0f) {
        return 0.0f;
    }
    return sp * (dr - dO) * r / (2.0f * dO * dr * tanHalfFov);
}

// The seed of a pixel's jitter: the user's seed and the pixel, hashed (the same pixel and seed give
// the same samples in every frame, so the result is reproducible and cached).
SHARED_FN uint pvmfPixelSeed(uint seed, uint x, uint y) {
    return pcgHash(seed * 0x9E3779B9u ^ pcgHash(x + pcgHash(y)));
}

// Sample i of the n_pcf x n_pcf cell grid of the filter (sec. 5.2), jittered in its cell: an offset
// from the filter's centre in units of its width, each coordinate in [-1/2, 1/2). The grid is the
// stratification of light_sampling.glsl with n_pcf^2 samples (n_pcf rows of n_pcf cells).
SHARED_FN vec2 pvmfSampleOffset(uint i, uint npcf, uint pixelSeed) {
    vec3 s = stratifiedSample(i, npcf * npcf, pixelSeed);
    return vec2(s.x - 0.5f, s.y - 0.5f);
}

// The blur's taps on a frame `frameHeight` pixels high: n_blur counts taps on sec. 5.5's 512 x 512
// visibility buffer ("all texture maps are 512x512 pixels with n_blur = 12"), so the blur covers the
// same share of the picture at any frame size: round(n_blur frameHeight / 512). A fixed count would
// blur a 128-pixel frame's penumbrae over four times their share (measured on sphere-light at
// 128 x 128: RMSE 0.060 against raytraced with 12 taps, see techniques/pvmf/README.md).
SHARED_FN int pvmfBlurTaps(int nBlur, int frameHeight) {
    return int(floor(float(nBlur) * float(frameHeight) / 512.0f + 0.5f));
}

// B of sec. 5.3: a blur tap counts when its texel shows the same object as the texel being blurred
// (ids from the G-buffer; the background, id < 0, matches nothing) and some of the light is in front
// of the tap's tangent plane (frontTap > 0, lightFractionInFront). The blur averages the filter's
// estimate, v / front: the front fraction is exact geometry, not jitter noise, and is multiplied
// back with the blurred pixel's own. A tap turned away from the light (front 0) holds no estimate:
// its 0 is the convention's, and averaging it in would darken the lit faces beside it on the same
// object (a box's faces meet at its edges).
SHARED_FN float pvmfBlurWeight(float idCentre, float idTap, float frontTap) {
    return (idCentre >= 0.0f && idTap == idCentre && frontTap > 0.0f) ? 1.0f : 0.0f;
}

#endif
