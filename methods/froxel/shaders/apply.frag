#version 450 core
// Froxel Apply: L_s of each pixel read from the integrated grid at the distance of its surface,
// bilinear across tiles and linear in the boundary index between the slices' far boundaries (the
// eye's boundary holds 0). With volume data, also the volumes' transmittance along the ray.
#include "common.glsl"
#include "froxel.glsl"
layout(binding = 10) uniform sampler3D integratedIn;
layout(location = 0) out vec4 outInscatter;
#if VS_VOLUMES > 0
layout(binding = 11) uniform sampler3D opticalDepthIn;
layout(location = 1) out vec4 outVolumeTransmittance;
#endif

// The grid's value at boundary index j (0 at the eye) at the pixel's tile coordinates.
vec3 atBoundary(sampler3D grid, vec2 tileUv, int j) {
  if (j <= 0) return vec3(0.0);
  return textureLod(grid, vec3(tileUv, (float(min(j, fx.grid.z)) - 0.5) / float(fx.grid.z)), 0.0).rgb;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec2 tileUv = gl_FragCoord.xy / (float(fx.grid.w) * vec2(fx.grid.xy));
  float x = froxelIndexOf(dist);
  int j = int(floor(x));
  float f = x - float(j);
  outInscatter = vec4(mix(atBoundary(integratedIn, tileUv, j), atBoundary(integratedIn, tileUv, j + 1), f), 1.0);
#if VS_VOLUMES > 0
  vec3 depth = mix(atBoundary(opticalDepthIn, tileUv, j), atBoundary(opticalDepthIn, tileUv, j + 1), f);
  outVolumeTransmittance = vec4(exp(-depth), 1.0);
#endif
}
