#version 450 core
// Integration (Chen et al. 2011, §3.3, Fig. 5): per camera ray, the stackless traversal of the
// min-max mipmap of its slice finds the lit gamma intervals; each lit interval adds
// sum_i B_i(beta) (P_i(b) - P_i(a)) with P_i the prefix sums of Gamma_i (or of Gamma_i T per slice).
// Same algorithm as vs::minmax::traverseRow (methods/minmax/traversal.hpp).
#include "common.glsl"
#include "epipolar.glsl"
#include "work_counters.glsl"
#include "tree.glsl"
// Built per variant (minmax.cpp): MINMAX_RANK, MINMAX_TEXTURED, MINMAX_DELAY_GAMMA,
// MINMAX_UP_ONE_LEVEL and MINMAX_TOP_START are compile-time constants, since llvmpipe runs both
// sides of every branch and every iteration of a loop bounded by a uniform under a mask.
#define kRankGroups ((MINMAX_RANK + 3) / 4)
layout(binding = 10) uniform sampler2D tree;            // RGBA32F, 3d/4 x slices (tree.glsl), nearest
layout(binding = 11) uniform sampler2D basisBeta;       // RGBA32F, kGridSize x kRankGroups (4 ranks per texel), linear
layout(binding = 12) uniform sampler2D gammaPrefix;     // RGBA32F, (prefixRes + 1) x kRankGroups, linear
layout(binding = 13) uniform sampler2D texturedPrefix;  // (texRes + 1) x (slices * rank), linear
layout(location = 0) out vec4 outInscatter;

#if MINMAX_TEXTURED
vec3 coefficient[MINMAX_RANK];
#else
vec4 coefficient[kRankGroups];  // four ranks per vec4: the light is grey along each light ray
#endif
int rowSlice = 0;
uint workIterations = 0u, workRuns = 0u;  // traversal iterations and lit runs (work counters)

// Adds sign * P_i(x) to every coefficient, x in texel units of the rectified row (or beyond it for
// the unoccluded tail). A lit interval [a, b] is P(b) - P(a): the traversal adds its two ends as
// events, so that one lookup per event serves all ranks (four ranks per fetch without a texture).
void addPrefix(float sign, float x) {
  float gamma = x * (ep.gammaInfo.x / ep.gammaInfo.z);
#if MINMAX_TEXTURED
  float res = float(ep.counts.w);
  float xc = (gamma / ep.gammaInfo.y * res + 0.5) / (res + 1.0);
  float rows = float(ep.counts.x * MINMAX_RANK);
  for (int i = 0; i < MINMAX_RANK; ++i)
    coefficient[i] += sign * textureLod(texturedPrefix, vec2(xc, (float(rowSlice * MINMAX_RANK + i) + 0.5) / rows), 0.0).rgb;
#else
  float res = float(ep.counts.z);
  float xc = (gamma / ep.gammaInfo.y * res + 0.5) / (res + 1.0);
  for (int g = 0; g < kRankGroups; ++g)
    coefficient[g] += sign * textureLod(gammaPrefix, vec2(xc, (float(g) + 0.5) / float(kRankGroups)), 0.0);
#endif
}

int treeLevel(uint node) { return findMSB(node); }

// (min, max) of node k of this pixel's row (one fetch; leaves have min = max).
vec2 treeNode(uint node, int d) {
  bool leaf = node >= uint(d);
  uint j = node - uint(d);
  vec4 t = texelFetch(tree, ivec2(leaf ? leafTexel(d, j) : innerTexel(node), rowSlice), 0);
  vec2 half_ = (leaf ? (j & 2u) != 0u : (node & 1u) != 0u) ? t.zw : t.xy;
  return leaf ? vec2((j & 1u) != 0u ? half_.y : half_.x) : half_;
}

// The next node after a step to the right: up while it is a left child's right sibling's parent
// (paper 3.5: one level per step with MINMAX_UP_ONE_LEVEL).
uint climb(uint node) {
#if MINMAX_UP_ONE_LEVEL
  if ((node & 1u) == 0u && node > 1u) node >>= 1;
#else
  while ((node & 1u) == 0u && node > 1u) node >>= 1;
#endif
  return node;
}

// The first node: the leaf of the ray's first texel, one level up (paper), or with MINMAX_TOP_START
// the largest node that begins there (the root for g0 = 0), from which the walk descends. On
// 384x288 at slices=512:rank=3:res=512 this cut the iterations per pixel on terrain 12.6 -> 7.7,
// room 26.9 -> 23.0, spheres 22.7 -> 19.9, and raised them on trees 68 -> 76 (high-frequency
// shadows right at the eye: the descent costs a level each).
uint firstNode(int d, float g0) {
  uint node = uint(d) + uint(min(int(floor(g0)), d - 1));
#if MINMAX_TOP_START
  while ((node & 1u) == 0u && node > 1u) node >>= 1;
  return node;
#else
  return climb(node);
#endif
}

#if MINMAX_DELAY_GAMMA
// The traversal in phases: each runs the stackless walk without any prefix lookup until the pixel
// meets its next event (a lit run starts or ends) or the row's end, and the phase's one event is
// added after it. llvmpipe runs a block under a branch for every pixel of a batch, so a lookup
// inside the walk cost every node visit; here it costs one per phase: Integration on room at
// 384x288 11.9 -> 8.2 ms at slices=128:rank=2:res=256, fence 54 -> 41 ms at slices=512:rank=3:res=512,
// the same images bit for bit (scripts/shader-ab, idiff).
struct Walk {
  uint node;
  bool inRun;
  float runEnd;
  bool done;
  float start, size;  // the node's texels, kept along the walk instead of a findMSB per step
};

