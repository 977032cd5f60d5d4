#version 450 core
// L_surf: Lambert surfaces lit by the light with shadow-map visibility (same for every method).
#include "common.glsl"
layout(location = 0) out vec4 outRadiance;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  outRadiance = vec4(surfaceRadiance(pixel, surfaceShadowVisibility(pixel)), 1.0);
}
