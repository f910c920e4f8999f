// Pull-push reconstruction of a sparse screen-space visibility buffer (guennebaud2007 sec. 5.2,
// "Pull-push reconstruction", after Gortler et al. 1996 [GGSC96]): the per-texel math shared by
// shaders/common/pull_push_pull.comp, pull_push_push.comp and the CPU mirror pullPushCpu
// (techniques/core/visibility/pull_push.cpp). Common GLSL/C++ subset: see shaders/shared/shared.h.
//
// Conventions:
//  - a texel holds (v, w): v the visibility in [0, 1], w its weight in [0, 1] (1: a computed pixel,
//    0: a gap; anything between is a partial confidence);
//  - texel coordinates are integer indices counted from the first row of the texture (the same rule
//    applies whichever way the rows run, so GL's bottom-first and Image's top-first agree);
//  - level 0 is the frame; level k + 1 has ceil(n0 / 2) texels across for k = 0 and then
//    max(1, n(k) / 2) (rounded down) — the GL mip chain of a texture of ceil(n0 / 2) texels, i.e. the
//    pyramid resources of SizeRule::frame(2) (pullPushLevelSize). Coarse texel i covers the fine
//    texels 2i and 2i + 1, and the last coarse texel also the left-over ones (pullBlock), so every
//    fine texel is counted by exactly one coarse texel (the rule of backprojection/hsm.comp).
#ifndef SHADOWLAB_PULL_PUSH_GLSL
#define SHADOWLAB_PULL_PUSH_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// Texels across pull-push level `level` of a frame n0 texels across (level 0: the frame).
SHARED_FN int pullPushLevelSize(int level, int n0) {
    if (level == 0) {
        return n0;
    }
    return max(1, ((n0 + 1) / 2) >> (level - 1));
}

// ---- pull: level k + 1 from level k -------------------------------------------------------------

// The fine texels (x0, y0, x1, y1), inclusive, that coarse texel p of a level coarseSize texels
// across covers in the level below (fineSize texels across): the 2x2 block 2p .. 2p + 1, clamped to
// the fine level, widened on the coarse level's last row or column to the fine level's last one.
SHARED_FN ivec4 pullBlock(ivec2 p, ivec2 coarseSize, ivec2 fineSize) {
    int x1 = p.x == coarseSize.x - 1 ? fineSize.x - 1 : min(2 * p.x + 1, fineSize.x - 1);
    int y1 = p.y == coarseSize.y - 1 ? fineSize.y - 1 : min(2 * p.y + 1, fineSize.y - 1);
    return ivec4(2 * p.x, 2 * p.y, x1, y1);
}

// Adds fine texel (v, w) to the running sums (sum w_i v_i, sum w_i); start from vec2(0.0f).
SHARED_FN vec2 pullAccumulate(vec2 sums, vec2 texel) {
    return vec2(sums.x + texel.y * texel.x, sums.y + texel.y);
}

// guennebaud2007 sec. 5.2: "the visibility and weight buffers are iteratively reduced by
// accumulating the weights and averaging the visibility factors": the coarse texel
// (v', w') = (sum w_i v_i / sum w_i, min(1, sum w_i)), v' = 0 where no fine texel has weight.
SHARED_FN vec2 pullResult(vec2 sums) {
    float v = sums.y > 0.0f ? sums.x / sums.y : 0.0f;
    return vec2(v, min(1.0f, sums.y));
}

// ---- push: level k from the complete level k + 1 ------------------------------------------------

// The coarse texel coordinate (centres at integers) of fine texel x's centre: the fine centre
// x + 0.5 is at (x + 0.5) / 2 in coarse texels, whose centres are at i + 0.5. Clamped to the
// coarse level's first and last centres (clamp-to-edge bilinear). Before the clamp the fraction
// is always 0.75 (even x) or 0.25 (odd x): Gortler's 3/4, 1/4 tent.
SHARED_FN float pushCoarseCoordinate(int x, int coarseSize) {
    float u = 0.5f * float(x) - 0.25f;
    return clamp(u, 0.0f, float(coarseSize - 1));
}

// The 2x2 coarse texels (x0, y0, x1, y1) whose bilinear blend gives the coarse level at the centre
// of fine texel `fine`, for a coarse level coarseSize texels across.
SHARED_FN ivec4 pushTaps(ivec2 fine, ivec2 coarseSize) {
    int x0 = int(floor(pushCoarseCoordinate(fine.x, coarseSize.x)));
    int y0 = int(floor(pushCoarseCoordinate(fine.y, coarseSize.y)));
    return ivec4(x0, y0, min(x0 + 1, coarseSize.x - 1), min(y0 + 1, coarseSize.y - 1));
}

// The bilinear fractions (towards x1, towards y1) of pushTaps.
SHARED_FN vec2 pushFractions(ivec2 fine, ivec2 coarseSize) {
    float u = pushCoarseCoordinate(fine.x, coarseSize.x);
    float t = pushCoarseCoordinate(fine.y, coarseSize.y);
    return vec2(u - floor(u), t - floor(t));
}

// Bilinear blend of the four taps' completed visibilities c(x0,y0), c(x1,y0), c(x0,y1), c(x1,y1).
SHARED_FN float pushBilinear(float c00, float c10, float c01, float c11, vec2 f) {
    float bottom = c00 + f.x * (c10 - c00);
    float top = c01 + f.x * (c11 - c01);
    return bottom + f.y * (top - bottom);
}

// guennebaud2007 sec. 5.2: "the gaps are iteratively filled, from the complete lowest resolution up
// to the highest by linearly blending the current, incomplete, high resolution buffer with the
// current, complete, low resolution buffer scaled up using bilinear filtering": w v + (1 - w) c,
// with (v, w) this level's pulled texel and c the coarser level's completed visibility here. A
// texel of weight 1 keeps its v exactly (the blend is not written as a lerp, which would round).
SHARED_FN float pushBlend(vec2 texel, float coarse) {
    float w = clamp(texel.y, 0.0f, 1.0f);
    if (w == 1.0f) {
        return texel.x;
    }
    return w * texel.x + (1.0f - w) * coarse;
}

#endif
