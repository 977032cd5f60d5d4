// The slicemap seen from the lookups: which column and slice a point falls in, and the light's
// transmittance there from the bits set in front of it. Mirrors SlicemapUniforms (slicemap.cpp).
// Defines from the method: SLICEMAP_CLASSES, SLICEMAP_TARGETS, SLICEMAP_LOCAL, SLICEMAP_PREFIX,
// SLICEMAP_OPAQUE_IN_SLICES.
layout(std140, binding = 4) uniform SlicemapBlock {
  mat4 faceViewProj[6];
  vec4 params;  // resolution, faces, slices, classes
  vec4 range;   // uniform slicing: near, far
  vec4 classTransmittance[4];
} slicemap;
layout(binding = 10) uniform usampler2DArray slicemapBits;  // layer (face * classes + class) * targets + target
layout(binding = 11) uniform sampler2DArray slicemapNearFar;  // local slicing: near, -far per column (face * classes + class)
layout(binding = 12) uniform usampler2DArray slicemapPrefix;  // bits in the column's words before each word

// Distance from a point or spot light; depth along the light's direction for a directional light.
float slicemapDepth(vec3 x) {
  return lightType() == LIGHT_DIRECTIONAL ? dot(x, u.lightDir.xyz) : length(x - u.lightPos.xyz);
}

// Slice coordinate in [0, slices] of depth d in a column's range (negative before it, above
// `slices` behind it).
float sliceCoordinate(ivec2 texel, int column, float d) {
#if SLICEMAP_LOCAL
  vec2 nf = texelFetch(slicemapNearFar, ivec3(texel, column), 0).xy;
  vec2 range = vec2(nf.x, -nf.y);
#else
  vec2 range = slicemap.range.xy;
#endif
  return (d - range.x) / max(range.y - range.x, 1e-30) * slicemap.params.z;
}

#ifndef NEAR_FAR_PASS
// Bits set in cells 0 .. slice-1 of a column whose words start at `layer`.
int bitsInFront(ivec2 texel, int layer, int slice) {
#if SLICEMAP_PREFIX
  // Two fetches whatever the number of targets: the word holding the last cell in front, and the
  // bits in the words before it.
  int word = min(slice >> 5, 4 * SLICEMAP_TARGETS - 1);
  int bits = clamp(slice - 32 * word, 0, 32);
  ivec3 at = ivec3(texel, layer + (word >> 2));
  uint w = texelFetch(slicemapBits, at, 0)[word & 3];
  uint before = texelFetch(slicemapPrefix, at, 0)[word & 3];
  uint mask = bits >= 32 ? 0xFFFFFFFFu : (1u << uint(bits)) - 1u;
  return int(before) + bitCount(w & mask);
#else
  // The paper's count: every word of the column, masked to the cells in front.
  int n = 0;
  for (int k = 0; k < SLICEMAP_TARGETS; ++k) {
    uvec4 w = texelFetch(slicemapBits, ivec3(texel, layer + k), 0);
    ivec4 bits = clamp(ivec4(slice) - (ivec4(0, 32, 64, 96) + 128 * k), ivec4(0), ivec4(32));
    uvec4 mask = mix((uvec4(1u) << uvec4(min(bits, ivec4(31)))) - 1u, uvec4(0xFFFFFFFFu), equal(bits, ivec4(32)));
    ivec4 c = bitCount(w & mask);
    n += c.x + c.y + c.z + c.w;
  }
  return n;
#endif
}

// Transmittance of the voxelized occluders between the light and x: per colour class,
// t^n with n the class's bits in front of x's slice. `biasSlices` moves the lookup towards the
// light (surfaces: their own cell). 1 outside the light's views.
vec3 slicemapTransmittance(vec3 x, float biasSlices) {
  vec3 T = vec3(1.0);
#if SLICEMAP_CLASSES > 0
  int face = 0;
  if (slicemap.params.y > 1.5) {  // cube faces +x, -x, +y, -y, +z, -z
    vec3 d = x - u.lightPos.xyz;
    vec3 a = abs(d);
    int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    face = 2 * axis + (d[axis] < 0.0 ? 1 : 0);
  }
  vec4 p = slicemap.faceViewProj[face] * vec4(x, 1.0);
  vec2 st = p.xy / max(p.w, 1e-20) * 0.5 + 0.5;
  bool inside = p.w > 1e-20 && all(greaterThanEqual(st, vec2(0.0))) && all(lessThan(st, vec2(1.0)));
  int res = int(slicemap.params.x);
  ivec2 texel = clamp(ivec2(st * float(res)), ivec2(0), ivec2(res - 1));
  float depth = slicemapDepth(x);
  float slices = slicemap.params.z;
  for (int c = 0; c < SLICEMAP_CLASSES; ++c) {
    int column = face * SLICEMAP_CLASSES + c;
    float coord = sliceCoordinate(texel, column, depth) - biasSlices;
    int slice = coord <= 0.0 ? 0 : (coord >= slices ? int(slices) : int(coord));
    int n = inside ? bitsInFront(texel, column * SLICEMAP_TARGETS, slice) : 0;
    vec3 t = slicemap.classTransmittance[c].rgb;
    T *= n == 0 ? vec3(1.0) : exp2(float(n) * log2(max(t, vec3(1e-30))));
  }
#endif
  return T;
}

// Visibility of the light from x: the shared shadow map for opaque occluders (the paper's
// transmittance shadow maps) unless they are voxelized too, times the slicemaps' transmittance.
vec3 slicemapVisibility(vec3 x, float biasSlices) {
#if SLICEMAP_OPAQUE_IN_SLICES
  return slicemapTransmittance(x, biasSlices);
#else
  float v = shadowVisibility(x);
  return v > 0.0 ? v * slicemapTransmittance(x, biasSlices) : vec3(0.0);
#endif
}
#endif
