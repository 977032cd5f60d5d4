#version 450 core
// Brute-force ray marching of L_s = int_0^d sigma_s exp(-sigma_t s) V(x_s) rho(cos theta) L_in(x_s) ds
// with N stratified samples, uniform or equiangular (harness/shaders/march.glsl).
// Volume data: sigma_s(x), the camera ray's optical depth (trapezoid rule between samples) and the
// volumes' transmittance towards the light by a nested march. Semi-transparent occluders: V is
// the transmittance map's product (common.glsl). This pass marches samples [firstStep, lastStep):
// the method splits long marches into several passes (raymarch.cpp, "loop budget").
#include "common.glsl"
#include "march.glsl"
layout(location = 0) uniform int steps;
layout(location = 1) uniform int jitter;
layout(location = 2) uniform float volumeStepsPerVoxel;  // light-ray steps per voxel through volume data
layout(location = 3) uniform int firstStep;
layout(location = 4) uniform int lastStep;
layout(location = 5) uniform int lightStepsMax;          // per volume and sample
layout(location = 0) out vec4 outInscatter;
#if AREA_SAMPLES > 0
// Area lights: AREA_SAMPLES stratified points on the light (raymarch.cpp), each a cosine-lobed
// point light with its own cube shadow map.
layout(std140, binding = 3) uniform AreaLightBlock {
  vec4 position[256];
  vec4 weight;  // rgb radiance x area / samples
  vec4 range;   // near, far of the cube maps
} al;
layout(binding = 11) uniform samplerCubeArrayShadow lightSampleShadows;

// L_in summed over the light samples, times the phase towards the eye (per unit sigma_s).
vec3 areaLightInscatter(vec3 x, vec3 dir) {
  vec3 total = vec3(0.0);
  float n = al.range.x, f = al.range.y;
  for (int k = 0; k < AREA_SAMPLES; ++k) {
    vec3 d = x - al.position[k].xyz;
    float r2 = max(dot(d, d), 1e-12);
    float r = sqrt(r2);
    vec3 l = d / r;
    float m = max(abs(d.x), max(abs(d.y), abs(d.z)));
    float zNdc = (f + n) / max(f - n, 1e-20) - 2.0 * f * n / max((f - n) * m, 1e-20);
    float v = texture(lightSampleShadows, vec4(d, float(k)), clamp(zNdc * 0.5 + 0.5, 0.0, 1.0));
    total += areaEmission(l) * v * exp(-sigmaT() * r) / r2 * phase(dot(l, -dir));
  }
  return total * al.weight.rgb;
}
#endif
#if VS_VOLUMES > 0
// The camera ray's rgb optical depth up to the previous sample (xyz) and its distance (w), carried
// from pass to pass.
layout(binding = 10) uniform sampler2D opticalDepthIn;
layout(location = 1) out vec4 outVolumeTransmittance;
layout(location = 2) out vec4 outOpticalDepth;
#endif
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = u.eye.xyz;
  March m = beginMarch(pixel, eye, dir, dist, steps, jitter != 0);
  float pixelOffset = m.pixelOffset;
  vec3 sum = vec3(0.0);
#if VS_VOLUMES > 0
  vec3 tau = vec3(0.0);
  float sPrev = 0.0;
  if (firstStep > 0) {
    vec4 carried = texelFetch(opticalDepthIn, pixel, 0);
    tau = carried.xyz;
    sPrev = carried.w;
  }
  vec3 sigmaTPrev = volumeExtinction(eye + dir * sPrev);
#endif
  for (int i = firstStep; i < lastStep; ++i) {
    float s, weight;
    marchSample(m, i, s, weight);
    vec3 x = eye + dir * s;
    vec3 visibility = lightVisibility(x);
    float cosTheta = dot(lightTravelDir(x), -dir);
#if VS_VOLUMES > 0
    vec3 volumeScattering, extinction;
    volumeCoefficients(x, volumeScattering, extinction);
    tau += 0.5 * (sigmaTPrev + extinction) * (s - sPrev);
    sPrev = s;
    sigmaTPrev = extinction;
    vec3 scattering = sigmaS() + volumeScattering;
    // Nested march towards the light, only where this sample scatters and is not in a shadow.
    int lightSteps = any(greaterThan(scattering, vec3(0.0))) && any(greaterThan(visibility, vec3(0.0))) ? lightStepsMax : 0;
    float offset = jitter != 0 ? fract(pixelOffset + float(i) * 0.7548776662) : 0.5;
    visibility *= volumeLightTransmittance(x, volumeStepsPerVoxel, lightSteps, offset);
    sum += weight * scattering * exp(-sigmaT() * s - tau) * visibility * phase(cosTheta) * lightIncident(x);
#elif AREA_SAMPLES > 0
    sum += weight * sigmaS() * exp(-sigmaT() * s) * areaLightInscatter(x, dir);
#else
    sum += visibility * marchInscatter(m, x, dir, s, weight);
#endif
  }
#if VS_VOLUMES > 0
  outOpticalDepth = vec4(tau, sPrev);
  vec3 tauTotal = tau + (lastStep >= m.n ? sigmaTPrev * max(dist - sPrev, 0.0) : vec3(0.0));
  outInscatter = vec4(sum, 1.0);
  outVolumeTransmittance = vec4(exp(-tauTotal), 1.0);
#else
  outInscatter = vec4(sum, 1.0);
#endif
}
