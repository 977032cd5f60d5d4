#version 450 core
// Near Epipole (Chen et al. 2011, §3.5): where camera rays run almost along light rays the epipolar
// parameterisation degenerates (1 / sin beta), so pixels within the radius are ray marched,
// stratified and jittered like the reference.
#include "common.glsl"
#include "epipolar.glsl"
layout(location = 0) out vec4 outInscatter;
void main() {
  if (!nearEpipole(gl_FragCoord.xy)) discard;
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  int steps = max(int(ep.epipoleInfo.y), 1);
  float ds = dist / float(steps);
  float offset = random01(uvec4(uint(pixel.x), uint(pixel.y), uint(u.viewport.w), 17u));
  vec3 sum = vec3(0.0);
  for (int i = 0; i < steps; ++i) {
    float s = (float(i) + fract(offset + float(i) * 0.61803398875)) * ds;
    vec3 x = u.eye.xyz + dir * s;
    float visibility = shadowVisibility(x);
    if (visibility <= 0.0) continue;
    sum += exp(-sigmaT() * s) * visibility * phase(dot(lightTravelDir(x), -dir)) * lightIncident(x);
  }
  outInscatter = vec4(sum * sigmaS() * ds, 1.0);
}
