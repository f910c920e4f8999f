// What the visibility passes of ssm-gbp06 and ssm-contour share (guennebaud2007 sec. 3-5): the
// maps they read, the per-level depth access of the light-space multi-resolution (sec. 5.1) and
// the per-pixel driver `pixelVisibility`: classification, then the occluded area at the level (or
// two blended levels) the technique picks, times the light-front fraction. The technique's file,
// included before visibility_levels.glsl, defines `float occludedAreaAtLevel(int level, float w)`
// (the occluded light area from p at HSM level `level` with the level-0 kernel width w) and
// `vec3 chooseLevels(float w, float zOcc)` (lod, the other level, its weight). The C++ mirror for
// --pixel is techniques/hsm/hsm.cpp and each technique's .cpp.
#ifndef SHADOWLAB_BACKPROJECTION_VISIBILITY_COMMON_GLSL
#define SHADOWLAB_BACKPROJECTION_VISIBILITY_COMMON_GLSL
#include "receiver.glsl"
#include "../common/light_front.glsl"
uniform sampler2D shadowMap;       // light-view depth z (R32F), HSM level 0
uniform sampler2D hsm;             // HSM levels 1, 2, ... as mip levels 0, 1, ...: (min, max)
uniform int hsmTopLevel;           // the 1x1 HSM level
uniform sampler2D kernelSize;      // from kernel.frag
uniform sampler2D classification;  // from kernel.frag
uniform sampler2D occluderDepth;   // z_occ from kernel.frag (sec. 5.1)
// BP_LIGHT_SQUARE or BP_LIGHT_DISK, a compile-time constant: the host compiles one variant per
// shape (define BP_LIGHT_SHAPE, hsm.cpp: backprojectionVisibilityDefines). llvmpipe runs both sides
// of a branch on a uniform, so with a uniform shape every back-projected quad (ssm-gbp06) and edge
// (ssm-contour) of a square light also paid the disk's radial integration: on plant at 384x384 the
// gbp06 visibility pass took 63 ms with the uniform and 34 ms with the constant.
const int lightShape = BP_LIGHT_SHAPE;
uniform float lightHalfSize;       // w_l / 2 or r: the unit of light coordinates
uniform float lightWidthWorld;     // w_l (eq. 1)
uniform float maxKernelTexels;     // the `max_kernel` cap
uniform float kernelThreshold;     // t_k, texels of the level (eq. 2)

BpReceiver receiver;
// What the multi-resolution chose for the current pixel (the `light_levels` internal): lambda
// (eq. 3; GBP06: eq. 2's level), the level walked, the level blended in and its weight.
float chosenLambda = 0.0;
vec3 chosenLevels = vec3(0.0);

// Min depth of HSM level `level` at its texel t (level 0: the map); no caster outside the level.
// Without LIGHT_MULTIRES (the variant `light_multires` off compiles) every level is 0 and the
// compiler folds the level arithmetic away: llvmpipe runs both sides of a per-pixel branch, so the
// full-resolution walk must not pay for the HSM fetch it never uses.
// With it, every level's min depth is one fetch of `depthLevels`, an atlas of two layers: the map
// (layer 0) and the HSM levels 1, 2, ... side by side (layer 1, hsmLevelAtlasX; the hsm pass writes
// them), fetched at level of detail 0: not a branch between two textures, and not a mip level
// chosen per pixel, which llvmpipe pays on every fetch (on plant at 384x384 the gbp06 visibility
// pass took about 35 ms with the mip pyramid, 27 ms with the atlas).
#ifdef LIGHT_MULTIRES
uniform sampler2DArray depthLevels;
#endif
float levelDepth(int level, ivec2 t, int levelSize) {
    if (t.x < 0 || t.y < 0 || t.x >= levelSize || t.y >= levelSize) return 3.4e38;
#ifdef LIGHT_MULTIRES
    return texelFetch(depthLevels, ivec3(t.x + hsmLevelAtlasX(level, int(shadowMapSize)), t.y, min(level, 1)), 0).r;
#else
    return texelFetch(shadowMap, t, 0).r;
#endif
}

