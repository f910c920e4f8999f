// pvm, pass volume_map (cournia2005 sec. 4.1.3): the penumbra volume quadrilaterals rendered from
// the light. Every vertex carries the silhouette edge its volume was extruded from, so that the
// edge maps can store it.
layout(location = 0) in vec4 worldVertex;  // xyz world, w = 1
layout(location = 1) in vec4 edgeStart;    // h0 (world), the edge's index
layout(location = 2) in vec4 edgeEnd;      // h1 (world), the side (0 outer, 1 inner)
uniform mat4 lightViewFromWorld;
uniform mat4 lightClipFromView;
out float lightDepth;
flat out vec4 h0;
flat out vec4 h1;

void main() {
    vec4 view = lightViewFromWorld * vec4(worldVertex.xyz, 1.0);
    lightDepth = -view.z;
    h0 = edgeStart;
    h1 = edgeEnd;
    gl_Position = lightClipFromView * view;
}
