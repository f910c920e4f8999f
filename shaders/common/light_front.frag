// Writes the fraction of the light in front of each receiver's tangent plane (light_front.glsl):
// the visibility of the pixels a technique's stencil marks as unoccluded (pcss's pixels without a
// blocker), where v = 1 would count the part of the light behind the receiver's own surface.
#include "gbuffer_access.glsl"
#include "light_front.glsl"
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    visibility = isBackground(pixel) ? 1.0 : lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
}
