// reference: adds one light sample's weighted hard visibility (additive blending into R32F).
#include "../common/gbuffer_access.glsl"
#include "../common/shadow_lookup.glsl"
uniform float sampleWeight;  // area of the sample's stratum on the light (the weights sum to 1)
layout(location = 0) out float visibility;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (isBackground(pixel)) {
        visibility = sampleWeight;
        return;
    }
    visibility = sampleWeight * shadowTest(worldPosition(pixel), worldNormal(pixel));
}
