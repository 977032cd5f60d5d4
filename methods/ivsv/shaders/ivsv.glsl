// Shared by the ivsv shaders: the method's block, the virtual point lights with their epipolar
// frames, and the imperfect-shadow-map atlas (ivsv.cpp mirrors the layouts).
#include "methods/epipolar/shaders/epipolar_frame.glsl"

layout(std140, binding = 3) uniform IvsvBlock {
  ivec4 dims;       // VPL count, grid N (N_alpha = N_theta), ISM tiles per side, ISM tile texels
  ivec4 counts;     // points per VPL, gather steps, first VPL of this gather pass, VPLs in it
  vec4 tangent;     // the light's frame: tangent, bitangent, normal (xyz)
  vec4 bitangent;
  vec4 normal;      // w = ISM depth range (far)
  vec4 weight;      // rgb: intensity of one VPL (radiance x area / N x colour); w: 1 = jitter
} iv;

struct Vpl {
  vec4 position;  // xyz
  vec4 axis;      // unit, eye towards the VPL; w = distance from the eye
  vec4 e1;
  vec4 e2;
};
layout(std430, binding = 1) readonly buffer IvsvLights { Vpl vpls[]; };

const int kPhiBits = 128;  // one RGBA32UI texel per (alpha, theta) column of a VPL's grid

EpipolarFrame vplFrame(int k) {
  return EpipolarFrame(u.eye.xyz, vpls[k].axis.w, vpls[k].axis.xyz, vpls[k].e1.xyz, vpls[k].e2.xyz, false);
}

// Paraboloid map of the hemisphere the light faces: unit d with dot(d, normal) > 0 to the unit disk.
vec2 paraboloid(vec3 d) {
  float z = max(dot(d, iv.normal.xyz), 0.0);
  return vec2(dot(d, iv.tangent.xyz), dot(d, iv.bitangent.xyz)) / (1.0 + z);
}
// Atlas texel of VPL k's tile at paraboloid point p.
ivec2 ismTexel(int k, vec2 p) {
  int res = iv.dims.w;
  ivec2 tile = ivec2(k % iv.dims.z, k / iv.dims.z);
  ivec2 texel = clamp(ivec2((p * 0.5 + 0.5) * float(res)), ivec2(0), ivec2(res - 1));
  return tile * res + texel;
}
