#version 450 core
// Per-VPL wrapper (harness/runner.cpp): one virtual point light's L_s, added into the sum by blending.
layout(binding = VS_UNIT_INSCATTER) uniform sampler2D inscatter;
layout(location = 0) out vec4 outSum;
void main() { outSum = texelFetch(inscatter, ivec2(gl_FragCoord.xy), 0); }
