#version 450 core
// Near Epipole (Chen et al. 2011, §3.5): where camera rays run almost along light rays the epipolar
// parameterisation degenerates, so pixels within the radius are ray marched with exact shadow-map
// visibility, stratified and jittered. Point and spot lights march uniformly in gamma (the angle at
// the light, i.e. equiangular sampling), which resolves the 1/r^2 peak of rays passing the light;
// directional lights march uniformly in distance.
#include "common.glsl"
#include "epipolar.glsl"
layout(location = 0) out vec4 outInscatter;

vec3 scatteredAt(vec3 dir, float s) {
  vec3 x = u.eye.xyz + dir * s;
  float visibility = shadowVisibility(x);
  if (visibility <= 0.0) return vec3(0.0);
  return exp(-sigmaT() * s) * visibility * phase(dot(lightTravelDir(x), -dir)) * lightIncident(x);
}

void main() {
  if (!nearEpipole(gl_FragCoord.xy)) discard;
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  int steps = max(int(ep.epipoleInfo.y), 1);
  float offset = random01(uvec4(uint(pixel.x), uint(pixel.y), uint(u.viewport.w), 17u));
  const float golden = 0.61803398875;
  vec3 sum = vec3(0.0);
  float D = ep.axis.w;
  float cosBeta = clamp(dot(dir, ep.axis.xyz), -1.0, 1.0);
  float sinBeta = length(dir - ep.axis.xyz * cosBeta);
  float beta = atan(sinBeta, cosBeta);
  if (!isDirectional() && ep.epipoleInfo.z < 0.5 && sinBeta > 1e-4) {
    float gammaEnd = atan(dist * sinBeta, D - dist * cosBeta);
    float dGamma = gammaEnd / float(steps);
    for (int i = 0; i < steps; ++i) {
      float gamma = (float(i) + fract(offset + float(i) * golden)) * dGamma;
      float sinSum = max(sin(beta + gamma), 1e-20);
      float s = D * sin(gamma) / sinSum;
      sum += scatteredAt(dir, s) * (D * sinBeta / (sinSum * sinSum)) * dGamma;
    }
  } else {
    float ds = dist / float(steps);
    for (int i = 0; i < steps; ++i) sum += scatteredAt(dir, (float(i) + fract(offset + float(i) * golden)) * ds) * ds;
  }
  vec3 result = sum * sigmaS();
  if (any(isnan(result)) || any(isinf(result))) result = vec3(0.0);
  outInscatter = vec4(result, 1.0);
}
