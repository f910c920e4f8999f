// Test-only: declarations for the uniform name check, and the setters for mat3, ivec2 and uint.
uniform vec4 color;
uniform mat3 tint;
uniform ivec2 shift;
uniform uint count;
uniform float unusedScale;  // declared, never read: the compiler removes it
uniform vec3 lightPositions[4], lightTint;
#ifdef NEVER_DEFINED
uniform float onlyUnderIfdef;
#endif
/* uniform float commentedOut; */
// uniform float alsoCommentedOut;
layout(location = 0) out vec4 outColor;

void main() {
#ifdef NEVER_DEFINED
    outColor = vec4(onlyUnderIfdef);
#else
    outColor = vec4(tint * color.rgb + lightPositions[3] + lightTint, float(shift.x * 10 + shift.y) + 100.0 * float(count));
#endif
}
