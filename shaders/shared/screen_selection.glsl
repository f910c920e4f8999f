// The view-dependent selection of guennebaud2007 sec. 5.2 ("View dependent selection", Fig. 9): the
// penumbra's object-space size from the smooth occluder depth z_occ (eq. 4), its screen-space size
// (eq. 5) and the dithered choice of the pixels whose visibility is computed (eq. 6); and the codes
// the `selection` internal stores per pixel. Shared by shaders/backprojection/select.frag,
// pack.comp, the evaluation shaders and the C++ tests (common GLSL/C++ subset: shared.h).
#ifndef SHADOWLAB_SCREEN_SELECTION_GLSL
#define SHADOWLAB_SCREEN_SELECTION_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// Codes of the `selection` internal, one per pixel.
#define SEL_BACKGROUND 0  // no geometry
#define SEL_LIT 1         // lit by the kernel's classification: its visibility is known (the light-front fraction)
#define SEL_UMBRA 2       // umbra by the classification: 0
#define SEL_SELECTED 3    // penumbra, selected by eq. 6: evaluated
#define SEL_FORCED 4      // penumbra, not selected by eq. 6 but on a discontinuity: evaluated
#define SEL_BLOCK 5       // penumbra, not selected, in a block processed whole (sec. 6, > 80%): evaluated
#define SEL_SKIPPED 6     // penumbra, not evaluated: filled by the pull-push reconstruction

// The block of sec. 6's classification: BP_BLOCK x BP_BLOCK pixels; a block whose selected pixels
// are more than BP_BLOCK_WHOLE of its pixels is processed whole.
#define BP_BLOCK 16
#define BP_BLOCK_WHOLE 0.8f

// Eq. 4: s_obj = w_l (p_z - z_occ) / z_occ, a conservative object-space penumbra size (world units)
// from the light width w_l, the receiver's light depth p_z and the smooth occluder depth z_occ (the
// kernel pass's occluder_depth; 0 where the pixel is lit).
SHARED_FN float penumbraObjectSize(float lightWidth, float zReceiver, float zOccluder) {
    if (zOccluder <= 0.0f) {
        return 0.0f;
    }
    return lightWidth * max(zReceiver - zOccluder, 0.0f) / zOccluder;
}

// Eq. 5: s_scr = eta s_obj / z_pe (n . v), the smallest diameter of the projection, in pixels, of a
// disk of diameter s_obj centred at p with normal n: eta is the camera's pixels per world unit at
// unit depth (height / (2 tan(fovy / 2))), z_pe the camera-space depth of p, cosView = |n . v|.
SHARED_FN float penumbraScreenSize(float objectSize, float eta, float cameraDepth, float cosView) {
    return eta * objectSize / max(cameraDepth, 1e-6f) * cosView;
}

// The rank 1 .. h^2 of pixel (i, j) in the h x h ordered-dither (Bayer) pattern, h a power of two:
// the classic recursive matrix [[0, 2], [3, 1]] (bit-interleaving of i xor j and j), plus one.
// Every h x h window of the screen holds each rank once, and the pixels of the ranks above any k
// are spread evenly over it (Fig. 9's 4 x 4 pattern).
SHARED_FN int ditherRank(int i, int j, int h) {
    int x = i % h;
    int y = j % h;
    int bits = 0;
    while ((1 << bits) < h) {
        bits = bits + 1;
    }
    int v = 0;
    for (int k = 0; k < bits; ++k) {
        int level = bits - 1 - k;  // the finest bit of (x, y) is the most significant of the rank
        v = v | ((((x ^ y) >> k) & 1) << (2 * level + 1)) | (((y >> k) & 1) << (2 * level));
    }
    return v + 1;
}

// Eq. 6: the pixel's visibility is computed iff s_scr < s_min sqrt(pattern[i % h, j % h]), the
// pattern holding the ranks 1 .. h^2. Our addition: the pixel of rank h^2 is always selected, so
// every h x h window keeps one sample however wide the penumbra (the lowest density the pattern
// gives, which sec. 5.2 calls the point of larger patterns); without it a penumbra wider than
// s_min h pixels would have no sample at all and pull-push would fill it from its borders.
SHARED_FN bool screenSelected(float screenSize, float sMin, int rank, int h) {
    return rank == h * h || screenSize < sMin * sqrt(float(rank));
}

// The selection code of a penumbra pixel: selected by eq. 6, forced by the discontinuity buffer, or
// skipped (sec. 5.2: "evaluated if it either satisfies the equation [6] or is on a discontinuity").
SHARED_FN int penumbraSelectionCode(bool selected, bool onDiscontinuity) {
    return selected ? SEL_SELECTED : (onDiscontinuity ? SEL_FORCED : SEL_SKIPPED);
}

// Whether a code's pixel is evaluated by the visibility pass (a penumbra pixel not skipped).
SHARED_FN bool selectionEvaluated(int code) {
    return code == SEL_SELECTED || code == SEL_FORCED || code == SEL_BLOCK;
}

// Sec. 6's block classification from the count of selected (eq. 6 or forced) pixels among the
// block's pixels inside the frame: 2 processed whole (more than BP_BLOCK_WHOLE of them), 0 skipped
// (none), 1 its selected pixels compacted.
SHARED_FN int blockClass(int selected, int pixels) {
    if (selected == 0) {
        return 0;
    }
    return float(selected) > BP_BLOCK_WHOLE * float(pixels) ? 2 : 1;
}
#endif
