#version 450 core
// Appends this crossing (distance from the light, transmittance) to the list of its light texel.
layout(early_fragment_tests) in;
#include "common.glsl"
in vec3 vPosition;
in vec3 vColor;
in vec2 vUv;
in vec3 vAlpha;
layout(location = 1) uniform vec3 lightPos;
layout(location = 2) uniform vec3 lightDir;
layout(location = 3) uniform int lightKind;  // 2 directional: distance along lightDir
layout(location = 4) uniform uint capacity;
layout(location = 5) uniform int face;
layout(binding = 0, r32ui) uniform coherent uimage2DArray heads;
layout(binding = 1, r32ui) uniform coherent uimage2DArray lengths;
struct Node {
  vec4 data;   // rgb transmittance of the crossing, w distance from the light
  uvec4 link;  // x next node (0xFFFFFFFF ends the list)
};
layout(std430, binding = VS_STORAGE_TRANSMITTANCE_NODES) writeonly buffer Nodes { Node nodes[]; };
layout(std430, binding = VS_STORAGE_TRANSMITTANCE_COUNTER) buffer TransmittanceCounter {
  uint appended;
  uint longest;  // the longest list: the lookups' trip count
};
void main() {
  float o = surfaceOpacity(vAlpha, vUv);
  if (o <= 0.0) return;  // a cut-out or fully transparent texel casts no shadow
  vec3 crossing = vec3(1.0) - o * (vec3(1.0) - vColor);
  uint index = atomicAdd(appended, 1u);
  ivec3 texel = ivec3(ivec2(gl_FragCoord.xy), face);
  atomicMax(longest, imageAtomicAdd(lengths, texel, 1u) + 1u);
  if (index >= capacity) return;  // counted: the map grows and is built again
  float dist = lightKind == 2 ? dot(vPosition, lightDir) : length(vPosition - lightPos);
  uint next = imageAtomicExchange(heads, texel, index);
  nodes[index].data = vec4(clamp(crossing, 0.0, 1.0), dist);
  nodes[index].link = uvec4(next, 0u, 0u, 0u);
}
