// Test-only: color + (x, y, 0, 0) for the pixel at column x, GL row y (0 at the bottom), so a read-back
// shows both which target was written and which way up it came back.
uniform vec4 color;
layout(location = 0) out vec4 outColor;

void main() { outColor = color + vec4(floor(gl_FragCoord.xy), 0.0, 0.0); }
