// Penumbra estimation of the shadow-map filtering family: PCSS (Fernando 2005, recapped in
// buades2015 sec. 2, eq. 1) and separable soft shadow mapping (buades2015 sec. 4). Blocker search
// region, blocker averaging, penumbra width (eq. 1), kernel sizes, the reuse criteria alpha and
// beta, and the filter weights (sec. 4.4). Common GLSL/C++ subset: see shaders/shared/shared.h.
//
// Depths are light-view depths z (world units along the light's axis, as the shadow maps store
// them); the light plane is at z = 0. Kernel widths are full widths in texels or pixels.
#ifndef SHADOWLAB_PENUMBRA_GLSL
#define SHADOWLAB_PENUMBRA_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// Filter choices of the `filter` parameter (buades2015 sec. 4.4) and PCSS's sampling `pattern`.
const int FILTER_GAUSSIAN = 0;
const int FILTER_MEAN = 1;
const int PATTERN_REGULAR = 0;
const int PATTERN_POISSON = 1;

// Largest kernel width a shadow map of smSize texels can use: from any texel every other texel is
// reachable within a radius of smSize - 1, so a width of 2 smSize - 1 (a larger kernel only reads
// clamped border texels again). The documented clamp of `blocker_kernel` and `filter_kernel`.
SHARED_FN float maxKernelForMap(float smSize) {
    return max(2.0f * smSize - 1.0f, 1.0f);
}

// Blocker search region (Fernando 2005; buades2015 sec. 4: "the evaluated area is determined by n,
// which depends on the size of the light source and the distance d"). Blockers of a receiver at
// depth zReceiver lie in the pyramid from the receiver to the light square (width w_l); at depth z
// its cross-section is w_l (zReceiver - z) / zReceiver wide, i.e. that divided by one texel's
// world size 2 z tanHalfFov / smSize. The widest section is at the nearest possible caster, the
// light frustum's near plane zNear. Returns that width in texels, clamped to [1, maxKernel] (the
// paper's n) and to the map (maxKernelForMap).
SHARED_FN float blockerSearchWidthTexels(float lightWidth, float zReceiver, float zNear, float tanHalfFov, float smSize,
                                         float maxKernel) {
    float zn = max(zNear, 1e-6f * max(zReceiver, 1e-6f));
    float across = max(zReceiver - zn, 0.0f) / max(zReceiver, 1e-20f);
    float texelAtNear = 2.0f * zn * tanHalfFov / smSize;
    float width = max(lightWidth, 0.0f) * across / max(texelAtNear, 1e-20f);
    float cap = min(max(maxKernel, 1.0f), maxKernelForMap(smSize));
    return clamp(width, 1.0f, cap);
}

// One tap of the blocker search (buades2015 sec. 4, blocker_sum and blocker_count): a stored depth
// dm is a blocker when it lies in front of the receiver by more than the bias (dm < d - bias; the
// paper's Fig. 2 "a bias of 1 has been taken into account"). acc = (sum, count).
SHARED_FN vec2 accumulateBlocker(vec2 acc, float storedZ, float zReceiver, float bias) {
    if (storedZ < zReceiver - bias) {
        return vec2(acc.x + storedZ, acc.y + 1.0f);
    }
    return acc;
}

// blocker_average = blocker_sum / blocker_count; -1 when no blocker was found (the pixel is lit:
// "in the case that no potential blockers were found ... it is considered as being totally
// illuminated", buades2015 sec. 4.2).
SHARED_FN float averageBlockerDepth(vec2 sumCount) {
    if (sumCount.y <= 0.0f) {
        return -1.0f;
    }
    return sumCount.x / sumCount.y;
}

// buades2015 eq. 1 (Fernando 2005): w_penumbra = w_light (z_receiver - z_avg) / z_avg, the width
// of the penumbra on the receiver (world units) when light, occluder and receiver are parallel.
// No blocker (zAvg < 0) or a blocker at the receiver's depth: 0 (hard shadow at contact). A blocker
// at the light (zAvg -> 0) makes eq. 1 grow without bound; zAvg is kept >= 1e-6 zReceiver so the
// result stays finite, and the kernel caps (n, m) bound the cost.
SHARED_FN float penumbraWidth(float lightWidth, float zReceiver, float zAvg) {
    if (zAvg < 0.0f || lightWidth <= 0.0f) {
        return 0.0f;
    }
    float z = max(zAvg, 1e-6f * max(zReceiver, 1e-6f));
    return lightWidth * max(zReceiver - z, 0.0f) / z;
}

