#version 450 core
// Integration (Chen et al. 2011, §3.3, Fig. 5): per camera ray, the stackless traversal of the
// min-max mipmap of its slice finds the lit gamma intervals; each lit interval adds
// sum_i B_i(beta) (P_i(b) - P_i(a)) with P_i the prefix sums of Gamma_i (or of Gamma_i T per slice).
// Same algorithm as vs::minmax::traverseRow (methods/minmax/traversal.hpp).
#include "common.glsl"
#include "epipolar.glsl"
layout(binding = 10) uniform sampler2D tree;            // RG32F, 2d x slices, nearest
layout(binding = 11) uniform sampler2D basisBeta;       // kGridSize x rank, linear
layout(binding = 12) uniform sampler2D gammaPrefix;     // (prefixRes + 1) x rank, linear
layout(binding = 13) uniform sampler2D texturedPrefix;  // (texRes + 1) x (slices * rank), linear
layout(location = 0) out vec4 outInscatter;

vec3 coefficient[kMaxRank];
int rowSlice = 0;

// Adds the lit interval [a, b] (texel units of the rectified row, or beyond for the unoccluded tail).
void addLitInterval(float a, float b) {
  float toGamma = ep.gammaInfo.x / ep.gammaInfo.z;
  float gammaA = a * toGamma, gammaB = b * toGamma;
  int rank = ep.counts.y;
  if (ep.flags.z != 0) {
    float res = float(ep.counts.w);
    float xa = (gammaA / ep.gammaInfo.y * res + 0.5) / (res + 1.0);
    float xb = (gammaB / ep.gammaInfo.y * res + 0.5) / (res + 1.0);
    float rows = float(ep.counts.x * rank);
    for (int i = 0; i < rank; ++i) {
      float y = (float(rowSlice * rank + i) + 0.5) / rows;
      coefficient[i] += textureLod(texturedPrefix, vec2(xb, y), 0.0).rgb - textureLod(texturedPrefix, vec2(xa, y), 0.0).rgb;
    }
  } else {
    float res = float(ep.counts.z);
    float xa = (gammaA / ep.gammaInfo.y * res + 0.5) / (res + 1.0);
    float xb = (gammaB / ep.gammaInfo.y * res + 0.5) / (res + 1.0);
    for (int i = 0; i < rank; ++i) {
      float y = (float(i) + 0.5) / float(rank);
      coefficient[i] += vec3(textureLod(gammaPrefix, vec2(xb, y), 0.0).r - textureLod(gammaPrefix, vec2(xa, y), 0.0).r);
    }
  }
}

int treeLevel(uint node) { return findMSB(node); }

void traverseRow(int d, float beta, float g0, float g1) {
  g0 = clamp(g0, 0.0, float(d));
  g1 = clamp(g1, 0.0, float(d));
  if (!(g1 > g0)) return;
  bool upOneLevel = ep.flags.x != 0, delayGamma = ep.flags.y != 0;
  uint node = uint(d) + uint(min(int(floor(g0)), d - 1));
  if (upOneLevel) {
    if ((node & 1u) == 0u && node > 1u) node >>= 1;
  } else {
    while ((node & 1u) == 0u && node > 1u) node >>= 1;
  }
  float runStart = -1.0, runEnd = -1.0;
  int maxIterations = 4 * d + 64;
  for (int iteration = 0; iteration < maxIterations; ++iteration) {
    int level = treeLevel(node);
    float size = float(d >> level);
    float start = float(node - (1u << level)) * size, end = start + size;
    if (start >= g1) break;
    vec2 m = texelFetch(tree, ivec2(int(node), rowSlice), 0).xy;
    bool lit = beta < m.x;
    bool shadowed = !lit && (beta >= m.y || node >= uint(d));
    if (!lit && !shadowed) {
      node *= 2u;
      continue;
    }
    if (lit) {
      float a = max(start, g0), b = min(end, g1);
      if (!delayGamma) {
        addLitInterval(a, b);
      } else {
        if (runStart < 0.0) runStart = a;
        runEnd = b;
      }
    } else if (runStart >= 0.0) {
      addLitInterval(runStart, runEnd);
      runStart = -1.0;
    }
    if (end >= g1) break;
    node += 1u;
    if ((node & (node - 1u)) == 0u) break;
    if (upOneLevel) {
      if ((node & 1u) == 0u && node > 1u) node >>= 1;
    } else {
      while ((node & 1u) == 0u && node > 1u) node >>= 1;
    }
  }
  if (runStart >= 0.0) addLitInterval(runStart, runEnd);
}

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
  int rank = ep.counts.y;
  for (int i = 0; i < rank; ++i) coefficient[i] = vec3(0.0);
  int d = int(ep.gammaInfo.z);
  float gammaEnd = min(gammaAlongRay(dist, beta, sinBeta), ep.gammaInfo.y);
  float toTexel = ep.gammaInfo.z / ep.gammaInfo.x;
  traverseRow(d, beta, 0.0, gammaEnd * toTexel);
  // Directional light: beyond gammaMap no light ray meets the scene, so the tail is lit.
  if (gammaEnd > ep.gammaInfo.x) addLitInterval(float(d), gammaEnd * toTexel);
  vec3 sum = vec3(0.0);
  float y = betaGridCoord(beta);
  for (int i = 0; i < rank; ++i)
    sum += textureLod(basisBeta, vec2(y, (float(i) + 0.5) / float(rank)), 0.0).r * coefficient[i];
  vec3 color = u.lightColor.rgb;
  vec3 result = max(color * sum / (ep.axis.w * sinBeta), vec3(0.0));
  if (any(isnan(result)) || any(isinf(result))) result = vec3(0.0);
  outInscatter = vec4(result, 1.0);
}
