// Tests for harness/bench/equal_error: speed-ups as per-round ratios, the equal-quality table's
// cells, and the brute-force matcher's step search on a small scene.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "harness/bench/equal_error.hpp"
#include "methods/registry.hpp"

namespace vs {
namespace {

TEST(EqualErrorTest, SpeedupsAreMediansOfPerRoundRatios) {
  // Round 2 was slow for both sides: the ratio of medians (30/10 = 3) is not the median of the
  // rounds' ratios (2, 2, 4 -> 2); only the latter cancels a slow round.
  Spread s = ratioSpread({20, 60, 40}, {10, 30, 10});
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.lo, 2.0);
  EXPECT_DOUBLE_EQ(s.hi, 4.0);
  // A round missing on either side, or with no time, is left out.
  s = ratioSpread({20, 60}, {10, 0, 5});
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.hi, 2.0);
  s = ratioSpread({}, {1});
  EXPECT_EQ(s.median, 0.0);
  EXPECT_EQ(spreadCell({12.34, 11.9, 13.0}), "12.3 [11.9–13.0]");
  EXPECT_EQ(speedupCell({4.2, 3.9, 4.51}), "4.20x [3.90–4.51]");
}

EqualQualityRow rowWith(std::vector<bool> reached, std::vector<double> medians, int cheapest) {
  EqualQualityRow row;
  row.method.ok = true;
  row.method.relmse = 1e-3;
  row.timing.methodMs = {10, 9, 11};
  for (size_t i = 0; i < reached.size(); ++i) {
    BaselineMatch m;
    m.spec = "raymarch:steps=" + std::to_string(10 * (i + 1));
    m.reached = reached[i];
    row.matches.push_back(m);
    row.timing.baselineMs.push_back({medians[i] * 10, medians[i] * 9, medians[i] * 11});
    row.timing.speedup.push_back({medians[i], medians[i] - 0.5, medians[i] + 0.5});
  }
  row.timing.cheapest = cheapest;
  return row;
}

TEST(EqualErrorTest, TableMarksTheStrongestBaselineAndLowerBounds) {
  std::vector<std::pair<std::string, EqualQualityRow>> rows = {
      {"a", rowWith({true, true}, {3.0, 2.0}, 1)}, {"b", rowWith({false}, {5.0}, 0)}};
  rows.push_back({"c", EqualQualityRow{}});  // a method that failed
  // Row d: a match that missed the error beside one that reached it keeps its line, untimed.
  EqualQualityRow d = rowWith({true, false}, {2.0, 0.0}, 0);
  d.timing.speedup[1] = Spread{};
  d.timing.baselineMs[1] = Spread{};
  rows.push_back({"d", d});
  const std::string table = equalQualityTable(rows, "scene");
  EXPECT_NE(table.find("| scene | L_s relMSE |"), std::string::npos) << table;
  // Row a: the uniform match plain, the cheaper one bold; the second line leaves the method's cells empty.
  EXPECT_NE(table.find("| a | 1.00e-03 | 10.0 [9.0–11.0] | `raymarch:steps=10` |"), std::string::npos) << table;
  EXPECT_NE(table.find("| 3.00x [2.50–3.50] |"), std::string::npos) << table;
  EXPECT_NE(table.find("| | | | `raymarch:steps=20` |"), std::string::npos) << table;
  EXPECT_NE(table.find("| **2.00x** [1.50–2.50] |"), std::string::npos) << table;
  // Row b: the baseline never reached the error, so its speed-up is a lower bound.
  EXPECT_NE(table.find("(does not reach it)"), std::string::npos) << table;
  EXPECT_NE(table.find("| **>= 5.00x** [4.50–5.50] |"), std::string::npos) << table;
  EXPECT_NE(table.find("| c | failed |"), std::string::npos) << table;
  EXPECT_NE(table.find("`raymarch:steps=20` (does not reach it) | 0.00e+00 | - | - |"), std::string::npos) << table;
}

class BruteForceMatcherTest : public ::testing::Test {};

TEST_F(BruteForceMatcherTest, FindsTheFewestStepsThatReachTheError) {
  BenchmarkSession session;
  Scene scene = loadScene("spheres");
  const int w = 32, h = 24;
  Measured ref = measure(scene, referenceSpec(scene, "sm=128"), session.limits(), w, h, 0, nullptr);
  ASSERT_TRUE(ref.ok);
  BruteForceMatcher matcher(scene, ref.run.inscatter, session.limits(), registeredMethods(), w, h, 1, "sm=128");
  // A point light in view: the uniform and the equiangular series.
  ASSERT_EQ(matcher.series(), (std::vector<std::string>{"uniform", "equiangular"}));
  for (const std::string& series : matcher.series()) {
    const double target = matcher.errorAt({series, 40}).relmse;
    ASSERT_TRUE(std::isfinite(target) && target > 0.0) << series;
    BaselineMatch m = matcher.matchSteps(series, target);
    EXPECT_TRUE(m.reached) << series;
    EXPECT_LE(m.point.steps, 40) << series;
    EXPECT_LE(m.relmse, target) << series;
    EXPECT_GT(matcher.errorAt({series, std::max(1, m.point.steps / 2)}).relmse, target) << series;
    // The spec is the reference method's own, with the shared shadow map.
    ResolvedSpec spec = resolveSpec(m.spec, session.limits());
    EXPECT_EQ(spec.method, matcher.method());
    EXPECT_EQ(spec.params.getInt("steps"), m.point.steps);
    EXPECT_EQ(spec.params.getInt("sm"), 128);
  }
  // An error no step count reaches: not reached, at the most steps allowed.
  BaselineMatch none = matcher.matchSteps("uniform", 0.0, 0, 32);
  EXPECT_FALSE(none.reached);
  EXPECT_EQ(none.point.steps, 32);
  EXPECT_THROW(matcher.spec({"no-such-series", 8}), UsageError);
}

TEST_F(BruteForceMatcherTest, TimesTheMethodAndItsBaselinesInTheSameRounds) {
  BenchmarkSession session;
  Scene scene = loadScene("spheres");
  EqualQualityTiming t = timeAgainstBaselines(scene, "raymarch:steps=8:sm=64",
                                              {"raymarch:steps=64:sm=64", "dsm", "raymarch:steps=16:sm=64"},
                                              session.limits(), 16, 12, 1, 2);
  ASSERT_EQ(t.speedup.size(), 3u);
  EXPECT_GT(t.methodMs.median, 0.0);
  EXPECT_GT(t.speedup[0].median, 0.0);
  EXPECT_EQ(t.speedup[1].median, 0.0);  // dsm cannot render spheres: never the match
  EXPECT_NE(t.cheapest, 1);
  EXPECT_GE(t.cheapest, 0);
}

}  // namespace
}  // namespace vs
