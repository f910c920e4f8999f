// ssm-contour's occluded area at one HSM level (guennebaud2007 sec. 4, at the level sec. 5.1
// picks): the contour edges of the level's occluding samples in the kernel, found 2x2 block by 2x2
// block with the rule table (sec. 4.1, Fig. 3-4), back-projected from p onto the light, clipped to
// it and radially integrated from the light centre with signed areas (sec. 4.2, Fig. 5a). The
// integration starts from the full light when the contour inside test on the block of four samples
// around p' occludes the light centre (Fig. 5b), from zero otherwise. Level 0 uses the parameter t;
// coarser levels (min depths, fattened occluders) shrink their contour with t = 1 (Fig. 7c). The
// C++ mirror for --pixel is techniques/ssm-contour/contour.cpp.
#ifndef SHADOWLAB_BACKPROJECTION_CONTOUR_AREA_GLSL
#define SHADOWLAB_BACKPROJECTION_CONTOUR_AREA_GLSL
uniform float contourT;     // t in [-1, 1] on level 0
uniform float contourBeta;  // beta: width of the blending band between levels (sec. 5.1)

// Edge `which` of the level block whose lower-left sample is `corner`, back-projected: (a, b).
vec4 blockEdge(int level, ivec2 corner, int mask, int which, vec4 depths, float t) {
    vec4 e = contourEdge(mask, t, which);
    ivec2 holders = contourEdgeHolders(mask, which);
    vec2 centre = vec2(corner) + 1.0;  // the block's centre: the samples' shared corner
    return vec4(backprojectLevel(centre + vec2(e.x, e.y), level, depths[holders.x]),
                backprojectLevel(centre + vec2(e.z, e.w), level, depths[holders.y]));
}

// Block row `by` of a chunk: the blocks between sample rows by (`below`) and by + 1 (`above`)
// whose samples neither all occlude nor all miss, their contour edges' areas added to `occluded`
// one by one (the plain walk's order, which the C++ mirror keeps).
void contourBlockRow(int level, int x0, int by, int blocks, uint below, uint above, int n, float t, inout float occluded) {
    uint todo = contourBlockBits(below, above, blocks);
    while (todo != 0u) {
        int i = findLSB(todo);
        todo &= todo - 1u;
        ivec2 corner = ivec2(x0 + i, by);
        int mask = contourBlockMask(below, above, i);
        vec4 depths = levelDepthQuad(level, corner, n);
        int count = contourRule(mask).x;
        for (int which = 0; which < count; ++which) {
            vec4 e = blockEdge(level, corner, mask, which, depths, t);
            occluded += edgeOccludedArea(lightShape, e.xy, e.zw);
        }
    }
}

float occludedAreaAtLevel(int level, float w) {
    int size = int(shadowMapSize);
    int n = hsmLevelSize(level, size);
    float t = level == 0 ? contourT : 1.0;
    ivec4 range = levelTexelRange(kernelTexelRange(receiver.centre, w, size), level, n);
    float occluded = 0.0;

    // Initialisation (Fig. 5b): the block of the four samples around p'.
    {
        ivec2 corner = ivec2(floor(receiver.centre / levelScale(level) - 0.5));
        vec4 z = levelDepthQuad(level, corner, n);
        int mask = (levelOccludes(level, corner, z.x, n) ? 1 : 0) | (levelOccludes(level, corner + ivec2(1, 0), z.y, n) ? 2 : 0) |
                   (levelOccludes(level, corner + ivec2(1, 1), z.z, n) ? 4 : 0) |
                   (levelOccludes(level, corner + ivec2(0, 1), z.w, n) ? 8 : 0);
        int count = contourRule(mask).x;
        float turn0 = 0.0, turn1 = 0.0;
        if (count >= 1) {
            vec4 e = blockEdge(level, corner, mask, 0, z, t);
            turn0 = edgeTurn(e.xy, e.zw);
        }
        if (count == 2) {
            vec4 e = blockEdge(level, corner, mask, 1, z, t);
            turn1 = edgeTurn(e.xy, e.zw);
        }
        if (contourCentreOccluded(mask, t, turn0, turn1)) occluded = bpLightArea(lightShape);
    }

    // Every 2x2 block with a sample in the kernel, chunk of BP_ROW_CHUNK blocks by chunk, two rows at
    // a time (backprojection.glsl section 9): the occlusion bits of each row of samples once, the
    // edge work only on the contour blocks.
    int columns = range.z - range.x + 2;  // block columns range.x - 1 .. range.z
    for (int cx = 0; cx < columns; cx += BP_ROW_CHUNK) {
        int x0 = range.x - 1 + cx;
        int blocks = min(BP_ROW_CHUNK, columns - cx);
        uint below = rowOcclusionBits(level, x0, range.y - 1, blocks + 1, n);
        for (int by = range.y - 1; by <= range.w; by += 2) {
            uint above, next;
            rowPairOcclusionBits(level, x0, by + 1, blocks + 1, n, above, next);
            contourBlockRow(level, x0, by, blocks, below, above, n, t, occluded);
            if (by + 1 <= range.w) contourBlockRow(level, x0, by + 1, blocks, above, next, n, t, occluded);
            below = next;
        }
    }
    return occluded;
}

// Sec. 5.1: the continuous level lambda from z_occ (eq. 3) and the pseudo-code's blending.
vec3 chooseLevels(float w, float zOcc) {
    float smoothKernel = hsmKernelTexels(lightWidthWorld, shadowMapSize, lightTanHalfFov, zOcc, receiver.position.z);
    float lambda = lightLevelContinuous(smoothKernel, w, kernelThreshold, hsmTopLevel);
    chosenLambda = lambda;
    return lightLevelBlend(lambda, contourBeta, hsmTopLevel);
}
#endif
