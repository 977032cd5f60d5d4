#version 450 core
// L_surf: Lambert surfaces lit by the light with shadow-map visibility and the transmittance of
// semi-transparent occluders and volume data towards the light (the same for every method).
#include "common.glsl"
layout(location = 0) out vec4 outRadiance;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 visibility = surfaceLightVisibility(pixel);
#if VS_VOLUMES > 0
  // Volume shadows on surfaces: 2 steps per voxel along the light ray (the same for every method).
  if (any(greaterThan(visibility, vec3(0.0)))) visibility *= volumeLightTransmittance(texelFetch(gPosition, pixel, 0).xyz, 2.0, 4096, 0.5);
#endif
  outRadiance = vec4(surfaceRadiance(pixel, visibility), 1.0);
}
