#version 450 core
// Dynamic angular ranges (§4.3): α_max over the pixels' rays, φ_max over their visible end points.
// Non-negative floats order like their bit patterns, so atomicMax on the bits is a float max.
// Each invocation takes a RANGES_TILE² block of pixels: one atomic per block, not per pixel. Per
// pixel the angles are reduced as diamond angles (monotone in the angle, no atan); a workgroup
// turns its maxima into angles once: 1.7 → 1.3 ms on room, 1.5 → 1.2 on terrain (384x288).
#define VSV_RANGES_WRITABLE 1
#include "common.glsl"
#include "epipolar.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
shared uint groupAlpha, groupPhi;

// A monotone stand-in for the angle of (x, y), y >= 0, in [0, 2] for [0, π]: y / (x + y) for
// x >= 0, else 2 - y / (y - x). Well conditioned at small angles, unlike 1 - cos.
float diamondAngle(vec2 v) {
  float sum = abs(v.x) + v.y;
  if (!(sum > 0.0)) return 0.0;
  float d = v.y / sum;
  return v.x >= 0.0 ? d : 2.0 - d;
}
float angleOfDiamond(float d) {
  return d <= 1.0 ? safeAtan(d, 1.0 - d) : safeAtan(2.0 - d, 1.0 - d);
}

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    groupAlpha = 0u;
    groupPhi = 0u;
  }
  barrier();
  float alpha = 0.0, phi = 0.0;  // diamond angles; for a directional light φ itself
  ivec2 first = ivec2(gl_GlobalInvocationID.xy) * RANGES_TILE;
  ivec2 last = min(first + RANGES_TILE, u.viewport.xy);
  float D = gridDistance();
  for (int y = first.y; y < last.y; ++y)
    for (int x = first.x; x < last.x; ++x) {
      vec3 dir;
      float dist;
      cameraRay(ivec2(x, y), dir, dist);
      vec2 p = planeCoords(dir);  // (cos α, sin α)
      alpha = max(alpha, diamondAngle(p));
      p *= dist;  // the end point in its half-plane
      phi = max(phi, parallelLight() ? p.y : diamondAngle(vec2(D - p.x, p.y)));
    }
  atomicMax(groupAlpha, floatBitsToUint(alpha));
  atomicMax(groupPhi, floatBitsToUint(phi));
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    float phiMaxHere = uintBitsToFloat(groupPhi);
    atomicMax(vsvRanges.alphaMaxBits, floatBitsToUint(angleOfDiamond(uintBitsToFloat(groupAlpha))));
    atomicMax(vsvRanges.phiMaxBits, floatBitsToUint(parallelLight() ? phiMaxHere : angleOfDiamond(phiMaxHere)));
  }
}
