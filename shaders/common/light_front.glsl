// The visibility convention for the techniques that filter or back-project (pcss, sssm, ssm-gbp06,
// ssm-contour): their v is multiplied by the exact fraction of the light in front of the
// receiver's tangent plane (shaders/shared/tangent_plane.glsl; DESIGN.md section 5). The uniforms
// are set by setLightFrontUniforms (techniques/core/visibility/shadow_map.h).
#ifndef SHADOWLAB_LIGHT_FRONT_GLSL
#define SHADOWLAB_LIGHT_FRONT_GLSL
#include "../shared/tangent_plane.glsl"

uniform int frontLightShape;     // LIGHT_SHAPE_* of light_sampling.glsl
uniform vec3 frontLightCentre;   // world
uniform vec3 frontLightRight;    // the light plane's axes (world, unit)
uniform vec3 frontLightUp;
uniform float frontLightSize;    // square: width; disk and sphere: radius

float lightFrontFraction(vec3 worldPos, vec3 worldNormal) {
    return lightFractionInFront(frontLightShape, frontLightCentre, frontLightRight, frontLightUp, frontLightSize,
                                worldPos, worldNormal);
}
#endif
