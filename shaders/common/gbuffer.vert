// G-buffer from the camera: world position and normal per pixel.
layout(location = 0) in vec3 objectPosition;
layout(location = 1) in vec3 objectNormal;
uniform mat4 worldFromObject;
uniform mat4 viewFromWorld;
uniform mat4 clipFromView;
out vec3 worldPos;
out vec3 worldNormal;

void main() {
    vec4 world = worldFromObject * vec4(objectPosition, 1.0);
    worldPos = world.xyz;
    worldNormal = mat3(transpose(inverse(worldFromObject))) * objectNormal;
    gl_Position = clipFromView * viewFromWorld * world;
}
