#version 450 core
// "Volume March" (Shook §4): L_s along the camera ray. VIEW_STEPS stratified samples over the ray's
// span through the volume boxes (heterogeneous sigma_s, camera optical depth by the trapezoid
// rule) and HAZE_STEPS over the rest of the ray, where only the homogeneous medium scatters.
// Light reaching a sample: L_in x shadow-map (and translucency) visibility x the DSM's volume
// transmittance.
#include "common.glsl"
#include "dsm.glsl"
#include "equiangular.glsl"
layout(location = 0) uniform int jitter;
layout(location = 0) out vec4 outInscatter;
layout(location = 1) out vec4 outVolumeTransmittance;

// In-scattered radiance at x for a volume transmittance from the DSM.
vec3 inscatterAt(vec3 x, vec3 dir, vec3 scattering, vec3 volumeTransmittance) {
  if (all(lessThanEqual(scattering, vec3(0.0)))) return vec3(0.0);
  vec3 visibility = lightVisibility(x);
  if (all(equal(visibility, vec3(0.0)))) return vec3(0.0);
  float cosTheta = dot(lightTravelDir(x), -dir);
  return scattering * visibility * volumeTransmittance * phase(cosTheta) * lightIncident(x);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = u.eye.xyz;
  float offset = jitter != 0 ? random01(uvec4(uint(pixel.x), uint(pixel.y), uint(u.viewport.w), 0u)) : 0.5;
  const float goldenRatio = 0.61803398875;

  // The camera ray's span through the volumes, clipped to [0, dist].
  vec2 span = volumeSpan(eye, dir, 0.0);
  span = vec2(max(span.x, 0.0), min(span.y, dist));
  bool inside = span.y > span.x;
  float a = inside ? span.x : dist, b = inside ? span.y : dist;

  // Inside the span: volume + haze, optical depth accumulated sample to sample.
  vec3 sum = vec3(0.0);
  vec3 tauVolume = vec3(0.0), sigmaPrev = vec3(0.0);
  float sPrev = a;
  float dtV = (b - a) / float(VIEW_STEPS);
  // Fixed trip counts: llvmpipe ended data-dependent loops early around nested loops.
  if (inside) for (int i = 0; i < VIEW_STEPS; ++i) {
    float s = a + (float(i) + (jitter != 0 ? fract(offset + float(i) * goldenRatio) : 0.5)) * dtV;
    vec3 x = eye + dir * s;
    vec3 scattering, extinction;
    volumeCoefficients(x, scattering, extinction);
    if (i == 0) sigmaPrev = extinction;  // [a, first sample]: the box's face may read as outside
    tauVolume += 0.5 * (sigmaPrev + extinction) * (s - sPrev);
    sPrev = s;
    sigmaPrev = extinction;
    sum += dtV * exp(-sigmaT() * s - tauVolume) * inscatterAt(x, dir, sigmaS() + scattering, dsmTransmittance(x));
  }
  tauVolume += sigmaPrev * max(b - sPrev, 0.0);

  // Outside the span: the haze in front of the volumes [0, a) and behind them (b, dist]. Point and
  // spot lights: equiangular samples over the whole ray (harness/shaders/equiangular.glsl, as
  // raymarch's sampling=equiangular), those inside the span add nothing. Directional: the two
  // pieces share the samples in proportion to length x the volumes' transmittance (known now), so
  // that haze seen through a dense volume takes few; within a piece the samples are equal steps.
  float front = a, back = max(dist - b, 0.0), haze = front + back;
  bool angular = lightType() != LIGHT_DIRECTIONAL;
  EquiangularSpan around = EquiangularSpan(0.0, 1.0, 0.0, 0.0);
  if (angular) around = equiangularSpan(u.lightPos.xyz, eye, dir, dist);
  vec3 through = exp(-tauVolume);
  float behind = max((through.r + through.g + through.b) / 3.0, 1e-30);
  float measure = front + back * behind;  // samples per unit length: 1 in front, `behind` behind
  float dtH = measure / float(max(HAZE_STEPS, 1));
  if (haze > 0.0 && measure > 0.0 && sigmaS() > 0.0) for (int i = 0; i < HAZE_STEPS; ++i) {
    float ui = stratumPosition(i, HAZE_STEPS, offset, jitter != 0, 0.7548776662);
    float s, weight;
    if (angular) {
      s = equiangularDistance(around, ui, dist);
      weight = s >= a && s <= b && inside ? 0.0 : equiangularWeight(around, s, HAZE_STEPS);
    } else {
      float h = ui * measure;
      s = h < front ? h : min(b + (h - front) / behind, dist);
      weight = h < front ? dtH : dtH / behind;
    }
    vec3 tau = sigmaT() * s + (s > b ? tauVolume : vec3(0.0));
    vec3 x = eye + dir * s;
    if (weight > 0.0) sum += weight * exp(-tau) * inscatterAt(x, dir, vec3(sigmaS()), dsmHazeTransmittance(x));
  }
  vec3 L = all(lessThan(abs(sum), vec3(3.0e38))) ? sum : vec3(0.0);
  outInscatter = vec4(L, 1.0);
  outVolumeTransmittance = vec4(through, 1.0);
}
