#version 450 core
// "Surface Shadows" (Shook §4): L_surf re-shaded with the DSM's transmittance at each visible
// surface point (beyond the volume this is the stored final opacity), times the shared shadow map.
#include "common.glsl"
#include "dsm.glsl"
layout(location = 0) out vec4 outRadiance;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 visibility = surfaceLightVisibility(pixel);
  if (any(greaterThan(visibility, vec3(0.0)))) visibility *= dsmTransmittance(texelFetch(gPosition, pixel, 0).xyz);
  vec3 L = surfaceRadiance(pixel, visibility);
  outRadiance = vec4(all(lessThan(abs(L), vec3(3.0e38))) ? L : vec3(0.0), 1.0);
}
