// One light sample of the window's progressive reference, added (additive blending) to the sums:
// weight x the linear shaded image and weight x the visibility of a `hard` frame rendered with the
// light at the sample point (app/window/reference.cpp).
uniform sampler2D image;
uniform sampler2D visibility;
uniform float weight;
layout(location = 0) out vec4 imageSum;
layout(location = 1) out float visibilitySum;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    imageSum = vec4(weight * texelFetch(image, p, 0).rgb, weight);
    visibilitySum = weight * texelFetch(visibility, p, 0).r;
}
