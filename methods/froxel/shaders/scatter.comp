#version 450 core
// Froxel Scattering: per froxel, the in-scattered radiance per unit length sigma_s V rho L_in at
// `samples` stratified distances along the ray through the tile's centre within the slice
// (averaged), and with volume data the volumes' extinction there; V from the shared shadow map
// and transmittance map, times the volumes' transmittance towards the light.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "common.glsl"
#include "froxel.glsl"
layout(location = 0) uniform int lightSteps;  // per volume, towards the light
layout(binding = 0, rgba32f) writeonly uniform image3D scatteringOut;
#if VS_VOLUMES > 0
layout(binding = 1, rgba32f) writeonly uniform image3D extinctionOut;
#endif

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(c, fx.grid.xyz))) return;
  vec3 dir = froxelRayDir((vec2(c.xy) + 0.5) * float(fx.grid.w));
  vec3 eye = u.eye.xyz;
  float t0 = froxelBoundary(float(c.z)), t1 = froxelBoundary(float(c.z + 1));
  int n = max(int(fx.range.z), 1);
  vec3 inscatter = vec3(0.0), volumeExt = vec3(0.0);
  for (int i = 0; i < n; ++i) {
    float t = mix(t0, t1, (float(i) + fx.range.w) / float(n));
    vec3 x = eye + dir * t;
    vec3 visibility = lightVisibility(x);
    vec3 scattering = vec3(sigmaS());
#if VS_VOLUMES > 0
    vec3 volumeScattering, extinction;
    volumeCoefficients(x, volumeScattering, extinction);
    scattering += volumeScattering;
    volumeExt += extinction;
    int steps = any(greaterThan(scattering, vec3(0.0))) && any(greaterThan(visibility, vec3(0.0))) ? lightSteps : 0;
    visibility *= volumeLightTransmittance(x, 1.0, steps, fx.range.w);
#endif
    inscatter += scattering * visibility * phase(dot(lightTravelDir(x), -dir)) * lightIncident(x);
  }
  imageStore(scatteringOut, c, vec4(inscatter / float(n), 0.0));
#if VS_VOLUMES > 0
  imageStore(extinctionOut, c, vec4(volumeExt / float(n), 0.0));
#endif
}
