// ssv, pass wedges: a wedge's triangles (xyz world, w the silhouette edge's index), or with
// EVERYWHERE one triangle over the viewport for an edge whose wedge could not be built.
uniform mat4 clipFromWorld;
flat out int edgeIndex;
#ifdef EVERYWHERE
uniform int everywhereEdge;
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
    edgeIndex = everywhereEdge;
}
#else
layout(location = 0) in vec4 wedgeVertex;
void main() {
    gl_Position = clipFromWorld * vec4(wedgeVertex.xyz, 1.0);
    edgeIndex = int(wedgeVertex.w);
}
#endif
