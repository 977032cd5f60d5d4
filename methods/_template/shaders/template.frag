#version 450 core
// L_s = int_0^d sigma_s exp(-sigma_t s) V(x_s) rho(cos theta) L_in(x_s) ds by `steps` uniform
// samples at the centres of equal intervals; V from the shared shadow map (common.glsl).
#include "common.glsl"
layout(location = 0) uniform int steps;
layout(location = 0) out vec4 outInscatter;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = u.eye.xyz;
  int n = max(steps, 1);
  float ds = dist / float(n);
  vec3 sum = vec3(0.0);
  for (int i = 0; i < n; ++i) {
    float s = (float(i) + 0.5) * ds;
    vec3 x = eye + dir * s;
    float cosTheta = dot(lightTravelDir(x), -dir);
    sum += ds * sigmaS() * exp(-sigmaT() * s) * lightVisibility(x) * phase(cosTheta) * lightIncident(x);
  }
  outInscatter = vec4(sum, 1.0);
}
