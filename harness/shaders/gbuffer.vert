#version 450 core
#include "common.glsl"
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 albedo;
out vec3 vPosition;
out vec3 vNormal;
out vec3 vAlbedo;
void main() {
  vPosition = position;
  vNormal = normal;
  vAlbedo = albedo;
  gl_Position = u.viewProj * vec4(position, 1.0);
}
