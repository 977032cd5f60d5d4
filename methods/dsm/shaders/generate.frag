#version 450 core
// "DSM Generation" (Shook §3): per light texel, march the light ray through the volumes
// (equal steps over its span through the union of the boxes, midpoint rule), accumulate
// opacity 1 - exp(-tau), and store the depth at which it crosses each knot's threshold; the last
// slot holds the final opacity. Interpolation of a crossing between the two steps around it:
// linear in opacity (or in optical depth with DSM_SEGMENTS 1, exact under the midpoint rule),
// smoothstep (the paper's) or bucket (the depth before the crossing step). With DSM_CHANNELS 3
// each colour channel has its own map (one draw per channel), otherwise the mean extinction's.
#include "common.glsl"
#include "dsm.glsl"
layout(location = 0) uniform int face;
layout(location = 1) uniform int channel;
layout(location = 0) out vec4 outKnots[DSM_LAYERS];

float extinctionAt(vec3 x) {
#if DSM_CHANNELS == 3
  return volumeExtinction(x)[channel];
#else
  return volumeMeanExtinction(x);
#endif
}

void main() {
  float size = dsm.params.x;
  vec2 ndc = gl_FragCoord.xy / size * 2.0 - 1.0;
  vec4 nearH = dsm.faceInvViewProj[face] * vec4(ndc, -1.0, 1.0);
  vec4 farH = dsm.faceInvViewProj[face] * vec4(ndc, 1.0, 1.0);
  vec3 nearP = nearH.xyz / nearH.w, farP = farH.xyz / farH.w;
  vec3 origin, dir;
  lightRayThrough(lightType() == LIGHT_DIRECTIONAL ? nearP : farP, origin, dir);
  vec2 span = volumeSpan(origin, dir, lightRayStart());
  float base = lightType() == LIGHT_DIRECTIONAL ? dot(origin, dir) : 0.0;
  float values[DSM_LAYERS * 4];
  for (int k = 0; k < DSM_LAYERS * 4; ++k) values[k] = 0.0;
  bool hit = span.y > span.x;
  // Steps of GEN_STEP_VOXELS voxels of the finest volume, at most GEN_STEPS (the paper: a step
  // length, at most 512 steps).
  float voxel = 3.0e38;
  for (int i = 0; i < VS_VOLUMES; ++i) voxel = min(voxel, vol.coeff[i].w);
  int steps = hit ? clamp(int(ceil(min((span.y - span.x) / max(voxel * GEN_STEP_VOXELS, 1e-30), 1e6))), 1, GEN_STEPS) : 0;
  float dt = hit ? (span.y - span.x) / float(steps) : 0.0;
  for (int k = 0; k < DSM_KNOTS; ++k) values[k] = base + (hit ? span.y : 0.0);
  // Relative knots (DSM_RELATIVE) sit at fractions of the ray's final value: a first march finds it.
  float lastValue = 0.0;
#if DSM_RELATIVE == 1
  float tauFinal = 0.0;
  for (int i = 0; i < steps; ++i) tauFinal += extinctionAt(origin + dir * (span.x + (float(i) + 0.5) * dt)) * dt;
  lastValue = finalValue(1.0 - exp(-tauFinal));
#endif
  // Crossings are found in the interpolated quantity (opacity, or optical depth with DSM_SEGMENTS 1).
  float tau = 0.0, opacity = 0.0;
  uint crossed = 0u;
  for (int i = 0; i < steps; ++i) {
    float t = span.x + (float(i) + 0.5) * dt;
    float previousTau = tau, previousOpacity = opacity;
    tau += extinctionAt(origin + dir * t) * dt;
    opacity = 1.0 - exp(-tau);
#if DSM_SEGMENTS == 1
    float previous = previousTau, current = tau;
#else
    float previous = previousOpacity, current = opacity;
#endif
    float d0 = base + span.x + float(i) * dt;
    for (int k = 0; k < DSM_KNOTS; ++k) {
      float target = knotAt(k, lastValue);
      if ((crossed & (1u << uint(k))) == 0u && current >= target && current > previous) {
        float w = (target - previous) / max(current - previous, 1e-30);
#if DSM_INTERP == 1
        w = smoothstep(previous, current, target);
#elif DSM_INTERP == 2
        w = 0.0;
#endif
        values[k] = d0 + clamp(w, 0.0, 1.0) * dt;
        crossed |= 1u << uint(k);
      }
    }
  }
  values[DSM_KNOTS] = hit ? opacity : 0.0;
  for (int j = 0; j < DSM_LAYERS; ++j)
    outKnots[j] = vec4(values[4 * j], values[4 * j + 1], values[4 * j + 2], values[4 * j + 3]);
}
