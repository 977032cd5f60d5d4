#version 450 core
// Test probe: the GPU epipolar transform of points, for comparison with the CPU one.
#include "common.glsl"
#include "epipolar.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 1) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 2) writeonly buffer Coords { vec4 coords[]; };  // θ, α, φ
layout(std430, binding = 3) writeonly buffer Cells { ivec4 cells[]; };   // row, column, bin
layout(location = 0) uniform int count;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= count) return;
  vec3 c = epipolarCoords(points[i].xyz);
  coords[i] = vec4(c, 0.0);
  cells[i] = ivec4(thetaRow(c.x), alphaColumn(c.y, alphaMax()), phiBin(c.z, phiMax()), 0);
}
