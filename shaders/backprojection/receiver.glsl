// What every back-projection pass reads of the receiver and the light (ssm-gbp06, ssm-contour):
// the G-buffer, the light view and the depth bias, through the shared BpReceiver
// (shaders/shared/backprojection.glsl), so the C++ per-pixel record prepares the same numbers.
#ifndef SHADOWLAB_BACKPROJECTION_RECEIVER_GLSL
#define SHADOWLAB_BACKPROJECTION_RECEIVER_GLSL
#include "../common/gbuffer_access.glsl"
#include "../shared/backprojection.glsl"

uniform mat4 lightViewFromWorld;
uniform mat4 lightClipFromView;
uniform float lightTanHalfFov;
uniform float shadowMapSize;     // r, texels across
uniform vec3 lightPosition;      // the light centre, where the shadow map was rendered from
uniform float biasConstTexels;
uniform float biasSlopeTexels;

BpReceiver prepareReceiver(ivec2 pixel) {
    return bpReceiver(lightViewFromWorld, lightClipFromView, worldPosition(pixel), worldNormal(pixel), lightPosition,
                      lightTanHalfFov, shadowMapSize, biasConstTexels, biasSlopeTexels);
}
#endif
