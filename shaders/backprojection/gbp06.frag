// ssm-gbp06 (guennebaud2007 sec. 3, after GBP06): every occluding shadow-map sample in the kernel
// is a small quad parallel to the light (its texel at its depth), back-projected from p onto the
// light and clipped to it; the occluded areas are summed. Gaps between the quads of neighbouring
// samples at different depths are filled by extending each quad's right and top sides to the
// back-projected left and bottom sides of its right and top neighbours when those occlude too. The
// overlaps this creates (and those already there) are not corrected: the shadow is overestimated,
// as the paper says. The C++ mirror for --pixel is techniques/ssm-gbp06/gbp06.cpp.
#include "receiver.glsl"
#include "../common/light_front.glsl"
uniform sampler2D shadowMap;       // light-view depth z (R32F), level 0
uniform sampler2D kernelSize;      // from kernel.frag
uniform sampler2D classification;  // from kernel.frag
uniform int lightShape;            // BP_LIGHT_SQUARE or BP_LIGHT_DISK
uniform float lightHalfSize;       // w_l / 2 or r: the unit of light coordinates
uniform float maxKernelTexels;     // the `max_kernel` cap
layout(location = 0) out float visibility;

float depthAt(ivec2 t) {
    int last = int(shadowMapSize) - 1;
    if (t.x < 0 || t.y < 0 || t.x > last || t.y > last) return 3.4e38;  // off the map: no caster
    return texelFetch(shadowMap, t, 0).r;
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    visibility = 1.0;
    if (isBackground(pixel)) return;
    float cls = texelFetch(classification, pixel, 0).r;
    // The visibility convention (common/light_front.glsl): only the light in front of the
    // receiver's tangent plane counts, as a factor on the back-projected visibility.
    float front = lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
    if (cls == BP_CLASS_LIT) {
        visibility = front;
        return;
    }
    if (cls == BP_CLASS_UMBRA) {
        visibility = 0.0;
        return;
    }
    BpReceiver r = prepareReceiver(pixel);
    int size = int(shadowMapSize);
    float w = min(texelFetch(kernelSize, pixel, 0).r, maxKernelTexels);
    ivec4 range = kernelTexelRange(r.centre, w, size);
    float occluded = 0.0;
    for (int y = range.y; y <= range.w; ++y)
        for (int x = range.x; x <= range.z; ++x) {
            float z = depthAt(ivec2(x, y));
            if (!bpSampleOccludes(r, vec2(x, y) + 0.5, z, shadowMapSize, lightTanHalfFov)) continue;
            // The texel [x, x+1] x [y, y+1] at depth z, back-projected: an axis-aligned rectangle.
            vec2 lo = backprojectToLight(r.position, vec2(x, y), z, shadowMapSize, lightTanHalfFov, lightHalfSize);
            vec2 hi = backprojectToLight(r.position, vec2(x + 1, y + 1), z, shadowMapSize, lightTanHalfFov, lightHalfSize);
            // Gap filling (GBP06): extend to the right and top neighbours' facing sides.
            float zRight = depthAt(ivec2(x + 1, y));
            if (bpSampleOccludes(r, vec2(x + 1, y) + 0.5, zRight, shadowMapSize, lightTanHalfFov))
                hi.x = max(hi.x, backprojectToLight(r.position, vec2(x + 1, y), zRight, shadowMapSize, lightTanHalfFov, lightHalfSize).x);
            float zTop = depthAt(ivec2(x, y + 1));
            if (bpSampleOccludes(r, vec2(x, y + 1) + 0.5, zTop, shadowMapSize, lightTanHalfFov))
                hi.y = max(hi.y, backprojectToLight(r.position, vec2(x, y + 1), zTop, shadowMapSize, lightTanHalfFov, lightHalfSize).y);
            occluded += rectOccludedArea(lightShape, vec4(lo, hi));
        }
    visibility = bpVisibility(occluded, lightShape) * front;
}
