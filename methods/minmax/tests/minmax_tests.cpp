// minmax: the traversal against a brute-force scan, accuracy against raymarch, hard cases.
#include <cmath>
#include <cstdio>
#include <random>

#include "gl_test.hpp"
#include "harness/metrics.hpp"
#include "minmax/epipolar.hpp"
#include "minmax/traversal.hpp"

namespace vs::testing {
namespace {

using minmax::MinMax;
using Segments = std::vector<std::pair<float, float>>;

void appendMerged(Segments& out, float a, float b) {
  if (!out.empty() && out.back().second == a) out.back().second = b;
  else out.emplace_back(a, b);
}

Segments bruteForce(const std::vector<float>& row, float beta, float g0, float g1) {
  Segments out;
  int d = int(row.size());
  g0 = std::clamp(g0, 0.0f, float(d));
  g1 = std::clamp(g1, 0.0f, float(d));
  if (!(g1 > g0)) return out;
  for (int j = int(std::floor(g0)); j < d && float(j) < g1; ++j)
    if (beta < row[j]) appendMerged(out, std::max(float(j), g0), std::min(float(j + 1), g1));
  return out;
}

TEST(MinmaxTraversal, MatchesBruteForceOnRandomRows) {
  std::mt19937 rng(12345);
  int cases = 0;
  for (int log2d = 0; log2d <= 9; ++log2d) {
    int d = 1 << log2d;
    for (int rowIndex = 0; rowIndex < 60; ++rowIndex) {
      // Few distinct values so that ties between beta and stored values are common.
      int levels = 1 + int(rng() % 6);
      std::vector<float> row(d);
      for (float& v : row) v = float(rng() % levels) * 0.5f;
      if (rowIndex % 7 == 0) std::fill(row.begin(), row.end(), 1.0f);  // constant rows
      auto tree = minmax::buildMinMaxTree(row);
      for (int q = 0; q < 40; ++q) {
        float beta = q % 3 == 0 ? float(rng() % (levels + 1)) * 0.5f : std::uniform_real_distribution<float>(-0.2f, 3.2f)(rng);
        auto pick = [&]() -> float {
          switch (rng() % 4) {
            case 0: return float(rng() % (d + 1));                                         // texel edges, row ends
            case 1: return std::uniform_real_distribution<float>(0.0f, float(d))(rng);     // anywhere
            case 2: return rng() % 2 ? 0.0f : float(d);                                    // ends of the row
            default: return std::uniform_real_distribution<float>(-1.0f, float(d) + 1.0f)(rng);  // outside
          }
        };
        float g0 = pick(), g1 = pick();
        if (g1 < g0) std::swap(g0, g1);
        Segments expected = bruteForce(row, beta, g0, g1);
        for (int mode = 0; mode < 4; ++mode) {
          minmax::TraversalOptions options{(mode & 1) != 0, (mode & 2) != 0};
          Segments got;
          minmax::traverseRow(tree.data(), d, beta, g0, g1, options, [&](float a, float b) { appendMerged(got, a, b); });
          ASSERT_EQ(got, expected) << "d " << d << " beta " << beta << " [" << g0 << ", " << g1 << "] mode " << mode;
          ++cases;
        }
      }
    }
  }
  std::printf("%d traversals agree with the brute-force scan\n", cases);
}

TEST(MinmaxTraversal, DelayedRunsNeedFewerEmitsAndOneLevelClimbsTerminate) {
  std::vector<float> row(256);
  for (int j = 0; j < 256; ++j) row[j] = (j / 16) % 2 ? 0.0f : 2.0f;  // 8 lit blocks of 16
  auto tree = minmax::buildMinMaxTree(row);
  int emitsDelayed = 0, emitsEager = 0;
  minmax::traverseRow(tree.data(), 256, 1.0f, 0.0f, 256.0f, {true, true}, [&](float, float) { ++emitsDelayed; });
  minmax::traverseRow(tree.data(), 256, 1.0f, 0.0f, 256.0f, {true, false}, [&](float, float) { ++emitsEager; });
  EXPECT_EQ(emitsDelayed, 8);
  EXPECT_GE(emitsEager, 8);
  int iterations = minmax::traverseRow(tree.data(), 256, 1.0f, 0.0f, 256.0f, {true, true}, [](float, float) {});
  EXPECT_LT(iterations, 200);
}

class MinmaxTest : public GlTest {};

TEST_F(MinmaxTest, RendersSpheres) {
  Scene scene = loadScene("spheres");
  MethodRun ref = renderScene(scene, "raymarch:steps=1024:sm=512", 96, 72);
  MethodRun run = renderScene(scene, "minmax:sm=512", 96, 72);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  ErrorMetrics e = compareImages(run.inscatter, ref.inscatter);
  std::printf("rmse %.4g relmse %.4g\n", e.rmse, e.relmse);
}

}  // namespace
}  // namespace vs::testing
