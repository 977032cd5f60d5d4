#version 450 core
#include "common.glsl"
in vec3 vPosition;
in vec3 vNormal;
in vec3 vAlbedo;
in vec2 vUv;
in vec3 vAlpha;
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outAlbedo;
void main() {
  // The camera sees through texels of no opacity (MASK cut-outs, BLEND alpha 0); every other
  // surface is its first hit (a semi-transparent one too: README, "What is computed").
  if (vAlpha.x > -0.5 && surfaceOpacity(vAlpha, vUv) <= 0.0) discard;
  vec3 toEye = u.eye.xyz - vPosition;
  vec3 n = vNormal;
  float len = length(n);
  n = len > 1e-20 ? n / len : vec3(0.0, 1.0, 0.0);
  if (dot(n, toEye) < 0.0) n = -n;  // two-sided surfaces
  outPosition = vec4(vPosition, length(toEye));
  outNormal = vec4(n, 1.0);
  outAlbedo = vec4(vAlbedo, 1.0);
}
