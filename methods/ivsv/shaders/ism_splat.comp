#version 450 core
// Imperfect Shadow Maps (Ritschel et al. 2008) as a compute scatter: point i of the cloud belongs to
// VPL i / points; its distance / far goes into one texel of that VPL's paraboloid tile by atomicMin
// on the float's bits (non-negative floats order like their bit patterns). Points behind the
// light's plane are skipped: nothing is emitted towards them.
#include "common.glsl"
#include "ivsv.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer IvsvPoints { vec4 points[]; };
layout(binding = 3, r32ui) uniform coherent uimage2D splats;
layout(location = 0) uniform int total;
void main() {
  // 2D dispatch: a million points need more than 65,535 workgroups along x.
  int i = int((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x);
  if (i >= total) return;
  int k = i / max(iv.counts.x, 1);
  if (k >= iv.dims.x) return;
  vec3 d = points[i].xyz - vpls[k].position.xyz;
  float r = length(d);
  if (!(r > 1e-20)) return;
  vec3 dir = d / r;
  if (dot(dir, iv.normal.xyz) <= 0.0) return;
  float depth = clamp(r / iv.normal.w, 1e-7, 1.0);
  imageAtomicMin(splats, ismTexel(k, paraboloid(dir)), floatBitsToUint(depth));
}
