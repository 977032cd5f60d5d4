#version 450 core
// Fills the G-buffer where no geometry is hit: the camera ray ends on the far plane.
#include "common.glsl"
in vec2 uv;
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outAlbedo;
void main() {
  vec4 farPoint = u.invViewProj * vec4(uv * 2.0 - 1.0, 1.0, 1.0);
  vec3 p = farPoint.xyz / (abs(farPoint.w) > 1e-30 ? farPoint.w : 1e-30);
  vec3 d = p - u.eye.xyz;
  float len = length(d);
  vec3 dir = len > 1e-20 ? d / len : u.cameraForward.xyz;
  float dist = u.cameraClip.y / max(dot(dir, u.cameraForward.xyz), 1e-6);
  outPosition = vec4(u.eye.xyz + dir * dist, dist);
  outNormal = vec4(0.0);
  outAlbedo = vec4(0.0);
}
