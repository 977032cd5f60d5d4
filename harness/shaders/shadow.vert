#version 450 core
// Depth-only shadow-map pass; texture coordinate and alpha go on for alpha-tested occluders
// (shadow_alpha.frag), so that both programs place every triangle identically.
layout(location = 0) in vec3 position;
layout(location = 4) in vec2 uv;
layout(location = 5) in vec3 alpha;
layout(location = 0) uniform mat4 lightMatrix;
out vec2 vUv;
flat out vec3 vAlpha;  // one value per mesh: flat, so a threshold equal to it compares exactly
void main() {
  vUv = uv;
  vAlpha = alpha;
  gl_Position = lightMatrix * vec4(position, 1.0);
}
