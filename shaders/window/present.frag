// The window's technique view: the renderer's linear image scaled to the view (it may be rendered
// at a reduced resolution while the user drags), a split against a second image, or the error
// |a - b| of two visibility buffers as a heat map. sRGB-encoded for the default framebuffer.
uniform sampler2D imageA;      // technique (linear RGB, or visibility in error mode)
uniform sampler2D imageB;      // reference or second technique (same kinds)
uniform int mode;              // 0: A; 1: A left of the split, B right; 2: error |A - B|
uniform float split;           // fraction of the view's width
uniform vec2 viewSize;         // framebuffer pixels
uniform float errorScale;      // error drawn at the top of the colour scale
uniform float scaleA;          // multiplies A (1, or 1 / sum of weights for the reference's sums)
uniform float scaleB;
layout(location = 0) out vec4 color;

vec3 fetch(sampler2D s, vec2 uv) {
    ivec2 size = textureSize(s, 0);
    return texelFetch(s, clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1), 0).rgb;
}

vec3 encode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// Error colour scale: black (0) -> blue -> magenta -> orange -> yellow (errorScale and above).
vec3 heat(float t) {
    t = clamp(t, 0.0, 1.0);
    vec3 c0 = vec3(0.0), c1 = vec3(0.1, 0.1, 0.7), c2 = vec3(0.8, 0.1, 0.6), c3 = vec3(1.0, 0.5, 0.0), c4 = vec3(1.0, 1.0, 0.4);
    if (t < 0.25) return mix(c0, c1, t / 0.25);
    if (t < 0.5) return mix(c1, c2, (t - 0.25) / 0.25);
    if (t < 0.75) return mix(c2, c3, (t - 0.5) / 0.25);
    return mix(c3, c4, (t - 0.75) / 0.25);
}

void main() {
    vec2 uv = gl_FragCoord.xy / viewSize;
    if (mode == 2) {
        float a = scaleA * fetch(imageA, uv).r, b = scaleB * fetch(imageB, uv).r;
        color = vec4(heat(abs(a - b) / max(errorScale, 1e-6)), 1.0);  // already display values
        return;
    }
    vec3 c = (mode == 1 && uv.x >= split) ? scaleB * fetch(imageB, uv) : scaleA * fetch(imageA, uv);
    color = vec4(encode(c), 1.0);
}
