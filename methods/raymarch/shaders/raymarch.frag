#version 450 core
// Brute-force ray marching of L_s = int_0^d sigma_s exp(-sigma_t s) V(x_s) rho(cos theta) L_in(x_s) ds
// with stratified samples: step i samples s = (i + xi_i) / N * d. Jittered, xi_i = fract(h + i * phi)
// with h a hash of (pixel, seed) and phi the golden ratio (one hash per pixel, not per step);
// otherwise xi_i = 0.5 (midpoint rule).
#include "common.glsl"
layout(location = 0) uniform int steps;
layout(location = 1) uniform int jitter;
layout(location = 0) out vec4 outInscatter;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = u.eye.xyz;
  float ds = dist / float(max(steps, 1));
  vec3 sum = vec3(0.0);
  float pixelOffset = jitter != 0 ? random01(uvec4(uint(pixel.x), uint(pixel.y), uint(u.viewport.w), 0u)) : 0.5;
  const float goldenRatio = 0.61803398875;
  for (int i = 0; i < steps; ++i) {
    float xi = jitter != 0 ? fract(pixelOffset + float(i) * goldenRatio) : 0.5;
    float s = (float(i) + xi) * ds;
    vec3 x = eye + dir * s;
    float visibility = shadowVisibility(x);
    if (visibility <= 0.0) continue;
    float cosTheta = dot(lightTravelDir(x), -dir);
    sum += exp(-sigmaT() * s) * visibility * phase(cosTheta) * lightIncident(x);
  }
  outInscatter = vec4(sum * sigmaS() * ds, 1.0);
}
