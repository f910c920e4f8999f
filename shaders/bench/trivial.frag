// The trivial full-screen pass the fixed-cost benchmark divides by: it reads one G-buffer texel per
// pixel and writes one float (the least a full-screen pass of the renderer does).
uniform sampler2D gPosition;
layout(location = 0) out float value;
void main() { value = texelFetch(gPosition, ivec2(gl_FragCoord.xy), 0).w; }
