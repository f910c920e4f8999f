// pvm, pass volume_map: the penumbra volume map in one pass with three render targets (sec. 4.1.3):
// the PVDM (the light-view depth z of the nearest volume, kept by the reversed depth test) and the two
// PVEM (the end points of the silhouette edge that volume was extruded from; w: edge index + 1 and
// side + 1, 0 where no volume covers the texel).
in float lightDepth;
flat in vec4 h0;
flat in vec4 h1;
layout(location = 0) out float volumeDepth;
layout(location = 1) out vec4 edge0;
layout(location = 2) out vec4 edge1;

void main() {
    volumeDepth = lightDepth;
    edge0 = vec4(h0.xyz, h0.w + 1.0);
    edge1 = vec4(h1.xyz, h1.w + 1.0);
}
