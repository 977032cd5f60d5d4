#version 450 core
// Froxel Scattering: per froxel, the in-scattered radiance per unit length sigma_s V rho L_in at
// `samples` stratified distances along the ray through the tile's centre within the slice
// (averaged), and with volume data the volumes' extinction there; V from the shared shadow map
// and transmittance map, times the volumes' transmittance towards the light. With temporal
// reprojection the froxel's centre is projected into the previous frame's grid, and the history
// found there (trilinear) is blended in with weight previousEye.w; outside it, none.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "common.glsl"
#include "froxel.glsl"
layout(location = 0) uniform int lightSteps;  // per volume, towards the light
layout(binding = 0, rgba32f) writeonly uniform image3D scatteringOut;
layout(binding = 12) uniform sampler3D scatteringHistory;
#if VS_VOLUMES > 0
layout(binding = 1, rgba32f) writeonly uniform image3D extinctionOut;
layout(binding = 13) uniform sampler3D extinctionHistory;
#endif

// Texture coordinates of world point x in the previous frame's grid; false outside it.
bool previousGridCoord(vec3 x, out vec3 coord) {
  vec4 clip = fx.previousViewProj * vec4(x, 1.0);
  if (clip.w <= 1e-20) return false;
  vec2 ndc = clip.xy / clip.w;
  if (any(greaterThan(abs(ndc), vec2(1.0)))) return false;
  vec2 pixel = (ndc * 0.5 + 0.5) * vec2(u.viewport.xy);
  coord.xy = pixel / (float(fx.grid.w) * vec2(fx.grid.xy));
  coord.z = froxelIndexOf(length(x - fx.previousEye.xyz)) / float(fx.grid.z);
  return coord.z < 1.0;
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(c, fx.grid.xyz))) return;
  vec3 dir = froxelRayDir((vec2(c.xy) + 0.5) * float(fx.grid.w));
  vec3 eye = u.eye.xyz;
  float t0 = froxelBoundary(float(c.z)), t1 = froxelBoundary(float(c.z + 1));
  int n = max(int(fx.range.z), 1);
  // The history first: the froxel's centre in boundary-index space (its texel centre), so that a
  // still camera finds each froxel's own history and no other slice's. Read before the volumes'
  // loop: llvmpipe (Mesa 22.3) returned wrong texels for this read when it followed the loop's
  // indexing of the volumes' sampler array (legal GLSL, any order is right on other drivers).
  vec3 coord, scatteringBefore = vec3(0.0), extinctionBefore = vec3(0.0);
  const bool history = fx.previousEye.w > 0.0 && previousGridCoord(eye + dir * froxelBoundary(float(c.z) + 0.5), coord);
  if (history) {
    scatteringBefore = textureLod(scatteringHistory, coord, 0.0).rgb;
#if VS_VOLUMES > 0
    extinctionBefore = textureLod(extinctionHistory, coord, 0.0).rgb;
#endif
  }
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
  inscatter /= float(n);
  volumeExt /= float(n);
  if (history) {
    inscatter = mix(inscatter, scatteringBefore, fx.previousEye.w);
    volumeExt = mix(volumeExt, extinctionBefore, fx.previousEye.w);
  }
  imageStore(scatteringOut, c, vec4(inscatter, 0.0));
#if VS_VOLUMES > 0
  imageStore(extinctionOut, c, vec4(volumeExt, 0.0));
#endif
}
