#version 450 core
// Brute-force ray marching of L_s = int_0^d sigma_s exp(-sigma_t s) V(x_s) rho(cos theta) L_in(x_s) ds
// with N stratified samples u_i = (i + xi_i) / N. Jittered, xi_i = fract(h + i * phi) with h a hash
// of (pixel, seed) and phi the golden ratio (one hash per pixel, not per step); otherwise 0.5.
//  - uniform:     s_i = u_i d, weight d / N.
//  - equiangular: (point and spot lights) s_i spaced evenly in the angle seen from the light,
//    s = delta + D tan(theta), weight (theta_b - theta_a) r^2 / (D N): it cancels the 1/r^2 of
//    L_in, so rays passing close to the light converge as fast as the others.
#include "common.glsl"
layout(location = 0) uniform int steps;
layout(location = 1) uniform int jitter;
// EQUIANGULAR is defined by the method at build time (0 or 1): a uniform would cost a branch per
// step, which llvmpipe does not hoist.
layout(location = 0) out vec4 outInscatter;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = u.eye.xyz;
  int n = max(steps, 1);
  float pixelOffset = jitter != 0 ? random01(uvec4(uint(pixel.x), uint(pixel.y), uint(u.viewport.w), 0u)) : 0.5;
  const float goldenRatio = 0.61803398875;

  const bool angular = EQUIANGULAR != 0 && lightType() != LIGHT_DIRECTIONAL;
  float delta = 0.0, D = 1.0, thetaA = 0.0, thetaB = 0.0;
  if (angular) {
    vec3 toLight = u.lightPos.xyz - eye;
    delta = dot(toLight, dir);                                   // ray parameter closest to the light
    D = max(length(toLight - delta * dir), 1e-6 * max(dist, 1.0));  // light's distance from the ray
    thetaA = atan(-delta, D);
    thetaB = atan(dist - delta, D);
  }
  vec3 sum = vec3(0.0);
  for (int i = 0; i < n; ++i) {
    float ui = (float(i) + (jitter != 0 ? fract(pixelOffset + float(i) * goldenRatio) : 0.5)) / float(n);
    float s, weight;
    if (angular) {
      float theta = mix(thetaA, thetaB, ui);
      s = clamp(delta + D * tan(theta), 0.0, dist);
      float r2 = D * D + (s - delta) * (s - delta);
      weight = (thetaB - thetaA) * r2 / (D * float(n));
    } else {
      s = ui * dist;
      weight = dist / float(n);
    }
    vec3 x = eye + dir * s;
    float visibility = shadowVisibility(x);
    if (visibility <= 0.0) continue;
    float cosTheta = dot(lightTravelDir(x), -dir);
    sum += weight * exp(-sigmaT() * s) * visibility * phase(cosTheta) * lightIncident(x);
  }
  outInscatter = vec4(sum * sigmaS(), 1.0);
}
