#version 450 core
// Light Texture Precomputation (Chen et al. 2011, §3.4): with a light texture T (here also the spot
// cone and a point light's cosine lobe, which are functions of the light ray too) the gamma factor of the low-rank terms depends on
// the slice: per slice k, prefix sums of Gamma_i(gamma) T(alpha_k, gamma) over gamma at a reduced
// resolution (trapezoid rule), row k * rank + i of the table. MINMAX_RANK is a compile-time
// constant (minmax.cpp): with the rank loops unrolled the per-rank sums stay in registers, where
// llvmpipe keeps a dynamically indexed local array in memory, per lane.
#include "common.glsl"
#include "epipolar.glsl"
layout(local_size_x = 64) in;
layout(binding = 14) uniform sampler2D basisGamma;  // kGridSize x rank, Gamma_i at the gamma grid
layout(rgba32f, binding = 0) uniform writeonly image2D texturedPrefix;

// T(alpha, gamma) for the light ray gamma of the slice with in-slice normal n.
vec3 lightRayTexture(vec3 n, float gamma) {
  if (isDirectional()) return lightTextureAt(u.eye.xyz + gamma * n);
  vec3 w = -cos(gamma) * ep.axis.xyz + sin(gamma) * n;
  vec3 x = u.lightPos.xyz + w;
  vec3 t = lightTextureAt(x);
  if (lightType() == LIGHT_SPOT) {
    float cosOuter = u.lightDir.w, cosInner = u.lightColor.w;
    t *= clamp((dot(w, u.lightDir.xyz) - cosOuter) / max(cosInner - cosOuter, 1e-6), 0.0, 1.0);
  }
  if (cosineLobe()) t *= areaEmission(w);
  return t;
}

float basisGammaAt(int i, float gamma) {
  float x = gammaGridCoord(gamma) * float(kGridSize - 1);
  int k = min(int(x), kGridSize - 2);
  float w = x - float(k);
  return mix(texelFetch(basisGamma, ivec2(k, i), 0).r, texelFetch(basisGamma, ivec2(k + 1, i), 0).r, w);
}

void main() {
  int slice = int(gl_GlobalInvocationID.x);
  if (slice >= ep.counts.x) return;
  const int rank = MINMAX_RANK;
  int res = ep.counts.w;
  vec3 n = sliceNormal(sliceAlpha(slice));
  float step = ep.gammaInfo.y / float(res);
  vec3 sums[MINMAX_RANK];
  float previous[MINMAX_RANK];
  vec3 previousT = lightRayTexture(n, 0.0);
  for (int i = 0; i < rank; ++i) {
    sums[i] = vec3(0.0);
    previous[i] = basisGammaAt(i, 0.0);
    imageStore(texturedPrefix, ivec2(0, slice * rank + i), vec4(0.0));
  }
  for (int m = 1; m <= res; ++m) {
    float gamma = float(m) * step;
    vec3 t = lightRayTexture(n, gamma);
    for (int i = 0; i < rank; ++i) {
      float g = basisGammaAt(i, gamma);
      sums[i] += 0.5 * step * (previous[i] * previousT + g * t);
      previous[i] = g;
      imageStore(texturedPrefix, ivec2(m, slice * rank + i), vec4(sums[i], 0.0));
    }
    previousT = t;
  }
}
