// SSSM step 3, first draw: every pixel gets step 1's hard shadow (and "not filtered" in the reuse
// map); the second draw (step3.frag) overwrites the pixels with a penumbra.
// Both times the fraction of the light in front of the receiver's tangent plane (the visibility
// convention, common/light_front.glsl).
#include "../common/gbuffer_access.glsl"
#include "../common/light_front.glsl"
uniform sampler2D hardShadows;  // step 1: (hard shadow, camera depth)
layout(location = 0) out float visibility;
layout(location = 1) out float reuse;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float hard = texelFetch(hardShadows, pixel, 0).r;
    visibility = isBackground(pixel) ? hard : hard * lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
    reuse = -1.0;
}
