// The slicemap seen from the lookups: which column and slice a point falls in, and the light's
// transmittance there from the bits set in front of it. Mirrors SlicemapUniforms (slicemap.cpp).
// Defines from the method: SLICEMAP_CLASSES, SLICEMAP_TARGETS, SLICEMAP_LOCAL, SLICEMAP_PREFIX,
// SLICEMAP_OPAQUE_IN_SLICES, SLICEMAP_CUBE, SLICEMAP_PACKED, SLICEMAP_CLASS_WORDS, SLICEMAP_GREY (every
// class's transmittance is grey: one channel is counted and exponentiated).
layout(std140, binding = 4) uniform SlicemapBlock {
  mat4 faceViewProj[6];
  vec4 params;  // resolution, faces, slices, classes
  vec4 classRange[4];  // per class, uniform slicing: near, far, slices / (far - near)
  vec4 classTransmittance[4];     // rgb
  vec4 classLog2Transmittance[4];  // rgb: log2 of one crossing (-100 for 0)
  vec4 classBin[4];   // x alpha bin (-1: constant transmittance), y bins, z minimum opacity
  vec4 classTint[4];  // rgb: the alpha bin's transmittance colour
} slicemap;
// Point lights (SLICEMAP_CUBE): cube-map arrays looked up by direction from the light, layer
// class * targets + target (near/far: class); otherwise 2D arrays of one view.
#if SLICEMAP_CUBE
layout(binding = 10) uniform usamplerCubeArray slicemapBits;
layout(binding = 11) uniform samplerCubeArray slicemapNearFar;  // local slicing: near, -far per column
layout(binding = 12) uniform usamplerCubeArray slicemapPrefix;  // bits in the column's words before each word
#else
layout(binding = 10) uniform usampler2DArray slicemapBits;
layout(binding = 11) uniform sampler2DArray slicemapNearFar;
layout(binding = 12) uniform usampler2DArray slicemapPrefix;
#endif

// Distance from a point or spot light; depth along the light's direction for a directional light.
float slicemapDepth(vec3 x) {
  return lightType() == LIGHT_DIRECTIONAL ? dot(x, u.lightDir.xyz) : length(x - u.lightPos.xyz);
}

// The column a point falls in: its direction from the light (cube) or its texel (one view).
struct Column {
  vec3 dir;
  ivec2 texel;
  bool inside;
};

Column slicemapColumn(vec3 x) {
  Column c;
  c.dir = x - u.lightPos.xyz;
  c.texel = ivec2(0);
  c.inside = true;
#if !SLICEMAP_CUBE
  vec4 p = slicemap.faceViewProj[0] * vec4(x, 1.0);
  vec2 st = p.xy / max(p.w, 1e-20) * 0.5 + 0.5;
  c.inside = p.w > 1e-20 && all(greaterThanEqual(st, vec2(0.0))) && all(lessThan(st, vec2(1.0)));
  int res = int(slicemap.params.x);
  c.texel = clamp(ivec2(st * float(res)), ivec2(0), ivec2(res - 1));
#endif
  return c;
}

#if SLICEMAP_CUBE
#define SLICEMAP_FETCH(tex, column, layer) texture(tex, vec4((column).dir, float(layer)))
#else
#define SLICEMAP_FETCH(tex, column, layer) texelFetch(tex, ivec3((column).texel, (layer)), 0)
#endif

// Slice coordinate in [0, slices] of depth d in the column of class `cls` (negative before its
// range, above `slices` behind it).
float sliceCoordinate(Column column, int cls, float d) {
#if SLICEMAP_LOCAL
  vec2 nf = SLICEMAP_FETCH(slicemapNearFar, column, cls).xy;
  return (d - nf.x) / max(-nf.y - nf.x, 1e-30) * slicemap.params.z;
#else
  return (d - slicemap.classRange[cls].x) * slicemap.classRange[cls].z;
#endif
}

#ifndef NEAR_FAR_PASS
#if SLICEMAP_PREFIX
// Bits set in cells 0 .. slice-1 of a column whose words start at `layer`, from two fetches
// whatever the number of targets: the word holding the last cell in front, and the bits in the
// words before it.
int bitsInFront(Column column, int layer, int slice) {
  int word = min(slice >> 5, 4 * SLICEMAP_TARGETS - 1);
  int bits = clamp(slice - 32 * word, 0, 32);
  int at = layer + (word >> 2);
  uint w = SLICEMAP_FETCH(slicemapBits, column, at)[word & 3];
  uint before = SLICEMAP_FETCH(slicemapPrefix, column, at)[word & 3];
  uint mask = bits >= 32 ? 0xFFFFFFFFu : (1u << uint(bits)) - 1u;
  return int(before) + bitCount(w & mask);
}
#endif

// A column as the scan lookups see it: every target of every class slot, and (local slicing) each
// class's near/far, fetched once so that several march samples can share them.
#if SLICEMAP_CLASSES > 0
#define SLICEMAP_LAYERS (SLICEMAP_TARGETS * (SLICEMAP_PACKED != 0 ? 1 : SLICEMAP_CLASSES))
struct ColumnWords {
  uvec4 w[SLICEMAP_LAYERS];
  vec2 nearFar[SLICEMAP_CLASSES];
  bool inside;
};

