#version 450 core
// "Voxelize: From SM" (§4.1.3): one point per (θ row, φ bin). The light ray at the cell centre is
// looked up in the shadow map; its first occluder becomes one bit at (α_d, θ). Directional light:
// the ray is the line parallel to the axis at distance φ from it.
#include "common.glsl"
#include "epipolar.glsl"
#include "shadow_rays.glsl"
flat out int vBin;

void main() {
  gl_PointSize = 1.0;
  vBin = gl_VertexID % nPhi();
  int row = gl_VertexID / nPhi();
  int col = occluderColumn(row, vBin);
  if (col < 0) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: no bit
    return;
  }
  vec2 texel = (vec2(col, row) + 0.5) / vec2(nAlpha(), nTheta());
  gl_Position = vec4(texel * 2.0 - 1.0, 0.0, 1.0);
}
