#version 450 core
// Transmittance map: semi-transparent surfaces seen from the light (one cube face at a time).
layout(location = 0) in vec3 position;
layout(location = 3) in vec3 crossing;
layout(location = 0) uniform mat4 lightMatrix;
out vec3 vPosition;
out vec3 vCrossing;
void main() {
  vPosition = position;
  vCrossing = crossing;
  gl_Position = lightMatrix * vec4(position, 1.0);
}
