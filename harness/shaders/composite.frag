#version 450 core
// L = L_surf * exp(-sigma_t d) * T_volumes + L_s, with T_volumes (the camera ray's transmittance
// through volume data) in the in-scatter target's alpha.
#include "common.glsl"
layout(binding = 6) uniform sampler2D directRadiance;
layout(binding = 7) uniform sampler2D inscatter;
layout(location = 0) out vec4 outRadiance;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float d = texelFetch(gPosition, pixel, 0).w;
  vec3 surface = texelFetch(directRadiance, pixel, 0).rgb;
  vec4 scattered = texelFetch(inscatter, pixel, 0);
  vec3 L = surface * (exp(-sigmaT() * d) * clamp(scattered.a, 0.0, 1.0)) + scattered.rgb;
  outRadiance = vec4(L, 1.0);
}
