// pvmf, pass mask (cournia2005 sec. 5.1): the simplified penumbra volumes rendered from the light into
// the penumbra volume mask, one RG32F target: r the light-view depth z of the nearest volume (kept by
// the reversed depth test; FLT_MAX where none), g the distance d_e from the light centre to the edge
// that volume was extruded from (0: none). The vertices come through pvm/volume.vert, d_e in h0.w.
in float lightDepth;
flat in vec4 h0;
flat in vec4 h1;
layout(location = 0) out vec2 mask;

void main() {
    mask = vec2(lightDepth, h0.w);
}
