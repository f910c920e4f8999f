// ssv, pass visibility: the V-buffer resolved (the slides' additive - subtractive buffers, here
// one float buffer per sub-light channel): per sub-light k (one, or the four quarters of the 2x2
// splitting), v_k = 1 - (hard count x light area + coverage sum) / light area, clamped, times the
// fraction of the sub-light in front of the receiver's tangent plane (the visibility convention,
// shared/tangent_plane.glsl, as for the back-projection techniques); v is the mean of the v_k.
#include "../common/gbuffer_access.glsl"
#include "../shared/tangent_plane.glsl"
#include "../shared/soft_shadow_volumes.glsl"
uniform sampler2D hardCount;      // channel k: sub-light k
uniform sampler2D wedgeCoverage;  // channel k: sub-light k
uniform int lightShape;           // BP_LIGHT_SQUARE or BP_LIGHT_DISK
uniform int pointLight;
uniform int subLightCount;        // 1 or 4
uniform int frontShape;           // LIGHT_SHAPE_* of the (sub-)lights
uniform vec3 subLightCentre[4];   // world
uniform vec3 lightRight;          // the light plane's axes (world, unit)
uniform vec3 lightUp;
uniform float subLightSize;       // square: width; disk and sphere: radius
uniform int vbufferDivisor;       // k: the V-buffer's texel i is the frame's pixel k i + k / 2
uniform ivec2 vbufferSize;        // its texels
layout(location = 0) out float visibility;

// The V-buffer at this pixel: the texel itself (k = 1), or bilinear between the four texels whose
// pixels surround it (the slides: "can use bilinear filtering").
void vbufferAt(ivec2 pixel, out vec4 count, out vec4 coverage) {
    if (vbufferDivisor == 1) {
        count = texelFetch(hardCount, pixel, 0);
        coverage = texelFetch(wedgeCoverage, pixel, 0);
        return;
    }
    vec2 u = (vec2(pixel) - float(vbufferDivisor / 2)) / float(vbufferDivisor);
    ivec2 i0 = clamp(ivec2(floor(u)), ivec2(0), vbufferSize - 1);
    ivec2 i1 = min(i0 + 1, vbufferSize - 1);
    vec2 f = clamp(u - vec2(i0), 0.0, 1.0);
    count = mix(mix(texelFetch(hardCount, i0, 0), texelFetch(hardCount, ivec2(i1.x, i0.y), 0), f.x),
                mix(texelFetch(hardCount, ivec2(i0.x, i1.y), 0), texelFetch(hardCount, i1, 0), f.x), f.y);
    coverage = mix(mix(texelFetch(wedgeCoverage, i0, 0), texelFetch(wedgeCoverage, ivec2(i1.x, i0.y), 0), f.x),
                   mix(texelFetch(wedgeCoverage, ivec2(i0.x, i1.y), 0), texelFetch(wedgeCoverage, i1, 0), f.x), f.y);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    visibility = 1.0;
    if (isBackground(pixel)) return;
    vec4 count, coverage;
    vbufferAt(pixel, count, coverage);
    vec3 position = worldPosition(pixel);
    vec3 normal = worldNormal(pixel);
    float sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        if (k >= subLightCount) break;
        float front = lightFractionInFront(frontShape, subLightCentre[k], lightRight, lightUp, subLightSize, position,
                                           normal);
        if (pointLight == 1) {
            // Hard shadows: a point in a volume sees nothing (upsampled: the interpolated count).
            sum += (vbufferDivisor == 1 ? (count[k] != 0.0 ? 0.0 : 1.0) : clamp(1.0 - count[k], 0.0, 1.0)) * front;
        } else {
            sum += ssvVisibility(count[k], coverage[k], lightShape) * front;
        }
    }
    visibility = sum / float(subLightCount);
}
