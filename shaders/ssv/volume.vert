// ssv: the hard shadow volume's vertices, homogeneous (w = 0: at infinity in the direction xyz).
layout(location = 0) in vec4 worldVertex;
uniform mat4 clipFromWorld;

void main() { gl_Position = clipFromWorld * worldVertex; }
