#version 450 core
// Shadow map of semi-transparent occluders alpha-tested (SharedPasses::setAlphaTest): a texel blocks
// the light where the surface's opacity is at least the threshold.
#include "common.glsl"
in vec2 vUv;
flat in vec3 vAlpha;
layout(location = 1) uniform float alphaTest;
void main() {
  if (surfaceOpacity(vAlpha, vUv) < alphaTest) discard;
}
