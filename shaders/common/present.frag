// Shows the renderer's linear image in the window, sRGB-encoded.
uniform sampler2D image;
layout(location = 0) out vec4 color;

void main() {
    ivec2 size = textureSize(image, 0);
    vec3 c = clamp(texelFetch(image, min(ivec2(gl_FragCoord.xy), size - 1), 0).rgb, 0.0, 1.0);
    vec3 srgb = mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
    color = vec4(srgb, 1.0);
}
