// The deep shadow map shared by its passes: DSM_KNOTS opacity knots per light texel, stored four
// per RGBA32F layer, followed by the ray's final opacity (Shook: RGB = the 10/50/90 % depths, A =
// the final opacity). Depths are distances from the light (directional: along its direction).
// DSM_KNOTS, DSM_LAYERS and DSM_CHANNELS (1: the mean extinction's map, 3: one per colour
// channel) are defined by the method.
layout(std140, binding = 4) uniform DsmBlock {
  mat4 faceViewProj[6];
  mat4 faceInvViewProj[6];
  vec4 params;         // x resolution, y faces (1 or 6), z knots
  vec4 thresholds[4];  // opacity of knot k in thresholds[k / 4][k % 4]
  vec4 knotTaus[4];    // its optical depth -ln(1 - opacity), same layout
  vec4 channelRatio;   // DSM_CHANNELS 1: each colour channel's sigma_t over the mean (T_c = T^ratio_c)
} dsm;
layout(binding = 10) uniform sampler2DArray dsmKnots;  // layer = (face * DSM_CHANNELS + channel) * DSM_LAYERS + j

#if DSM_FACES == 1
mat4 faceViewProj(int face) { return dsm.faceViewProj[0]; }
#else
mat4 faceViewProj(int face) { return dsm.faceViewProj[face]; }
#endif

float knotThreshold(int k) { return dsm.thresholds[k >> 2][k & 3]; }

// What is interpolated between knots (DSM_SEGMENTS): 0 opacity (the paper, Lokovic and Veach:
// piecewise-linear visibility), 1 optical depth (piecewise-exponential visibility, exact in a
// homogeneous stretch). knotValue/finalValue map a knot's and the final opacity there, and
// valueOpacity maps back.
#if DSM_SEGMENTS == 1
float knotValue(int k) { return dsm.knotTaus[k >> 2][k & 3]; }
float finalValue(float final) { return -log(max(1.0 - final, 1e-30)); }
float valueOpacity(float v) { return 1.0 - exp(-v); }
#else
float knotValue(int k) { return knotThreshold(k); }
float finalValue(float final) { return final; }
float valueOpacity(float v) { return v; }
#endif
// Value of knot k on a ray whose final value is `last`: a fixed threshold (the paper), or with
// DSM_RELATIVE a fixed fraction of the final value, so that thin rays use every knot too.
#if DSM_RELATIVE == 1
float knotAt(int k, float last) { return knotThreshold(k) * last; }
#else
float knotAt(int k, float last) { return knotValue(k); }
#endif

// Distance of x from the light along the light's rays.
float lightDepth(vec3 x) {
  return lightType() == LIGHT_DIRECTIONAL ? dot(x, u.lightDir.xyz) : length(x - u.lightPos.xyz);
}

// Light ray through x: origin and unit direction (depth of origin + t is the depth at parameter t).
// Light rays from a directional light start infinitely far: their parameters may be negative.
float lightRayStart() { return lightType() == LIGHT_DIRECTIONAL ? -3.0e38 : 0.0; }

void lightRayThrough(vec3 x, out vec3 origin, out vec3 dir) {
  if (lightType() == LIGHT_DIRECTIONAL) {
    dir = u.lightDir.xyz;
    origin = x - dir * dot(x, dir);  // depth 0
  } else {
    origin = u.lightPos.xyz;
    vec3 d = x - origin;
    float len = length(d);
    dir = len > 1e-20 ? d / len : u.lightDir.xyz;
  }
}

// [entry, exit] ray parameters (>= tMin) of the ray (origin, dir) through the union of the volume
// boxes (entry > exit when it misses them).
vec2 volumeSpan(vec3 origin, vec3 dir, float tMinRay) {
  vec2 span = vec2(3.0e38, -3.0e38);
  vec3 inv = 1.0 / mix(dir, vec3(1e-30), lessThan(abs(dir), vec3(1e-30)));
  for (int i = 0; i < VS_VOLUMES; ++i) {
    vec3 tLo = (vol.boxLo[i].xyz - origin) * inv, tHi = (vol.boxHi[i].xyz - origin) * inv;
    vec3 tMin = min(tLo, tHi), tMax = max(tLo, tHi);
    float t0 = max(max(tMin.x, tMin.y), max(tMin.z, tMinRay));
    float t1 = min(min(tMax.x, tMax.y), tMax.z);
    if (t1 > t0) span = vec2(min(span.x, t0), max(span.y, t1));
  }
  return span;
}

