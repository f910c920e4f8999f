// spsm build: the casters' vertices in the light's view space (the geometry shader clips, packs and
// expands each triangle).
layout(location = 0) in vec3 objectPosition;
uniform mat4 worldFromObject;
uniform mat4 lightViewFromWorld;
out vec3 viewPosition;

void main() { viewPosition = vec3(lightViewFromWorld * worldFromObject * vec4(objectPosition, 1.0)); }
