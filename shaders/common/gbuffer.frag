// Writes position (w = 1 marks geometry), normal (w = receives shadows) and material (albedo, id).
// The normal is turned towards the camera, so single-sided quads shade the same from both sides.
in vec3 worldPos;
in vec3 worldNormal;
uniform vec3 albedo;
uniform float objectId;
uniform float receivesShadows;
uniform mat4 viewFromWorld;
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outMaterial;

void main() {
    vec3 n = normalize(worldNormal);
    vec3 cameraPos = -transpose(mat3(viewFromWorld)) * viewFromWorld[3].xyz;
    if (dot(n, cameraPos - worldPos) < 0.0) n = -n;
    outPosition = vec4(worldPos, 1.0);
    outNormal = vec4(n, receivesShadows);
    outMaterial = vec4(albedo, objectId);
}
