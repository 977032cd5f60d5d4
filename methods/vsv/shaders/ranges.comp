#version 450 core
// Dynamic angular ranges (§4.3): α_max over the pixels' rays, φ_max over their visible end points.
// Non-negative floats order like their bit patterns, so atomicMax on the bits is a float max.
// Each invocation takes a RANGES_TILE² block of pixels: one atomic per block, not per pixel.
#define VSV_RANGES_WRITABLE 1
#include "common.glsl"
#include "epipolar.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
shared uint groupAlpha, groupPhi;
void main() {
  if (gl_LocalInvocationIndex == 0u) {
    groupAlpha = 0u;
    groupPhi = 0u;
  }
  barrier();
  float alpha = 0.0, phi = 0.0;
  ivec2 first = ivec2(gl_GlobalInvocationID.xy) * RANGES_TILE;
  ivec2 last = min(first + RANGES_TILE, u.viewport.xy);
  for (int y = first.y; y < last.y; ++y)
    for (int x = first.x; x < last.x; ++x) {
      vec3 dir;
      float dist;
      cameraRay(ivec2(x, y), dir, dist);
      alpha = max(alpha, alphaOfPlane(planeCoords(dir)));
      phi = max(phi, phiOfPlane(planeCoords(dir * dist)));
    }
  atomicMax(groupAlpha, floatBitsToUint(alpha));
  atomicMax(groupPhi, floatBitsToUint(phi));
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    atomicMax(vsvRanges.alphaMaxBits, groupAlpha);
    atomicMax(vsvRanges.phiMaxBits, groupPhi);
  }
}
