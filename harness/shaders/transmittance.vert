#version 450 core
// Transmittance map: semi-transparent surfaces seen from the light (one cube face at a time).
layout(location = 0) in vec3 position;
layout(location = 3) in vec3 transmittanceColor;
layout(location = 4) in vec2 uv;
layout(location = 5) in vec3 alpha;
layout(location = 0) uniform mat4 lightMatrix;
out vec3 vPosition;
out vec3 vColor;
out vec2 vUv;
out vec3 vAlpha;
void main() {
  vPosition = position;
  vColor = transmittanceColor;
  vUv = uv;
  vAlpha = alpha;
  gl_Position = lightMatrix * vec4(position, 1.0);
}