// DSM face holding x (the major axis around the light for six faces). DSM_FACES is the method's
// compile-time count, so that one view reads its matrix without a per-lane index.
int dsmFace(vec3 x) {
#if DSM_FACES == 1
  return 0;
#endif
  vec3 d = x - u.lightPos.xyz;
  vec3 a = abs(d);
  int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return 2 * axis + (d[axis] < 0.0 ? 1 : 0);
}

// Layer j of one map (plane = face * DSM_CHANNELS + channel) at a texel (DSM_FILTER 0), or
// filtered by the hardware at uv (DSM_FILTER 1: knot depths and final opacity interpolated
// bilinearly, one lookup instead of four).
vec4 dsmLayer(ivec2 texel, vec2 uv, int plane, int j) {
#if DSM_FILTER == 1
  return textureLod(dsmKnots, vec3(uv, float(plane * DSM_LAYERS + j)), 0.0);
#else
  return texelFetch(dsmKnots, ivec3(texel, plane * DSM_LAYERS + j), 0);
#endif
}

// Opacity at depth z of one texel's visibility function, through (entry, 0),
// (knot k, min(threshold k, final)), (exit, final), each segment linear in opacity or in optical
// depth (DSM_SEGMENTS); a knot the ray never crossed sits at the exit.
#if DSM_KNOTS == 3
// The paper's layout in straight-line code (no local arrays: they cost llvmpipe a memory round trip).
float texelOpacity(ivec2 texel, vec2 uv, int plane, float z, float entry, float exit) {
  vec4 v = dsmLayer(texel, uv, plane, 0);
  float final = v.w;
  if (final <= 0.0 || z <= entry) return 0.0;
  float d0 = max(v.x, entry), d1 = max(v.y, d0), d2 = max(v.z, d1), d3 = max(exit, d2);
  float last = finalValue(final);
  vec3 a = min(vec3(knotAt(0, last), knotAt(1, last), knotAt(2, last)), vec3(last));
  float lo = entry, hi = d0, aLo = 0.0, aHi = a.x;
  if (z > d0) { lo = d0; hi = d1; aLo = a.x; aHi = a.y; }
  if (z > d1) { lo = d1; hi = d2; aLo = a.y; aHi = a.z; }
  if (z > d2) { lo = d2; hi = d3; aLo = a.z; aHi = last; }
  if (z > d3) return final;
  return valueOpacity(mix(aLo, aHi, clamp((z - lo) / max(hi - lo, 1e-20), 0.0, 1.0)));
}
#else
float texelOpacity(ivec2 texel, vec2 uv, int plane, float z, float entry, float exit) {
  float values[DSM_LAYERS * 4];
  for (int j = 0; j < DSM_LAYERS; ++j) {
    vec4 v = dsmLayer(texel, uv, plane, j);
    values[4 * j] = v.x;
    values[4 * j + 1] = v.y;
    values[4 * j + 2] = v.z;
    values[4 * j + 3] = v.w;
  }
  float final = values[DSM_KNOTS];
  if (final <= 0.0 || z <= entry) return 0.0;
  float last = finalValue(final);
  float prevDepth = entry, prevValue = 0.0, result = last;
  bool found = false;
  for (int k = 0; k <= DSM_KNOTS; ++k) {
    float depth = k < DSM_KNOTS ? max(values[k], prevDepth) : max(exit, prevDepth);
    float value = k < DSM_KNOTS ? min(knotAt(k, last), last) : last;
    if (!found && z <= depth) {
      float w = clamp((z - prevDepth) / max(depth - prevDepth, 1e-20), 0.0, 1.0);
      result = mix(prevValue, value, w);
      found = true;
    }
    prevDepth = depth;
    prevValue = value;
  }
  return found ? valueOpacity(result) : final;
}
#endif

