#version 450 core
// Dynamic angular ranges (§4.3): α_max over the pixels' rays, φ_max over their visible end points.
// Non-negative floats order like their bit patterns, so atomicMax on the bits is a float max.
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
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x < u.viewport.x && pixel.y < u.viewport.y) {
    vec3 dir;
    float dist;
    cameraRay(pixel, dir, dist);
    vec2 endPoint = planeCoords(dir * dist);
    float alpha = alphaOfPlane(planeCoords(dir));
    float phi = phiOfPlane(endPoint);
    atomicMax(groupAlpha, floatBitsToUint(max(alpha, 0.0)));
    atomicMax(groupPhi, floatBitsToUint(max(phi, 0.0)));
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    atomicMax(vsvRanges.alphaMaxBits, groupAlpha);
    atomicMax(vsvRanges.phiMaxBits, groupPhi);
  }
}
