// Test-only: one colour everywhere.
uniform vec4 color;
layout(location = 0) out vec4 outColor;

void main() { outColor = color; }
