#version 450 core
// "Scattering": L_s = int_0^d sigma_s exp(-sigma_t s) V(x_s) rho(cos theta) L_in(x_s) ds by
// stratified samples along the camera ray (harness/shaders/march.glsl), V from the slicemaps.
// Samples [firstStep, lastStep) of `steps`; the passes add up (slicemap.cpp, loop budget).
#include "common.glsl"
#include "march.glsl"
#include "slicemap.glsl"
layout(location = 0) uniform int steps;
layout(location = 1) uniform int jitter;
layout(location = 2) uniform int firstStep;
layout(location = 3) uniform int lastStep;
layout(location = 0) out vec4 outInscatter;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = u.eye.xyz;
  March m = beginMarch(pixel, eye, dir, dist, steps, jitter != 0);
  vec3 sum = vec3(0.0);
  for (int i = firstStep; i < lastStep; ++i) {
    float s, weight;
    marchSample(m, i, s, weight);
    vec3 x = eye + dir * s;
    vec3 visibility = slicemapVisibility(x);
    sum += visibility * marchInscatter(m, x, dir, s, weight);
  }
  // Added to the target (cleared to alpha 1: no volume data on the camera ray).
  outInscatter = vec4(all(lessThan(abs(sum), vec3(3.0e38))) ? sum : vec3(0.0), 0.0);
}
