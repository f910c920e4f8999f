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
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    visibility = 1.0;
    if (isBackground(pixel)) return;
    vec4 count = texelFetch(hardCount, pixel, 0);
    vec4 coverage = texelFetch(wedgeCoverage, pixel, 0);
    vec3 position = worldPosition(pixel);
    vec3 normal = worldNormal(pixel);
    float sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        if (k >= subLightCount) break;
        float front = lightFractionInFront(frontShape, subLightCentre[k], lightRight, lightUp, subLightSize, position,
                                           normal);
        if (pointLight == 1) {
            sum += count[k] != 0.0 ? 0.0 : front;
        } else {
            sum += ssvVisibility(count[k], coverage[k], lightShape) * front;
        }
    }
    visibility = sum / float(subLightCount);
}
