// Test-only: includes a file that does not compile, so the error must name that file and line.
#include "broken_include.glsl"
layout(local_size_x = 1) in;
void main() {}
