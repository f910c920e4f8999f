// Test-only: vertex i belongs to triangle i / 3, and every triangle covers the whole viewport.
void main() {
    int v = gl_VertexID % 3;
    vec2 p = vec2(float((v << 1) & 2), float(v & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