void traverseRow(int d, float beta, float g0, float g1) {
  g0 = clamp(g0, 0.0, float(d));
  g1 = clamp(g1, 0.0, float(d));
  if (!(g1 > g0)) return;
  Walk w = Walk(firstNode(d, g0), false, 0.0, false, 0.0, 0.0);
  int level0 = treeLevel(w.node);
  w.size = float(d >> level0);
  w.start = float(w.node - (1u << level0)) * w.size;
  int budget = 4 * d + 64;
  while (!w.done) {
    float eventSign = 0.0, eventX = 0.0;
    for (; budget > 0; --budget) {
      ++workIterations;
      float start = w.start, end = start + w.size;
      if (start >= g1) {
        w.done = true;
        break;
      }
      vec2 m = treeNode(w.node, d);
      bool lit = beta < m.x;
      bool shadowed = !lit && (beta >= m.y || w.node >= uint(d));
      if (!lit && !shadowed) {
        w.node *= 2u;
        w.size *= 0.5;
        continue;
      }
      float a = max(start, g0), b = min(end, g1);
      // One event at most per node: a run starts (-P(a)) or ends (+P(end of the run)).
      eventSign = lit ? (w.inRun ? 0.0 : -1.0) : (w.inRun ? 1.0 : 0.0);
      eventX = lit ? a : w.runEnd;
      w.inRun = lit;
      if (lit) w.runEnd = b;
      bool last = end >= g1;
      w.node += 1u;
      w.start = end;
      last = last || (w.node & (w.node - 1u)) == 0u;
      if (!last) {  // a parent starts where its left child does
#if MINMAX_UP_ONE_LEVEL
        bool up = (w.node & 1u) == 0u && w.node > 1u;
        w.node = up ? w.node >> 1 : w.node;
        w.size *= up ? 2.0 : 1.0;
#else
        w.node = climb(w.node);
        w.size = float(d >> treeLevel(w.node));
#endif
      }
      w.done = last;
      if (eventSign != 0.0 || last) {
        --budget;
        break;
      }
    }
    if (budget <= 0) w.done = true;
    if (eventSign < 0.0) ++workRuns;
    if (eventSign != 0.0) addPrefix(eventSign, eventX);
  }
  if (w.inRun) addPrefix(1.0, w.runEnd);
}
#else
// Without delay_gamma (paper 3.5 off) every lit node adds both its ends.
void traverseRow(int d, float beta, float g0, float g1) {
  g0 = clamp(g0, 0.0, float(d));
  g1 = clamp(g1, 0.0, float(d));
  if (!(g1 > g0)) return;
  uint node = firstNode(d, g0);
  int maxIterations = 4 * d + 64;
  for (int iteration = 0; iteration < maxIterations; ++iteration) {
    ++workIterations;
    int level = treeLevel(node);
    float size = float(d >> level);
    float start = float(node - (1u << level)) * size, end = start + size;
    if (start >= g1) break;
    vec2 m = treeNode(node, d);
    bool lit = beta < m.x;
    bool shadowed = !lit && (beta >= m.y || node >= uint(d));
    if (!lit && !shadowed) {
      node *= 2u;
      continue;
    }
    float a = max(start, g0), b = min(end, g1);
    if (lit) {
      ++workRuns;
      addPrefix(1.0, b);
      addPrefix(-1.0, a);
    }
    if (end >= g1) break;
    node += 1u;
    if ((node & (node - 1u)) == 0u) break;
    node = climb(node);
  }
}
#endif

void main() {
  if (nearEpipole(gl_FragCoord.xy)) {  // the Near Epipole pass writes these pixels
    outInscatter = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  vec3 v;
  float dist;
  cameraRay(ivec2(gl_FragCoord.xy), v, dist);
  float beta, sinBeta;
  rayCoords(v, rowSlice, beta, sinBeta);
  if (sinBeta < 1e-7) {
    outInscatter = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
#if MINMAX_TEXTURED
  for (int i = 0; i < MINMAX_RANK; ++i) coefficient[i] = vec3(0.0);
#else
  for (int g = 0; g < kRankGroups; ++g) coefficient[g] = vec4(0.0);
#endif
  int d = int(ep.gammaInfo.z);
  float gammaEnd = min(gammaAlongRay(dist, beta, sinBeta), ep.gammaInfo.y);
  float toTexel = ep.gammaInfo.z / ep.gammaInfo.x;
  traverseRow(d, beta, 0.0, gammaEnd * toTexel);
  // Directional light: beyond gammaMap no light ray meets the scene, so the tail is lit.
  if (gammaEnd > ep.gammaInfo.x) {
    ++workRuns;
    addPrefix(1.0, gammaEnd * toTexel);
    addPrefix(-1.0, float(d));
  }
  vec3 sum = vec3(0.0);
  float y = betaGridCoord(beta);
#if MINMAX_TEXTURED
  for (int g = 0; g < kRankGroups; ++g) {
    vec4 basis = textureLod(basisBeta, vec2(y, (float(g) + 0.5) / float(kRankGroups)), 0.0);
    for (int j = 0; j < 4 && 4 * g + j < MINMAX_RANK; ++j) sum += basis[j] * coefficient[4 * g + j];
  }
#else
  for (int g = 0; g < kRankGroups; ++g)
    sum += vec3(dot(textureLod(basisBeta, vec2(y, (float(g) + 0.5) / float(kRankGroups)), 0.0), coefficient[g]));
#endif
  vec3 color = u.lightColor.rgb;
  vec3 result = max(color * sum / (ep.axis.w * sinBeta), vec3(0.0));
  if (any(isnan(result)) || any(isinf(result))) result = vec3(0.0);
  outInscatter = vec4(result, 1.0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  countWork(pixel, 0, 1u);
  countWork(pixel, 1, workIterations);
  countWork(pixel, 2, workRuns);
}
