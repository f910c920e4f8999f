// ssm-contour's visibility pass over the whole frame (guennebaud2007 sec. 4 and 5.1): every pixel
// runs pixelVisibility (visibility_levels.glsl) with the contour's occluded area (contour_area.glsl).
#include "visibility_common.glsl"
#include "contour_area.glsl"
#include "visibility_levels.glsl"
layout(location = 0) out float visibility;
#ifdef LIGHT_MULTIRES
layout(location = 1) out vec4 lightLevels;  // lambda, level walked, level blended in, its weight (-1: lit, umbra)
#endif

void main() {
    chosenLambda = -1.0;
    chosenLevels = vec3(-1.0, -1.0, 0.0);
    visibility = pixelVisibility(ivec2(gl_FragCoord.xy));
#ifdef LIGHT_MULTIRES
    lightLevels = vec4(chosenLambda, chosenLevels);
#endif
}
