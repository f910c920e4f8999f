// SSSM step 3, first draw: every pixel gets step 1's hard shadow (and "not filtered" in the reuse
// map); the second draw (step3.frag) overwrites the pixels with a penumbra.
uniform sampler2D hardShadows;  // step 1: (hard shadow, camera depth)
layout(location = 0) out float visibility;
layout(location = 1) out float reuse;

void main() {
    visibility = texelFetch(hardShadows, ivec2(gl_FragCoord.xy), 0).r;
    reuse = -1.0;
}
