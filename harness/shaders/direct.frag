#version 450 core
// L_surf: Lambert surfaces lit by the light with shadow-map visibility (same for every method).
#include "common.glsl"
layout(location = 0) out vec4 outRadiance;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 n = texelFetch(gNormal, pixel, 0);
  if (n.w < 0.5) {
    outRadiance = vec4(0.0);
    return;
  }
  vec3 x = texelFetch(gPosition, pixel, 0).xyz;
  vec3 albedo = texelFetch(gAlbedo, pixel, 0).rgb;
  vec3 toLight = -lightTravelDir(x);
  float cosine = max(dot(n.xyz, toLight), 0.0);
  float visibility = cosine > 0.0 ? shadowVisibility(x + n.xyz * 1.5 * shadowTexelWorldSize(x)) : 0.0;
  vec3 L = albedo / PI * lightIncident(x) * cosine * visibility;
  outRadiance = vec4(L, 1.0);
}
