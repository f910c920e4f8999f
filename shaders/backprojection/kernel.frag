// guennebaud2007 sec. 3: the kernel ("search area" of GBP06) and the classification of each pixel.
//  1. first estimate from the global min depth z_min, the top HSM level (eq. 1);
//  2. refinement: the local min z'_min over the kernel read at level floor(log2 w_k), where the
//     kernel is "just below one pixel", gives a tighter w_k (eq. 1 again), until it stops shrinking;
//  3. the kernel's depth bounds (HSM min, max) against z_p: lit, umbra or penumbra.
// The C++ mirror for --pixel is techniques/hsm/hsm.cpp: computeKernel.
#include "receiver.glsl"
uniform sampler2D shadowMap;    // HSM level 0: light-view depth z (R32F)
uniform sampler2D hsm;          // HSM levels 1, 2, ... as mip levels 0, 1, ...: (min, max) depth per texel
uniform int hsmTopLevel;        // the 1x1 HSM level
uniform float lightWidthWorld;  // w_l: the square's width, the disk's diameter
layout(location = 0) out float kernelSize;        // converged w_k, texels (0: lit by the top level)
layout(location = 1) out float kernelIterations;  // refinement steps taken
layout(location = 2) out float classification;    // BP_CLASS_*: 0 umbra, 0.5 penumbra, 1 lit
layout(location = 3) out float occluderDepth;     // z_occ (sec. 5.1), the smooth occluder depth hint; 0 when lit

const int kMaxRefinements = 32;  // w_k shrinks every step; a 8192^2 map converges in far fewer

// (min, max) of HSM level `level` >= 1 at texel t, and the map's depth (HSM level 0) at t. They
// are two functions, not one with `level == 0 ? map : pyramid`: llvmpipe fetches both sides of a
// per-pixel select, so every texel of every refinement step paid the map's fetch too (on plant at
// 384x384 with ssm-gbp06 the pass took 15.2-16.4 ms with the select, 13.3-13.9 without, three
// alternated rounds). Level 0 is read only where the kernel is below two texels
// (hsmRefinementLevel), in its own loop below, which a group of pixels whose kernels are all wider
// leaves after zero trips. The z_occ hint's four texels (levelMinDepth) keep the select: they are
// read once per pixel, and the same two-loop split there measured no different.
vec2 pyramidTexel(int level, ivec2 t) { return texelFetch(hsm, t, level - 1).rg; }
float mapTexel(ivec2 t) { return texelFetch(shadowMap, t, 0).r; }

// The min depth of HSM level `level` at t; the no-caster marker outside the level.
float levelMinDepth(int level, ivec2 t, int levelSize) {
    if (t.x < 0 || t.y < 0 || t.x >= levelSize || t.y >= levelSize) return 3.4e38;
    return level == 0 ? mapTexel(t) : pyramidTexel(level, t).x;
}

// The kernel's (min, max) depth bounds over the texels of HSM level `level` >= 1 it overlaps, and
// the same over the map's texels (level 0).
vec2 pyramidBounds(ivec4 rangeL, int level) {
    vec2 bounds = vec2(3.4e38, -3.4e38);
    for (int y = rangeL.y; y <= rangeL.w; ++y)
        for (int x = rangeL.x; x <= rangeL.z; ++x) {
            vec2 t = pyramidTexel(level, ivec2(x, y));
            bounds = vec2(min(bounds.x, t.x), max(bounds.y, t.y));
        }
    return bounds;
}
vec2 mapBounds(ivec4 range) {
    vec2 bounds = vec2(3.4e38, -3.4e38);
    for (int y = range.y; y <= range.w; ++y)
        for (int x = range.x; x <= range.z; ++x) {
            float z = mapTexel(ivec2(x, y));
            bounds = vec2(min(bounds.x, z), max(bounds.y, z));
        }
    return bounds;
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    kernelSize = 0.0;
    kernelIterations = 0.0;
    classification = BP_CLASS_LIT;
    occluderDepth = 0.0;
    if (isBackground(pixel)) return;
    BpReceiver r = prepareReceiver(pixel);
    if (r.inside == 0.0) return;
    int size = int(shadowMapSize);
    float zp = r.position.z;
    float zMin = pyramidTexel(hsmTopLevel, ivec2(0)).x;
    if (zMin >= zp - r.bias) return;  // nothing in the whole map is in front of p
    // Eq. 1; a kernel wider than twice the map covers it whatever its centre.
    float w = min(hsmKernelTexels(lightWidthWorld, shadowMapSize, lightTanHalfFov, zMin, zp), 2.0 * shadowMapSize);
    vec2 bounds = vec2(zMin, 3.4e38);
    float planeMin = 0.0;
    int lastLevel = 0;
    // The refinement steps on HSM levels >= 1, then those on the map: w only shrinks, so once below
    // two texels (level 0) it stays there. Each step: the kernel's bounds at the level, then stop
    // where they say lit or where the refined kernel no longer shrinks.
    bool done = false;
    int step = 0;
    for (; step < kMaxRefinements; ++step) {
        int level = hsmRefinementLevel(w, hsmTopLevel);
        if (level == 0) break;  // the map's steps, below
        lastLevel = level;
        int levelSize = hsmLevelSize(level, size);
        ivec4 rangeL = levelTexelRange(kernelTexelRange(r.centre, w, size), level, levelSize);
        bounds = pyramidBounds(rangeL, level);
        planeMin = regionPlaneDepthMin(r, levelRegionTexels(rangeL, level, levelSize, size), shadowMapSize, lightTanHalfFov);
        kernelIterations += 1.0;
        float refined = hsmKernelTexels(lightWidthWorld, shadowMapSize, lightTanHalfFov, bounds.x, zp);
        if (bounds.x >= zp - r.bias || refined >= w) {  // lit (classified below), or converged
            done = true;
            break;
        }
        w = refined;
    }
    for (; !done && step < kMaxRefinements; ++step) {
        lastLevel = 0;
        ivec4 range = kernelTexelRange(r.centre, w, size);
        bounds = mapBounds(range);
        planeMin = regionPlaneDepthMin(r, levelRegionTexels(range, 0, size, size), shadowMapSize, lightTanHalfFov);
        kernelIterations += 1.0;
        float refined = hsmKernelTexels(lightWidthWorld, shadowMapSize, lightTanHalfFov, bounds.x, zp);
        if (bounds.x >= zp - r.bias || refined >= w) break;
        w = refined;
    }
    kernelSize = w;
    classification = bpClassify(r, bounds, planeMin);
    if (classification == BP_CLASS_LIT) return;
    // z_occ (sec. 5.1): the occluding min depths of the four texels of the refinement level around
    // p', bilinearly weighted (techniques/hsm/hsm.cpp: computeKernel mirrors it).
    int n = hsmLevelSize(lastLevel, size);
    vec2 u = r.centre / float(1 << lastLevel) - 0.5;
    ivec2 i0 = ivec2(floor(u));
    vec4 d = vec4(levelMinDepth(lastLevel, i0, n), levelMinDepth(lastLevel, i0 + ivec2(1, 0), n),
                  levelMinDepth(lastLevel, i0 + ivec2(1, 1), n), levelMinDepth(lastLevel, i0 + ivec2(0, 1), n));
    occluderDepth = occluderDepthHint(d, u - floor(u), zp - r.bias, bounds.x);
}