// Opacity at depth z of one texel's visibility function, or (finalOnly) its final opacity alone.
float texelValue(ivec2 texel, vec2 uv, int plane, float z, float entry, float exit, bool finalOnly) {
  if (finalOnly) return dsmLayer(texel, uv, plane, DSM_KNOTS / 4)[DSM_KNOTS % 4];
  return texelOpacity(texel, uv, plane, z, entry, exit);
}

// Opacity at depth z of one map (plane), bilinear between the four nearest texels' visibility
// functions, or from one hardware-filtered lookup (DSM_FILTER 1).
float mapOpacity(vec2 st, float size, int plane, float z, float entry, float exit, bool finalOnly) {
#if DSM_FILTER == 1
  return texelValue(ivec2(0), (st + 0.5) / size, plane, z, entry, exit, finalOnly);
#else
  vec2 f = fract(st);
  ivec2 t0 = clamp(ivec2(floor(st)), ivec2(0), ivec2(int(size) - 1));
  ivec2 t1 = min(t0 + 1, ivec2(int(size) - 1));
  float a00 = texelValue(t0, vec2(0.0), plane, z, entry, exit, finalOnly);
  float a10 = texelValue(ivec2(t1.x, t0.y), vec2(0.0), plane, z, entry, exit, finalOnly);
  float a01 = texelValue(ivec2(t0.x, t1.y), vec2(0.0), plane, z, entry, exit, finalOnly);
  float a11 = texelValue(t1, vec2(0.0), plane, z, entry, exit, finalOnly);
  return mix(mix(a00, a10, f.x), mix(a01, a11, f.x), f.y);
#endif
}

// Transmittance (rgb) of the volume data from the light to x: per colour channel from its own map
// (DSM_CHANNELS 3), or the mean extinction's transmittance T raised to each channel's ratio.
// `outside` (always a constant, so the compiler keeps one side): x lies outside the only volume
// box, so along its light ray it is in front of the volume (1) or behind it (the final opacity),
// and no knots are evaluated: with 8 or 16 knots that lookup is most of a haze sample's cost.
vec3 dsmTransmittanceAt(vec3 x, bool outside) {
  int face = dsmFace(x);
  vec4 p = faceViewProj(face) * vec4(x, 1.0);
  if (p.w <= 1e-20) return vec3(1.0);
  float size = dsm.params.x;
  vec2 st = (p.xy / p.w * 0.5 + 0.5) * size - 0.5;
  if (any(lessThan(st, vec2(-0.5))) || any(greaterThan(st, vec2(size - 0.5)))) return vec3(1.0);
  vec3 origin, dir;
  lightRayThrough(x, origin, dir);
  vec2 span = volumeSpan(origin, dir, lightRayStart());
  if (span.x >= span.y) return vec3(1.0);
  float z = lightDepth(x);
  float base = lightType() == LIGHT_DIRECTIONAL ? dot(origin, dir) : 0.0;
  float entry = base + span.x, exit = base + span.y;
  if (outside && z <= 0.5 * (entry + exit)) return vec3(1.0);
#if DSM_CHANNELS == 3
  int plane = face * 3;
  vec3 a = vec3(mapOpacity(st, size, plane, z, entry, exit, outside),
                mapOpacity(st, size, plane + 1, z, entry, exit, outside),
                mapOpacity(st, size, plane + 2, z, entry, exit, outside));
  return clamp(1.0 - a, 0.0, 1.0);
#else
  float t = clamp(1.0 - mapOpacity(st, size, face, z, entry, exit, outside), 0.0, 1.0);
#if DSM_GREY
  return vec3(t);  // volumes of grey extinction: every ratio is 1
#else
  return exp(dsm.channelRatio.rgb * log(max(t, 1e-30)));
#endif
#endif
}

vec3 dsmTransmittance(vec3 x) { return dsmTransmittanceAt(x, false); }

// A point outside every volume box (the camera ray's haze samples).
vec3 dsmHazeTransmittance(vec3 x) { return dsmTransmittanceAt(x, VS_VOLUMES == 1); }
