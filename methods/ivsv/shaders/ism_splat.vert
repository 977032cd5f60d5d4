#version 450 core
// Imperfect Shadow Maps (Ritschel et al. 2008): point i of the cloud belongs to VPL i / points and
// is splatted as one texel into that VPL's paraboloid tile, depth = distance / far.
#include "common.glsl"
#include "ivsv.glsl"
layout(std430, binding = 0) readonly buffer IvsvPoints { vec4 points[]; };
out float vDistance;
void main() {
  int k = gl_VertexID / max(iv.counts.x, 1);
  vec3 d = points[gl_VertexID].xyz - vpls[k].position.xyz;
  float r = length(d);
  vec3 dir = r > 1e-20 ? d / r : iv.normal.xyz;
  vDistance = r / iv.normal.w;
  gl_PointSize = 1.0;
  // Behind the light's plane nothing is emitted: such points cast no shadow that matters.
  if (dot(dir, iv.normal.xyz) <= 0.0 || r <= 1e-20 || k >= iv.dims.x) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);  // clipped
    return;
  }
  float res = float(iv.dims.w), tiles = float(iv.dims.z);
  vec2 texel = vec2(ismTexel(k, paraboloid(dir))) + 0.5;
  gl_Position = vec4(texel / (res * tiles) * 2.0 - 1.0, clamp(vDistance, 0.0, 1.0) * 2.0 - 1.0, 1.0);
}
