// Writes the light-view depth z. With peel = 1 (second-depth shadow mapping), fragments at or in
// front of the first depth layer are discarded, so the depth test keeps the second-nearest surface.
in float lightDepth;
uniform int peel;
uniform sampler2D firstDepth;
layout(location = 0) out float depthOut;

void main() {
    if (peel == 1) {
        float first = texelFetch(firstDepth, ivec2(gl_FragCoord.xy), 0).r;
        // A relative margin separates the layers of surfaces rasterised at the same depth.
        if (lightDepth <= first * (1.0 + 1e-5) + 1e-7) discard;
    }
    depthOut = lightDepth;
}
