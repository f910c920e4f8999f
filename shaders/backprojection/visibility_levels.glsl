// The per-pixel driver of the back-projection visibility passes (see visibility_common.glsl).
#ifndef SHADOWLAB_BACKPROJECTION_VISIBILITY_LEVELS_GLSL
#define SHADOWLAB_BACKPROJECTION_VISIBILITY_LEVELS_GLSL

// The light's visibility at `pixel`: lit pixels the light-front fraction, umbra 0, penumbra the
// back-projected occlusion at the chosen level(s), blended as sec. 5.1's pseudo-code.
float pixelVisibility(ivec2 pixel) {
    if (isBackground(pixel)) return 1.0;
    float cls = texelFetch(classification, pixel, 0).r;
    // The visibility convention (common/light_front.glsl): only the light in front of the
    // receiver's tangent plane counts, as a factor on the back-projected visibility.
    float front = lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
    if (cls == BP_CLASS_LIT) return front;
    if (cls == BP_CLASS_UMBRA) return 0.0;
    receiver = prepareReceiver(pixel);
    float w = min(texelFetch(kernelSize, pixel, 0).r, maxKernelTexels);
    vec3 levels = vec3(0.0);
#ifdef LIGHT_MULTIRES
    levels = chooseLevels(w, texelFetch(occluderDepth, pixel, 0).r);
    chosenLevels = levels;
#endif
    float v = bpVisibility(occludedAreaAtLevel(int(levels.x), w), lightShape);
#ifdef LIGHT_MULTIRES
    if (levels.z > 0.0) v = mix(v, bpVisibility(occludedAreaAtLevel(int(levels.y), w), lightShape), levels.z);
#endif
    return v * front;
}
#endif
