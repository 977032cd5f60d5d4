#version 450 core
// "DSM Generation" (Shook §3): per light texel, march the light ray through the volumes
// (equal steps over its span through the union of the boxes, midpoint rule), accumulate
// opacity 1 - exp(-tau), and store the depth at which it crosses each knot's threshold; the last
// slot holds the final opacity. Interpolation of a crossing between the two steps around it:
// linear in opacity, smoothstep (the paper's) or bucket (the depth before the crossing step).
#include "common.glsl"
#include "dsm.glsl"
layout(location = 0) uniform int face;
layout(location = 0) out vec4 outKnots[DSM_LAYERS];

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
  float tau = 0.0, opacity = 0.0;
  uint crossed = 0u;
  for (int i = 0; i < steps; ++i) {
    float t = span.x + (float(i) + 0.5) * dt;
    tau += volumeCoefficients(origin + dir * t).y * dt;
    float previous = opacity;
    opacity = 1.0 - exp(-tau);
    float d0 = base + span.x + float(i) * dt;
    for (int k = 0; k < DSM_KNOTS; ++k) {
      float threshold = knotThreshold(k);
      if ((crossed & (1u << uint(k))) == 0u && opacity >= threshold && opacity > previous) {
        float w = (threshold - previous) / max(opacity - previous, 1e-30);
#if DSM_INTERP == 1
        w = smoothstep(previous, opacity, threshold);
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
