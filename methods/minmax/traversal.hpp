// 1D min-max mipmap over one rectified shadow-map row and its stackless traversal (Chen et al.
// 2011, Fig. 5). The GLSL version in shaders/integrate.frag follows this code step by step, so the
// unit tests of this CPU version test the algorithm the GPU runs.
//
// Layout (Ahnentafel): node 1 is the root, node k has children 2k and 2k+1, the d leaves are the
// nodes d..2d-1 (d a power of two). Node k on level l = floor(log2 k) covers the texels
// [(k - 2^l) * (d >> l), + (d >> l)).
// A point at camera-ray parameter beta over texel j is lit iff beta < S[j] (S stores the beta at
// which the light ray of texel j is blocked), so a node is all lit when beta < min and all in
// shadow when beta >= max.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

namespace vs::minmax {

struct MinMax {
  float lo, hi;
};

// Builds the coalesced tree (index 0 unused) from a row of d = 2^k texels.
std::vector<MinMax> buildMinMaxTree(const std::vector<float>& row);

struct TraversalOptions {
  bool upOneLevel = true;  // §3.5: climb at most one level after each step (else as far as possible)
  bool delayGamma = true;  // §3.5: emit merged lit runs at the next unlit node (else every lit node)
  // Start at the largest node that begins at the ray's first texel (the root for a ray from the
  // eye, g0 = 0) and descend, instead of climbing from the leaf one level per step.
  bool topStart = true;
};

// Where the GPU keeps node k of a row of d = 2^k >= 16 leaves (shaders/tree.glsl): the float index
// in its row of RGBA32F texels of the node's min (its max follows, except for a leaf: min = max).
inline int gpuTreeFloat(unsigned node, int d) {
  if (node >= unsigned(d)) return 4 * (d / 2) + int(node - unsigned(d));
  return 2 * int(node);
}

inline int treeLevel(unsigned node) {
  int level = 0;
  while (node >>= 1) ++level;
  return level;
}

// Calls emit(a, b) for the lit parts of [g0, g1] (texel units, 0 <= g0 < g1 <= d) of a camera ray
// with parameter beta, in increasing order. Returns the number of loop iterations.
template <typename Emit>
int traverseRow(const MinMax* tree, int d, float beta, float g0, float g1, TraversalOptions options, Emit emit) {
  g0 = std::clamp(g0, 0.0f, float(d));
  g1 = std::clamp(g1, 0.0f, float(d));
  if (!(g1 > g0)) return 0;
  auto climb = [&](unsigned& node) {
    if (options.upOneLevel) {
      if ((node & 1u) == 0u && node > 1u) node >>= 1;
    } else {
      while ((node & 1u) == 0u && node > 1u) node >>= 1;
    }
  };
  unsigned node = unsigned(d) + unsigned(std::min(int(std::floor(g0)), d - 1));
  if (options.topStart) {
    while ((node & 1u) == 0u && node > 1u) node >>= 1;
  } else {
    climb(node);
  }
  float runStart = -1.0f, runEnd = -1.0f;
  const int maxIterations = 4 * d + 64;  // a guard; a row needs at most ~2 log2(d) per run
  int iteration = 0;
  for (; iteration < maxIterations; ++iteration) {
    int level = treeLevel(node);
    float size = float(d >> level);
    float start = float(node - (1u << level)) * size, end = start + size;
    if (start >= g1) break;
    MinMax m = tree[node];
    bool lit = beta < m.lo;
    bool shadowed = !lit && (beta >= m.hi || node >= unsigned(d));  // leaves are never mixed
    if (!lit && !shadowed) {
      node *= 2u;  // mixed: descend to the left child
      continue;
    }
    if (lit) {
      float a = std::max(start, g0), b = std::min(end, g1);
      if (!options.delayGamma) {
        emit(a, b);
      } else {
        if (runStart < 0.0f) runStart = a;
        runEnd = b;
      }
    } else if (runStart >= 0.0f) {
      emit(runStart, runEnd);
      runStart = -1.0f;
    }
    if (end >= g1) break;
    node += 1u;
    if ((node & (node - 1u)) == 0u) break;  // wrapped past the last node of the level: row done
    climb(node);
  }
  if (runStart >= 0.0f) emit(runStart, runEnd);
  return iteration;
}

}  // namespace vs::minmax
