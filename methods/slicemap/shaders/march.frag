#version 450 core
// "Scattering": L_s = int_0^d sigma_s exp(-sigma_t s) V(x_s) rho(cos theta) L_in(x_s) ds by
// stratified samples along the camera ray (harness/shaders/march.glsl), V from the slicemaps.
// Samples [firstStep, lastStep) of `steps`; the passes add up (slicemap.cpp, loop budget).
// SLICEMAP_SHARE > 1: groups of that many consecutive samples take their visibility from one
// column fetch (the column at the group's middle), each at its own light depth.
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
#if SLICEMAP_SHARE > 1 && SLICEMAP_CLASSES > 0
  for (int first = firstStep; first < lastStep; first += SLICEMAP_SHARE) {
    int count = min(SLICEMAP_SHARE, lastStep - first);
    float s[SLICEMAP_SHARE], weight[SLICEMAP_SHARE];
    for (int k = 0; k < SLICEMAP_SHARE; ++k) marchSample(m, min(first + k, lastStep - 1), s[k], weight[k]);
    ColumnWords column = fetchColumn(slicemapColumn(eye + dir * (0.5 * (s[0] + s[count - 1]))));
    for (int k = 0; k < SLICEMAP_SHARE; ++k) {
      vec3 x = eye + dir * s[k];
      vec3 visibility = columnTransmittance(column, slicemapDepth(x), 0.0);
#if !SLICEMAP_OPAQUE_IN_SLICES
      visibility *= shadowVisibility(x);
#endif
      if (k < count) sum += visibility * marchInscatter(m, x, dir, s[k], weight[k]);
    }
  }
#else
  for (int i = firstStep; i < lastStep; ++i) {
    float s, weight;
    marchSample(m, i, s, weight);
    vec3 x = eye + dir * s;
    sum += slicemapVisibility(x) * marchInscatter(m, x, dir, s, weight);
  }
#endif
  // Added to the target (cleared to alpha 1: no volume data on the camera ray).
  outInscatter = vec4(all(lessThan(abs(sum), vec3(3.0e38))) ? sum : vec3(0.0), 0.0);
}
