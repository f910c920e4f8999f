// ssm-gbp06's occluded area at one HSM level (guennebaud2007 sec. 3, after GBP06; light-space
// multi-resolution as GBP06 introduced it: the level of eq. 2, no blending, sec. 5.1): every
// occluding sample of the level in the kernel is a small quad parallel to the light (its texel at
// its min depth), back-projected from p onto the light and clipped to it; the occluded areas are
// summed. Gaps between the quads of neighbouring samples at different depths are filled by
// extending each quad's right and top sides to the back-projected left and bottom sides of its right
// and top neighbours when those occlude too. The overlaps this creates (and those already there)
// are not corrected: the shadow is overestimated, as the paper says. The C++ mirror for --pixel is
// techniques/ssm-gbp06/gbp06.cpp.
#ifndef SHADOWLAB_BACKPROJECTION_GBP06_AREA_GLSL
#define SHADOWLAB_BACKPROJECTION_GBP06_AREA_GLSL

// Row y of a chunk: the occluding samples of `row` (bits), their top neighbours in `top`; their
// areas added to `occluded` one by one (the plain walk's order, which the C++ mirror keeps).
void gbp06Row(int level, int x0, int y, int count, uint row, uint top, int n, inout float occluded) {
    uint todo = row & ((1u << uint(count)) - 1u);
    while (todo != 0u) {
        int i = findLSB(todo);
        todo &= todo - 1u;
        int x = x0 + i;
        float z = levelDepth(level, ivec2(x, y), n);
        // The texel [x, x+1] x [y, y+1] of the level at depth z, back-projected: an axis-aligned rectangle.
        vec2 lo = backprojectLevel(vec2(x, y), level, z);
        vec2 hi = backprojectLevel(vec2(x + 1, y + 1), level, z);
        // Gap filling (GBP06): extend to the right and top neighbours' facing sides.
        if (((row >> uint(i + 1)) & 1u) != 0u)
            hi.x = max(hi.x, backprojectLevel(vec2(x + 1, y), level, levelDepth(level, ivec2(x + 1, y), n)).x);
        if (((top >> uint(i)) & 1u) != 0u)
            hi.y = max(hi.y, backprojectLevel(vec2(x, y + 1), level, levelDepth(level, ivec2(x, y + 1), n)).y);
        occluded += rectOccludedArea(lightShape, vec4(lo, hi));
    }
}

float occludedAreaAtLevel(int level, float w) {
    int size = int(shadowMapSize);
    int n = hsmLevelSize(level, size);
    ivec4 range = levelTexelRange(kernelTexelRange(receiver.centre, w, size), level, n);
    float occluded = 0.0;
    // Chunk of BP_ROW_CHUNK samples by chunk, two rows at a time (backprojection.glsl section 9):
    // the occlusion bits of each row once (with the right neighbour of the chunk's last sample), the
    // quads only for the occluding samples.
    int columns = range.z - range.x + 1;
    for (int cx = 0; cx < columns; cx += BP_ROW_CHUNK) {
        int x0 = range.x + cx;
        int count = min(BP_ROW_CHUNK, columns - cx);
        uint row = rowOcclusionBits(level, x0, range.y, count + 1, n);
        for (int y = range.y; y <= range.w; y += 2) {
            uint top, next;
            rowPairOcclusionBits(level, x0, y + 1, count + 1, n, top, next);
            gbp06Row(level, x0, y, count, row, top, n, occluded);
            if (y + 1 <= range.w) gbp06Row(level, x0, y + 1, count, top, next, n, occluded);
            row = next;
        }
    }
    return occluded;
}

// GBP06's level: eq. 2, no blending.
vec3 chooseLevels(float w, float zOcc) {
    chosenLambda = float(lightLevelForKernel(w, kernelThreshold, hsmTopLevel));
    return vec3(chosenLambda, 0.0, 0.0);
}
#endif
