// ssv, pass hard_volumes: the camera's depth of each G-buffer point under the infinite-far-plane
// projection the volumes and wedges are drawn with (the slides' "position buffer" is the G-buffer).
#include "../common/gbuffer_access.glsl"
uniform mat4 clipFromWorld;
uniform int vbufferDivisor;  // k: this texel of the reduced V-buffer is the frame's pixel k i + k / 2

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy) * vbufferDivisor + vbufferDivisor / 2;
    if (isBackground(pixel)) {
        gl_FragDepth = 1.0;  // the clear value: nothing behind it counts
        return;
    }
    vec4 clip = clipFromWorld * vec4(worldPosition(pixel), 1.0);
    gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
}
