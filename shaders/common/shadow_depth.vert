// Light-view depth of the shadow casters (Williams 1978). Outputs the light-view depth z.
layout(location = 0) in vec3 objectPosition;
layout(location = 1) in vec3 objectNormal;
uniform mat4 worldFromObject;
uniform mat4 lightViewFromWorld;
uniform mat4 lightClipFromView;
out float lightDepth;

void main() {
    vec4 view = lightViewFromWorld * worldFromObject * vec4(objectPosition, 1.0);
    lightDepth = -view.z;
    gl_Position = lightClipFromView * view;
}