ColumnWords fetchColumn(Column column) {
  ColumnWords c;
  for (int k = 0; k < SLICEMAP_LAYERS; ++k) c.w[k] = SLICEMAP_FETCH(slicemapBits, column, k);
  for (int cls = 0; cls < SLICEMAP_CLASSES; ++cls) {
#if SLICEMAP_LOCAL
    vec2 nf = SLICEMAP_FETCH(slicemapNearFar, column, cls).xy;
    c.nearFar[cls] = vec2(nf.x, slicemap.params.z / max(-nf.y - nf.x, 1e-30));
#else
    c.nearFar[cls] = slicemap.classRange[cls].xz;
#endif
  }
  c.inside = column.inside;
  return c;
}
#endif

// log2 of the transmittance: float when every class is grey (one channel counted), else rgb.
#if SLICEMAP_GREY
#define SLICEMAP_CHANNELS float
#define SLICEMAP_LOG2T(c) slicemap.classLog2Transmittance[c].r
#else
#define SLICEMAP_CHANNELS vec3
#define SLICEMAP_LOG2T(c) slicemap.classLog2Transmittance[c].rgb
#endif

#if SLICEMAP_CLASSES > 0
// Transmittance at light depth `depth` in a fetched column: per colour class t^n with n the class's
// bits in front of the depth's slice, summed in log2 and exponentiated once. `biasSlices` moves
// the lookup towards the light.
vec3 columnTransmittance(ColumnWords c, float depth, float biasSlices) {
  float slices = slicemap.params.z;
  int slice[SLICEMAP_CLASSES];
  for (int cls = 0; cls < SLICEMAP_CLASSES; ++cls) {
    float coord = (depth - c.nearFar[cls].x) * c.nearFar[cls].y - biasSlices;
    slice[cls] = coord <= 0.0 ? 0 : (coord >= slices ? int(slices) : int(coord));
  }
  SLICEMAP_CHANNELS opticalDepth = SLICEMAP_CHANNELS(0.0);
#if SLICEMAP_PACKED
  // Every class's words in the same targets: each word is masked and counted once, for the class
  // that owns it (word j: class j / CLASS_WORDS, known at compile time after unrolling).
  for (int j = 0; j < 4 * SLICEMAP_TARGETS; ++j) {
    int cls = j / SLICEMAP_CLASS_WORDS;
    if (cls >= SLICEMAP_CLASSES) break;
    int bits = clamp(slice[cls] - 32 * (j - cls * SLICEMAP_CLASS_WORDS), 0, 32);
    opticalDepth += float(bitCount(bitfieldExtract(c.w[j >> 2][j & 3], 0, bits))) * SLICEMAP_LOG2T(cls);
  }
#else
  // The paper's count: every word of the class's targets, masked to the cells in front.
  for (int cls = 0; cls < SLICEMAP_CLASSES; ++cls) {
    int n = 0;
    for (int k = 0; k < SLICEMAP_TARGETS; ++k) {
      uvec4 w = c.w[cls * SLICEMAP_TARGETS + k];
      ivec4 bits = clamp(ivec4(slice[cls]) - (ivec4(0, 32, 64, 96) + 128 * k), ivec4(0), ivec4(32));
      uvec4 mask = mix((uvec4(1u) << uvec4(min(bits, ivec4(31)))) - 1u, uvec4(0xFFFFFFFFu), equal(bits, ivec4(32)));
      ivec4 b = bitCount(w & mask);
      n += b.x + b.y + b.z + b.w;
    }
    opticalDepth += float(n) * SLICEMAP_LOG2T(cls);
  }
#endif
  if (!c.inside) opticalDepth = SLICEMAP_CHANNELS(0.0);
  return vec3(exp2(max(opticalDepth, SLICEMAP_CHANNELS(-126.0))));
}
#endif

// Transmittance of the voxelized occluders between the light and x. `biasSlices` moves the
// lookup towards the light (surfaces: their own cell), and `biasDepth` the depth (world units).
// 1 outside the light's views.
vec3 slicemapTransmittance(vec3 x, float biasSlices, float biasDepth) {
#if SLICEMAP_CLASSES == 0
  return vec3(1.0);
#else
  Column column = slicemapColumn(x);
  float depth = slicemapDepth(x) - biasDepth;
#if SLICEMAP_PREFIX
  // Prefix Counts: two fetches per class whatever the number of targets.
  float slices = slicemap.params.z;
  SLICEMAP_CHANNELS opticalDepth = SLICEMAP_CHANNELS(0.0);
  for (int c = 0; c < SLICEMAP_CLASSES; ++c) {
    float coord = sliceCoordinate(column, c, depth) - biasSlices;
    int slice = coord <= 0.0 ? 0 : (coord >= slices ? int(slices) : int(coord));
    int n = column.inside ? bitsInFront(column, c * SLICEMAP_TARGETS, slice) : 0;
    opticalDepth += float(n) * SLICEMAP_LOG2T(c);
  }
  return vec3(exp2(max(opticalDepth, SLICEMAP_CHANNELS(-126.0))));
#else
  return columnTransmittance(fetchColumn(column), depth, biasSlices);
#endif
#endif
}

// Visibility of the light from x: the shared shadow map for opaque occluders (the paper's
// transmittance shadow maps) unless they are voxelized too, times the slicemaps' transmittance.
vec3 slicemapVisibility(vec3 x) {
#if SLICEMAP_OPAQUE_IN_SLICES
  return slicemapTransmittance(x, 0.0, 0.0);
#else
  float v = shadowVisibility(x);
  return v > 0.0 ? v * slicemapTransmittance(x, 0.0, 0.0) : vec3(0.0);
#endif
}
#endif