bool levelOccludes(int level, ivec2 t, float z, int levelSize) {
    return bpLevelSampleOccludes(receiver, level, t, z, shadowMapSize, lightTanHalfFov);
}

// The occlusion bits of `count` (at most 32) samples of row y of level `level` from x0: bit i for
// the sample x0 + i (backprojection.glsl section 9).
uint rowOcclusionBits(int level, int x0, int y, int count, int levelSize) {
    uint bits = 0u;
    for (int i = 0; i < count; ++i) {
        ivec2 t = ivec2(x0 + i, y);
        if (levelOccludes(level, t, levelDepth(level, t, levelSize), levelSize)) bits |= 1u << uint(i);
    }
    return bits;
}

// The 2x2 samples of level `level` whose lower-left sample is t, from one gather:
// (t, t + (1, 0), t + (1, 1), t + (0, 1)); the no-caster marker outside the level, as levelDepth.
// On llvmpipe a gather costs about three texel fetches: it pays where all four samples are used
// (the occlusion bits of two rows; a contour block's four depths: ssm-contour's visibility pass on
// plant at 384x384 went 102 -> 88 ms), not for ssm-gbp06's quad (its sample and two neighbours:
// 24.1 -> 25.4 ms, so gbp06_area.glsl keeps its three fetches).
vec4 levelDepthQuad(int level, ivec2 t, int levelSize) {
#ifdef LIGHT_MULTIRES
    vec2 uv = vec2(float(t.x + hsmLevelAtlasX(level, int(shadowMapSize)) + 1), float(t.y + 1)) / shadowMapSize;
    vec4 g = textureGather(depthLevels, vec3(uv, float(min(level, 1))));
#else
    vec4 g = textureGather(shadowMap, vec2(t + 1) / shadowMapSize);
#endif
    // gather's order: (x, y+1), (x+1, y+1), (x+1, y), (x, y); the footprint at its shared corner.
    bvec2 in0 = bvec2(t.x >= 0 && t.x < levelSize, t.y >= 0 && t.y < levelSize);
    bvec2 in1 = bvec2(t.x + 1 >= 0 && t.x + 1 < levelSize, t.y + 1 >= 0 && t.y + 1 < levelSize);
    return vec4(in0.x && in0.y ? g.w : 3.4e38, in1.x && in0.y ? g.z : 3.4e38, in1.x && in1.y ? g.y : 3.4e38,
                in0.x && in1.y ? g.x : 3.4e38);
}

// The occlusion bits of two rows, y and y + 1, of `count` (at most 32) samples from x0, as
// rowOcclusionBits for each: one gather of the 2x2 samples (x, y) .. (x + 1, y + 1) per two columns,
// a quarter of the fetches (on plant at 384x384 the visibility pass went 36 -> 24 ms for ssm-gbp06,
// 148 -> 105 ms for ssm-contour; techniques/ssm-contour/README.md). Samples outside the level
// (the gather reads the next level of the atlas, or the clamped border) do not occlude, as in
// levelDepth.
void rowPairOcclusionBits(int level, int x0, int y, int count, int levelSize, out uint lower, out uint upper) {
    lower = 0u;
    upper = 0u;
    for (int i = 0; i < count; i += 2) {
        ivec2 t = ivec2(x0 + i, y);
        vec4 z = levelDepthQuad(level, t, levelSize);
        bool right = i + 1 < count;
        if (levelOccludes(level, t, z.x, levelSize)) lower |= 1u << uint(i);
        if (right && levelOccludes(level, t + ivec2(1, 0), z.y, levelSize)) lower |= 1u << uint(i + 1);
        if (levelOccludes(level, t + ivec2(0, 1), z.w, levelSize)) upper |= 1u << uint(i);
        if (right && levelOccludes(level, t + ivec2(1, 1), z.z, levelSize)) upper |= 1u << uint(i + 1);
    }
}

// Level coordinates of level `level` to map texel coordinates.
float levelScale(int level) { return float(1 << level); }

// The receiver's current point back-projected from level coordinates u at depth z.
vec2 backprojectLevel(vec2 u, int level, float z) {
    return backprojectToLight(receiver.position, u * levelScale(level), z, shadowMapSize, lightTanHalfFov, lightHalfSize);
}
#endif
