#version 450 core
// L = L_surf * exp(-sigma_t d) + L_s.
#include "common.glsl"
layout(binding = 6) uniform sampler2D directRadiance;
layout(binding = 7) uniform sampler2D inscatter;
layout(location = 0) out vec4 outRadiance;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float d = texelFetch(gPosition, pixel, 0).w;
  vec3 surface = texelFetch(directRadiance, pixel, 0).rgb;
  vec3 scattered = texelFetch(inscatter, pixel, 0).rgb;
  vec3 L = surface * exp(-sigmaT() * d) + scattered;
  outRadiance = vec4(L, 1.0);
}
