#version 450 core
// Froxel Integration: front to back along each column of froxels with the energy-conserving
// integral of a slice of constant source S and extinction sigma (Hillaire 2015):
// int_0^dt S exp(-sigma s) ds = S (1 - exp(-sigma dt)) / sigma. Slice k stores L_s and, with volume
// data, the volumes' optical depth from the eye to its far boundary.
layout(local_size_x = 8, local_size_y = 8) in;
#include "common.glsl"
#include "froxel.glsl"
layout(binding = 10) uniform sampler3D scatteringIn;
layout(binding = 0, rgba32f) writeonly uniform image3D integratedOut;
#if VS_VOLUMES > 0
layout(binding = 11) uniform sampler3D extinctionIn;
layout(binding = 1, rgba32f) writeonly uniform image3D opticalDepthOut;
#endif

void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, fx.grid.xy))) return;
  vec3 radiance = vec3(0.0), transmittance = vec3(1.0), volumeDepth = vec3(0.0);
  for (int k = 0; k < fx.grid.z; ++k) {
    float dt = froxelBoundary(float(k + 1)) - froxelBoundary(float(k));
    vec3 source = texelFetch(scatteringIn, ivec3(c, k), 0).rgb;
    vec3 sigma = vec3(sigmaT());
#if VS_VOLUMES > 0
    vec3 volumeSigma = texelFetch(extinctionIn, ivec3(c, k), 0).rgb;
    sigma += volumeSigma;
    volumeDepth += volumeSigma * dt;
    imageStore(opticalDepthOut, ivec3(c, k), vec4(volumeDepth, 0.0));
#endif
    vec3 sliceT = exp(-sigma * dt);
    // S (1 - e^{-sigma dt}) / sigma, and S dt where sigma dt is too small to divide by.
    vec3 sliceIntegral = mix(source * (1.0 - sliceT) / max(sigma, vec3(1e-30)), source * dt,
                             lessThan(sigma * dt, vec3(1e-4)));
    radiance += transmittance * sliceIntegral;
    transmittance *= sliceT;
    imageStore(integratedOut, ivec3(c, k), vec4(radiance, 0.0));
  }
}
