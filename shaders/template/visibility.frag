// TEMPLATE: the technique's main pass. Replace the body with the paper's step, citing it
// ("guennebaud2007 eq. 1") next to the line that implements it; put the paper's equations in
// shaders/shared/<id>.glsl so tests run them on the CPU too.
#include "../common/gbuffer_access.glsl"
#include "../common/light_front.glsl"
#include "../common/shadow_lookup.glsl"
uniform int kernelTexels;  // the template's example parameter `kernel` (odd)
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (isBackground(pixel)) {
        visibility = 1.0;
        return;
    }
    ShadowReceiver receiver = prepareShadowReceiver(worldPosition(pixel), worldNormal(pixel));
    int radius = kernelTexels / 2;
    float lit = 0.0;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) lit += shadowTestOffset(receiver, vec2(dx, dy));
    // The visibility convention (DESIGN.md section 5): only the light in front of the receiver's
    // tangent plane counts; here as a factor (common/light_front.glsl), set by setLightFrontUniforms.
    visibility = lit / float((2 * radius + 1) * (2 * radius + 1)) *
                 lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
}
