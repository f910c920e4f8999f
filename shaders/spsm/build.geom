// spsm build (lecocq2014, "The Sub-Pixel Shadow Map"): per caster triangle, in the light's view
// space: the triangle clipped by the near plane, projected into SPSM space (texel coordinates, and
// 1/z, affine in them) and clipped to the map plus SPSM_MARGIN texels, so every stored vertex is in
// the packing's range; each piece of the clipped polygon code into 128 bits (spsmPack) and
// emitted, expanded for conservative rasterization (Hasselgren et al. 2005, the bounding-triangle
// algorithm: each edge moved out by the texel's semi-diagonal along its normal, plus one
// quantisation step; the fragment shader then keeps exactly the texels the triangle touches).
// CONSERVATIVE undefined: the triangle as it is (centre-sampling rasterization; or the driver's
// conservative rasterization when HARDWARE_CONSERVATIVE is enabled by the pass).
#include "../shared/spsm.glsl"
layout(triangles) in;
layout(triangle_strip, max_vertices = 24) out;
in vec3 viewPosition[];
flat out uvec4 packedTriangle;
uniform float smSize;
uniform float tanHalfFov;
uniform float nearZ;

vec2 toTexel(vec3 v) {
    float z = -v.z;
    return (vec2(v.x, v.y) / (z * tanHalfFov) * 0.5 + 0.5) * smSize;
}

void emitAt(vec2 x, uvec4 code) {
    packedTriangle = code;
    gl_Position = vec4(x / smSize * 2.0 - 1.0, 0.5, 1.0);
    EmitVertex();
}

void emitPiece(SpsmTriangle t) {
    uvec4 code = spsmPack(t, smSize);
    // The stored (quantised) triangle is what is rasterized: what the look-up tests.
    SpsmTriangle q = spsmUnpack(code, smSize);
#ifdef CONSERVATIVE
    vec2 v[3] = vec2[3](q.a, q.b, q.c);
    if (spsmEdgeFunction(v[0], v[1], v[2]) < 0.0) {
        vec2 s = v[1];
        v[1] = v[2];
        v[2] = s;
    }
    float grow = spsmCoordStep(smSize) + 1e-3;
    vec2 m[3];
    float c[3];
    bool ok = abs(spsmEdgeFunction(v[0], v[1], v[2])) > 1e-8;
    for (int i = 0; i < 3; ++i) {
        vec2 e = v[(i + 1) % 3] - v[i];
        float len = length(e);
        ok = ok && len > 1e-6;
        m[i] = len > 1e-6 ? vec2(e.y, -e.x) / len : vec2(1.0, 0.0);  // outward for counter-clockwise
        c[i] = dot(m[i], v[i]) + 0.5 * (abs(m[i].x) + abs(m[i].y)) + grow;
    }
    vec2 corner[3];
    for (int i = 0; i < 3; ++i) {
        int j = (i + 2) % 3;  // the edge ending at vertex i
        float det = m[j].x * m[i].y - m[j].y * m[i].x;
        ok = ok && abs(det) > 0.05;  // nearly parallel edges (a needle): the box below instead
        corner[i] = abs(det) > 1e-12 ? vec2(c[j] * m[i].y - m[j].y * c[i], m[j].x * c[i] - c[j] * m[i].x) / det : v[i];
    }
    if (ok) {
        for (int i = 0; i < 3; ++i) emitAt(corner[i], code);
        EndPrimitive();
    } else {
        // The triangle's bounding box grown to whole texels: every texel it may touch has its centre
        // inside; the fragment shader's exact footprint test drops the others.
        vec2 lo = floor(min(v[0], min(v[1], v[2])) - vec2(grow));
        vec2 hi = ceil(max(v[0], max(v[1], v[2])) + vec2(grow));
        emitAt(lo, code);
        emitAt(vec2(hi.x, lo.y), code);
        emitAt(vec2(lo.x, hi.y), code);
        emitAt(hi, code);
        EndPrimitive();
    }
#else
    emitAt(q.a, code);
    emitAt(q.b, code);
    emitAt(q.c, code);
    EndPrimitive();
#endif
}

void main() {
    vec3 a = viewPosition[0];
    vec3 b = viewPosition[1];
    vec3 c = viewPosition[2];
    vec3 n = cross(b - a, c - a);
    float len = length(n);
    if (!(len > 1e-20)) return;  // degenerate (or NaN)
    // A plane through the light's centre is seen edge-on: it covers no area of the map.
    if (abs(dot(n / len, a)) <= 1e-6 * max(length(a), max(length(b), length(c)))) return;

    // Clip by the near plane z >= nearZ (light-view depth z = -view.z): up to 4 vertices.
    vec3 src[3] = vec3[3](a, b, c);
    vec3 poly3[4];
    int count3 = 0;
    for (int i = 0; i < 3; ++i) {
        vec3 p = src[i];
        vec3 q = src[(i + 1) % 3];
        float fp = -p.z - nearZ;
        float fq = -q.z - nearZ;
        if (fp >= 0.0) poly3[count3++] = p;
        if ((fp >= 0.0) != (fq >= 0.0)) poly3[count3++] = p + (fp / (fp - fq)) * (q - p);
    }
    if (count3 < 3) return;

    // Project (texel coordinates and 1/z, which is affine in them) and clip to the square
    // [-margin, N + margin]^2: up to 8 vertices.
    vec3 poly[8];
    vec3 next[8];
    for (int i = 0; i < 8; ++i) {
        poly[i] = vec3(0.0);
        next[i] = vec3(0.0);
    }
    for (int i = 0; i < count3; ++i) poly[i] = vec3(toTexel(poly3[i]), 1.0 / -poly3[i].z);
    int count = count3;
    float lo = -SPSM_MARGIN + 1e-3;
    float hi = smSize + SPSM_MARGIN - 1e-3;
    // A polygon inside the square needs no clipping: the sides' loop runs 0 times (llvmpipe runs a
    // geometry shader over several primitives in lock-step and leaves a loop only when none needs
    // another trip: almost every caster's triangle is inside).
    bool inside = true;
    for (int i = 0; i < count3; ++i)
        inside = inside && poly[i].x >= lo && poly[i].x <= hi && poly[i].y >= lo && poly[i].y <= hi;
    int sides = inside ? 0 : 4;
    for (int side = 0; side < sides; ++side) {
        int kept = 0;
        for (int i = 0; i < count; ++i) {
            vec3 p = poly[i];
            vec3 q = poly[(i + 1) % count];
            float fp = side == 0 ? p.x - lo : (side == 1 ? hi - p.x : (side == 2 ? p.y - lo : hi - p.y));
            float fq = side == 0 ? q.x - lo : (side == 1 ? hi - q.x : (side == 2 ? q.y - lo : hi - q.y));
            if (fp >= 0.0 && kept < 8) next[kept++] = p;
            if ((fp >= 0.0) != (fq >= 0.0) && kept < 8) next[kept++] = p + (fp / (fp - fq)) * (q - p);
        }
        for (int i = 0; i < 8; ++i) poly[i] = next[i];
        count = kept;
        if (count < 3) return;
    }

    SpsmTriangle t;
    for (int i = 1; i + 1 < count; ++i) {
        t.a = poly[0].xy;
        t.b = poly[i].xy;
        t.c = poly[i + 1].xy;
        t.w = vec3(poly[0].z, poly[i].z, poly[i + 1].z);
        emitPiece(t);
    }
}
