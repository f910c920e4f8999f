// The scene's lights for the shade pass: LIGHT_COUNT (a define, 0..8), each with its visibility.
// A compile-time count lets the compiler unroll the light loop exactly: llvmpipe runs every
// iteration of a loop with a constant bound, so a loop over 8 slots cost 8 lights for one.
#ifndef SHADOWLAB_LIGHTS_GLSL
#define SHADOWLAB_LIGHTS_GLSL
#ifndef LIGHT_COUNT
#error "LIGHT_COUNT must be defined (the renderer injects it)"
#endif
#if LIGHT_COUNT > 0
uniform vec3 lightPositions[LIGHT_COUNT];
uniform vec3 lightRadiance[LIGHT_COUNT];   // colour * intensity
uniform sampler2D lightVisibility[LIGHT_COUNT];
#endif

// Unshadowed direct light of light i at a receiver (Lambert, from the light's centre), as a
// scalar weight: cos * mean radiance.
float directWeight(float cosine, vec3 radiance) { return cosine * (radiance.r + radiance.g + radiance.b) / 3.0; }
#endif
