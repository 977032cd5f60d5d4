// Tests for the rounds: how a row's timings combine over interleaved rounds.
#include <gtest/gtest.h>

#include "harness/pipeline/frame.hpp"
#include "harness/shootout/rounds.hpp"

namespace vs::shootout {
namespace {

TimingStats stats(double median, double min, double max, size_t samples, double mdape = 1.0) {
  TimingStats s;
  s.medianMs = median;
  s.minMs = min;
  s.maxMs = max;
  s.samples = samples;
  s.mdapePct = mdape;
  s.p95Ms = median + 1.0;
  s.p99Ms = median + 2.0;
  return s;
}

TEST(CombineRounds, MedianOfTheRoundsAndTheExtremesOfEveryFrame) {
  TimingStats c = combineRounds({stats(3.0, 2.5, 9.0, 10, 4.0), stats(1.0, 0.5, 1.5, 10, 1.0),
                                 stats(2.0, 1.8, 2.2, 5, 2.0)});
  EXPECT_DOUBLE_EQ(c.medianMs, 2.0);
  EXPECT_DOUBLE_EQ(c.minMs, 0.5);
  EXPECT_DOUBLE_EQ(c.maxMs, 9.0);
  EXPECT_EQ(c.samples, 25u);
  EXPECT_DOUBLE_EQ(c.mdapePct, 2.0);
  EXPECT_DOUBLE_EQ(c.p95Ms, 3.0);
  EXPECT_DOUBLE_EQ(c.p99Ms, 4.0);
}

TEST(CombineRounds, OneRoundIsItself) {
  TimingStats one = stats(4.0, 3.0, 6.0, 7, 3.5);
  TimingStats c = combineRounds({one});
  EXPECT_DOUBLE_EQ(c.medianMs, one.medianMs);
  EXPECT_DOUBLE_EQ(c.minMs, one.minMs);
  EXPECT_DOUBLE_EQ(c.maxMs, one.maxMs);
  EXPECT_DOUBLE_EQ(c.mdapePct, one.mdapePct);
  EXPECT_EQ(c.samples, one.samples);
}

TEST(CombineRounds, NoRoundsAreZeros) {
  TimingStats c = combineRounds({});
  EXPECT_EQ(c.medianMs, 0.0);
  EXPECT_EQ(c.maxMs, 0.0);
  EXPECT_EQ(c.samples, 0u);
}

TEST(RoundRange, SpanOfTheRoundsMedians) {
  EXPECT_EQ(roundRange({stats(5, 1, 50, 1), stats(2, 1, 50, 1), stats(9, 1, 50, 1)}), std::make_pair(2.0, 9.0));
  EXPECT_EQ(roundRange({stats(4, 1, 8, 1)}), std::make_pair(4.0, 4.0));
  EXPECT_EQ(roundRange({}), std::make_pair(0.0, 0.0));
}

TEST(RoundTimings, KeepsEachRoundsFramePassesAndScattering) {
  MethodRun run;
  run.frame = stats(10, 9, 11, 3);
  run.passStats[kShadowMapPass] = stats(2, 2, 2, 3);  // shared: not scattering
  run.passStats["March"] = stats(6, 5, 7, 3);
  RoundTimings t;
  t.add(run);
  run.passStats["March"] = stats(8, 7, 9, 3);
  t.add(run);
  EXPECT_EQ(t.count(), 2);
  ASSERT_EQ(t.passes.at("March").size(), 2u);
  EXPECT_DOUBLE_EQ(t.passes.at("March")[1].medianMs, 8.0);
  EXPECT_EQ(t.scatter, (std::vector<double>{6.0, 8.0}));
}

}  // namespace
}  // namespace vs::shootout
