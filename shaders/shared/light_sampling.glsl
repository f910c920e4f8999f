// Light-sample stratification shared by the `reference` technique (one shadow map per sample) and
// the `raytraced` reference (rays per pixel). Common GLSL/C++ subset: see shaders/shared/shared.h.
#ifndef SHADOWLAB_LIGHT_SAMPLING_GLSL
#define SHADOWLAB_LIGHT_SAMPLING_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// Light shapes, the same numbers as shadowlab::LightShape.
const int LIGHT_SHAPE_POINT = 0;
const int LIGHT_SHAPE_SQUARE = 1;
const int LIGHT_SHAPE_DISK = 2;
const int LIGHT_SHAPE_SPHERE = 3;

// PCG hash (Jarzynski and Olano 2020, "Hash Functions for GPU Rendering"): a well-mixed 32-bit
// hash, identical on the CPU and the GPU because uint arithmetic wraps mod 2^32 in both.
SHARED_FN uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// 16 high bits of a hash as a float in [0, 1). Sixteen bits, not 24: a cell index (up to 8 bits for
// n <= 65536) plus the jitter must stay exact in a float's 24-bit mantissa, or col + jitter can
// round up to col + 1 and a sample leave its stratum (u = 1).
SHARED_FN float hashToUnit(uint h) {
    return float(h >> 16u) * (1.0f / 65536.0f);
}

// Rows of the stratification of n samples: r = floor(sqrt(n)), at least 1.
SHARED_FN uint strataRows(uint n) {
    uint r = uint(floor(sqrt(float(n)) + 1e-3f));
    return max(r, 1u);
}

// Sample i of n stratified samples of the unit square, jittered by a hash of (seed, i).
// The square is cut into r = strataRows(n) rows of equal height; row j holds n / r cells, and the
// first n % r rows one more, so every n gives a complete partition into n cells. Cells of a row
// have equal width; a sample's weight is its cell's area, so sum(weight) = 1 and the weighted
// mean of a function over the samples is an unbiased stratified estimate of its mean.
// Returns (u, v, weight).
SHARED_FN vec3 stratifiedSample(uint i, uint n, uint seed) {
    uint r = strataRows(n);
    uint q = n / r;
    uint extra = n % r;  // rows 0 .. extra-1 hold q + 1 cells
    uint row;
    uint col;
    uint cells;
    if (i < extra * (q + 1u)) {
        row = i / (q + 1u);
        col = i % (q + 1u);
        cells = q + 1u;
    } else {
        uint rest = i - extra * (q + 1u);
        row = extra + rest / q;
        col = rest % q;
        cells = q;
    }
    uint h = pcgHash(seed * 0x9E3779B9u + i);
    float jitterU = hashToUnit(h);
    float jitterV = hashToUnit(pcgHash(h));
    float u = (float(col) + jitterU) / float(cells);
    float v = (float(row) + jitterV) / float(r);
    return vec3(u, v, 1.0f / (float(r) * float(cells)));
}

// Concentric map of the unit square onto the unit disk (Shirley and Chiu 1997). It preserves
// area ratios, so stratification weights carry over from the square to the disk.
SHARED_FN vec2 concentricSquareToDisk(vec2 uv) {
    vec2 p = 2.0f * uv - vec2(1.0f, 1.0f);
    if (p.x == 0.0f && p.y == 0.0f) {
        return vec2(0.0f, 0.0f);
    }
    const float quarterPi = 0.78539816339744830962f;
    float radius;
    float phi;
    if (abs(p.x) > abs(p.y)) {
        radius = p.x;
        phi = quarterPi * (p.y / p.x);
    } else {
        radius = p.y;
        phi = 2.0f * quarterPi - quarterPi * (p.x / p.y);
    }
    return radius * vec2(cos(phi), sin(phi));
}

// Offset of a light sample in the light plane, in world units along (right, up), for the sample
// (u, v) in [0,1)^2. Square: width w_l = size, offset ((u - 0.5) w_l, (v - 0.5) w_l). Disk and
// sphere: radius r = size; a sphere light is sampled as the disk through its centre facing the
// light direction (its silhouette from far along that direction). Point: the centre.
SHARED_FN vec2 lightSampleOffset(int shape, float size, vec2 uv) {
    if (shape == LIGHT_SHAPE_SQUARE) {
        return (uv - vec2(0.5f, 0.5f)) * size;
    }
    if (shape == LIGHT_SHAPE_DISK || shape == LIGHT_SHAPE_SPHERE) {
        return concentricSquareToDisk(uv) * size;
    }
    return vec2(0.0f, 0.0f);
}

// World position of a light sample.
SHARED_FN vec3 lightSamplePosition(vec3 centre, vec3 right, vec3 up, int shape, float size, vec2 uv) {
    vec2 offset = lightSampleOffset(shape, size, uv);
    return centre + offset.x * right + offset.y * up;
}

#endif
