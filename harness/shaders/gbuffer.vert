#version 450 core
#include "common.glsl"
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 albedo;
layout(location = 4) in vec2 uv;
layout(location = 5) in vec3 alpha;
out vec3 vPosition;
out vec2 vUv;
out vec3 vAlpha;
out vec3 vNormal;
out vec3 vAlbedo;
void main() {
  vPosition = position;
  vNormal = normal;
  vAlbedo = albedo;
  vUv = uv;
  vAlpha = alpha;
  gl_Position = u.viewProj * vec4(position, 1.0);
}
