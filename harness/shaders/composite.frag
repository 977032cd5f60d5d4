#version 450 core
// L = L_surf * exp(-sigma_t d) * T_volumes + L_s, with T_volumes the camera ray's rgb transmittance
// through volume data (written by the method to draw buffer 1 of the in-scatter target).
#include "common.glsl"
layout(binding = VS_UNIT_DIRECT) uniform sampler2D directRadiance;
layout(binding = VS_UNIT_INSCATTER) uniform sampler2D inscatter;
#if VS_VOLUMES > 0
layout(binding = VS_UNIT_VOLUME_TRANSMITTANCE) uniform sampler2D volumeTransmittance;
#endif
layout(location = 0) out vec4 outRadiance;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float d = texelFetch(gPosition, pixel, 0).w;
  vec3 surface = texelFetch(directRadiance, pixel, 0).rgb;
  vec3 scattered = texelFetch(inscatter, pixel, 0).rgb;
#if VS_VOLUMES > 0
  vec3 through = clamp(texelFetch(volumeTransmittance, pixel, 0).rgb, 0.0, 1.0);
#else
  vec3 through = vec3(1.0);
#endif
  vec3 L = surface * exp(-sigmaT() * d) * through + scattered;
  outRadiance = vec4(L, 1.0);
}