// The penumbra as a PCF kernel in the shadow map (PCSS): its width on the receiver divided by the
// world size of a texel at the receiver's depth, clamped to [1, maxKernel] (the paper's m) and to
// the map.
SHARED_FN float penumbraKernelTexels(float penumbraWorld, float zReceiver, float tanHalfFov, float smSize,
                                     float maxKernel) {
    float texel = 2.0f * max(zReceiver, 1e-20f) * tanHalfFov / smSize;
    float cap = min(max(maxKernel, 1.0f), maxKernelForMap(smSize));
    return clamp(penumbraWorld / texel, 1.0f, cap);
}

// The penumbra as a screen-space kernel (SSSM): its width on the receiver divided by the world
// length one pixel step covers on the receiver's tangent plane, clamped to [1, maxKernel] (m).
SHARED_FN float penumbraKernelPixels(float penumbraWorld, float worldPerPixel, float maxKernel) {
    return clamp(penumbraWorld / max(worldPerPixel, 1e-20f), 1.0f, max(maxKernel, 1.0f));
}

// Step-2 reuse (buades2015 sec. 4): the horizontal blocker result of a neighbour p_t at light depth
// d_t serves the pixel at light depth d when |d - d_t| < alpha. alpha = 0 never reuses (every row
// is read from the depth map: exact PCSS blocker search).
SHARED_FN bool reuseBlockerRow(float d, float dT, float alpha) {
    return abs(d - dT) < alpha;
}

// Step-3 reuse (buades2015 sec. 4, 4.2): the horizontal blur of a neighbour is reused when its
// camera depth is within beta of the depth the pixel's own surface has at that neighbour, i.e. the
// camera-depth distance "modified taking into account the normal of the pixel p": planeDepth is
// the depth of p's tangent plane along the neighbour's view ray.
SHARED_FN bool reuseShadowRow(float neighbourDepth, float planeDepth, float beta) {
    return abs(neighbourDepth - planeDepth) < beta;
}

// Camera depth of the plane through a point at view-space position pView with view-space normal
// nView, along the view ray through ndc (x, y) of a perspective camera with tanHalfFovY and aspect.
// The ray is t (ndc.x tanHalfFovY aspect, ndc.y tanHalfFovY, -1); the plane meets it at depth
// t = dot(n, p) / dot(n, dir). Grazing planes (|dot(n, dir)| tiny) return -1: no depth.
SHARED_FN float tangentPlaneDepth(vec3 pView, vec3 nView, vec2 ndc, float tanHalfFovY, float aspect) {
    vec3 dir = vec3(ndc.x * tanHalfFovY * aspect, ndc.y * tanHalfFovY, -1.0f);
    float denom = dot(nView, dir);
    if (abs(denom) < 1e-6f) {
        return -1.0f;
    }
    float t = dot(nView, pView) / denom;
    return t > 0.0f ? t : -1.0f;
}

// The same plane as an affine function of ndc: 1 / depth is affine in the view ray's ndc for any
// plane, so a kernel loop steps it with one multiply-add and one division per tap instead of
// intersecting a ray. Returns (1/depth at ndc, d(1/depth)/d ndc.x, d(1/depth)/d ndc.y); a plane
// through the eye gives (-1, 0, 0). 1/depth <= 0 at some ndc: the plane is behind the ray (no depth).
SHARED_FN vec3 planeInverseDepth(vec3 pView, vec3 nView, vec2 ndc, float tanHalfFovY, float aspect) {
    float c = dot(nView, pView);
    if (abs(c) < 1e-7f * length(pView)) {
        return vec3(-1.0f, 0.0f, 0.0f);
    }
    float gx = nView.x * tanHalfFovY * aspect / c;
    float gy = nView.y * tanHalfFovY / c;
    return vec3(gx * ndc.x + gy * ndc.y - nView.z / c, gx, gy);
}

// Weight of the tap at integer offset i of a kernel of full width `width` (buades2015 sec. 4.4).
// Mean: the box [-width/2, width/2] covering tap i's unit cell (so fractional widths vary
// continuously; the weights sum to width). Gaussian: exp(-x^2 / (2 sigma^2)) at x = i / (width/2),
// the paper's N(0, 0.5) over the kernel's half-width for sigma = 0.5, cut at the box's edge.
SHARED_FN float kernelWeight(float i, float width, int filterKind, float sigma) {
    float r = 0.5f * width;
    float cover = clamp(min(r, i + 0.5f) - max(-r, i - 0.5f), 0.0f, 1.0f);
    if (filterKind == FILTER_MEAN) {
        return cover;
    }
    float x = i / max(r, 0.5f);
    float s = max(sigma, 1e-3f);
    return cover * exp(-0.5f * x * x / (s * s));
}

// Taps a kernel of full width `width` needs on each side of its centre: ceil(width/2 - 1/2), so a
// width 1 kernel is the centre tap alone. Loops run to this, not to the cap (the cost follows the
// penumbra, not the largest kernel allowed).
SHARED_FN int kernelRadius(float width) {
    return int(ceil(max(0.5f * width - 0.5f, 0.0f)));
}

#endif
