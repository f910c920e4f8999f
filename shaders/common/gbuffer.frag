// Writes position (w = 1 marks geometry), the geometric normal (w = receives shadows), material
// (albedo, id) and the shading normal.
//  - The geometric normal is the plane of the triangle the pixel lies on (from the screen-space
//    derivatives of the position, constant over a triangle): the receiver's tangent plane of the
//    visibility convention (DESIGN.md section 5) and of every depth test. On a faceted mesh with
//    smooth normals it is what a ray tracer finds: a light point behind the facet's plane is hidden
//    by the mesh itself, one in front of it is not (issue 17: with the interpolated normal the two
//    references disagreed along terminators, RMSE 0.014 on contact, 0.003 with this one).
//  - The shading normal is the interpolated vertex normal; only the cosine of shading reads it.
// Both are turned towards the camera, so single-sided quads shade the same from both sides.
in vec3 worldPos;
in vec3 worldNormal;
uniform vec3 albedo;
uniform float objectId;
uniform float receivesShadows;
uniform mat4 viewFromWorld;
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outMaterial;
layout(location = 3) out vec4 outShadingNormal;

void main() {
    vec3 cameraPos = -transpose(mat3(viewFromWorld)) * viewFromWorld[3].xyz;
    vec3 toCamera = cameraPos - worldPos;
    vec3 n = normalize(worldNormal);
    if (dot(n, toCamera) < 0.0) n = -n;
    // A triangle seen exactly edge-on has no derivative plane: keep the interpolated normal there.
    vec3 facet = cross(dFdx(worldPos), dFdy(worldPos));
    float len = length(facet);
    facet = len > 0.0 && !isinf(len) && !isnan(len) ? facet / len : n;
    if (dot(facet, toCamera) < 0.0) facet = -facet;
    outPosition = vec4(worldPos, 1.0);
    outNormal = vec4(facet, receivesShadows);
    outMaterial = vec4(albedo, objectId);
    outShadingNormal = vec4(n, 0.0);
}
