// Tests for the equal-quality stage against a fake baseline whose error and time are known
// functions of the step count: the matches it finds, its lower bounds, its memo, and the columns
// it fills.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "harness/shootout/equal_quality.hpp"

namespace vs::shootout {
namespace {

// L_s relMSE 100 / steps (RMSE 1 / steps), scattering time steps / 100 ms; `failsFrom`: steps at
// which it fails to render. Counts every render.
class FakeBaseline : public BaselineSource {
 public:
  explicit FakeBaseline(std::map<std::pair<std::string, int>, int>& renders, int failsFrom = 1 << 30)
      : renders_(renders), failsFrom_(failsFrom) {}
  const std::string& method() const override { return method_; }
  const std::vector<std::string>& samplings() const override { return samplings_; }
  std::string spec(const std::string& sampling, int sm, int steps) const override {
    return "brute:" + sampling + ":steps=" + std::to_string(steps) + ":sm=" + std::to_string(sm);
  }
  BaselineError error(const std::string&, int, int steps) override {
    ++renders_[{"error", steps}];
    BaselineError e;
    e.ok = steps < failsFrom_;
    e.lsRelmse = 100.0 / steps;
    e.lsRmse = 1.0 / steps;
    return e;
  }
  double time(const std::string&, int, int steps) override {
    ++renders_[{"time", steps}];
    return steps < failsFrom_ ? steps / 100.0 : -1.0;
  }

 private:
  std::map<std::pair<std::string, int>, int>& renders_;
  int failsFrom_;
  std::string method_ = "brute";
  std::vector<std::string> samplings_ = {"uniform", "equiangular"};
};

struct EqualQualityTest : ::testing::Test {
  std::map<std::pair<std::string, int>, int> renders;
  Progress progress{1};
  EqualQuality eq{std::make_unique<FakeBaseline>(renders), progress};
};

TEST_F(EqualQualityTest, MatchIsTheSmallestPassingStepCountWithinTheTolerance) {
  for (double target : {50.0, 1.0, 0.3}) {
    EqualQuality::Match m = eq.match("uniform", 256, target);
    const double exact = std::ceil(100.0 / target);  // the smallest step count whose relMSE <= target
    EXPECT_TRUE(m.reached && m.any) << target;
    EXPECT_GE(m.steps, exact) << target;
    EXPECT_LE(m.steps, exact * (1.0 + 1.0 / 64) + 1) << target;
    EXPECT_EQ(m.ms, 0.0);  // a reached match is timed in the rounds
  }
  for (const auto& [what, count] : renders) EXPECT_EQ(count, 1) << what.first << " " << what.second;
  for (const auto& [what, count] : renders) EXPECT_EQ(what.first, "error");  // matching needs no times
}

TEST_F(EqualQualityTest, NotReachedGivesTheTimeAtTheMostStepsAsALowerBound) {
  EqualQuality::Match m = eq.match("uniform", 256, 100.0 / 5000);
  EXPECT_FALSE(m.reached);
  EXPECT_TRUE(m.any);
  EXPECT_EQ(m.steps, EqualQuality::kMaxSteps);
  EXPECT_DOUBLE_EQ(m.ms, EqualQuality::kMaxSteps / 100.0);
}

TEST(EqualQuality, ABaselineThatFailsAtTheMostStepsGivesNoMatch) {
  std::map<std::pair<std::string, int>, int> renders;
  Progress progress(1);
  EqualQuality eq(std::make_unique<FakeBaseline>(renders, 1000), progress);
  EqualQuality::Match m = eq.match("uniform", 256, 100.0 / 5000);
  EXPECT_FALSE(m.any);
  EXPECT_FALSE(m.reached);
}

TEST_F(EqualQualityTest, EveryPointIsRenderedOnce) {
  eq.match("uniform", 256, 1.0);
  const size_t first = renders.size();
  eq.match("uniform", 256, 1.0);
  eq.at("uniform", 256, 16);
  EXPECT_EQ(renders.size(), first);
  for (const auto& [what, count] : renders) EXPECT_EQ(count, 1);
  eq.timeAt("uniform", 256, 64);
  eq.timeAt("uniform", 256, 64);
  EXPECT_EQ((renders[{"time", 64}]), 1);
}

TEST_F(EqualQualityTest, EqualTimeErrorIsAtTheMostStepsWithinTheRowsTime) {
  const double rowMs = 3.0;  // 300 steps
  double rmse = eq.equalTimeLsRmse("uniform", 256, rowMs);
  const int steps = int(std::lround(1.0 / rmse));
  EXPECT_GE(steps, 300);
  EXPECT_LE(steps, 300 * (1.0 + 1.0 / 64) + 1);  // the search's tolerance
  // A row slower than the most steps: the error at the most steps.
  EXPECT_DOUBLE_EQ(eq.equalTimeLsRmse("uniform", 256, 1000.0), 1.0 / EqualQuality::kMaxSteps);
}

Measured successfulRow(const std::string& method, double lsRelmse, double scatterMs) {
  Measured m;
  m.run.method = method;
  m.run.shadowMapSize = 512;
  m.run.passStats["March"].medianMs = scatterMs;
  m.measured = m.exactMeasured = true;
  m.lsErr.relmse = lsRelmse * 2;  // against the reference: not the one matched with the ground truth
  m.exactLsErr.relmse = lsRelmse;
  return m;
}

RunPlan exactPlan() {
  RunPlan plan;
  plan.equalQualityExact = true;
  return plan;
}

TEST_F(EqualQualityTest, MatchRowMatchesEverySamplingOnTheRowsError) {
  RowMatches matches = matchRow(successfulRow("fast", 1.0, 0.5), eq, exactPlan());
  ASSERT_EQ(matches.baselines.size(), 2u);
  EXPECT_EQ(matches.baselines[0].sampling, "uniform");
  EXPECT_EQ(matches.baselines[1].sampling, "equiangular");
  const EqualQuality::Match& m = matches.baselines[0].match;
  EXPECT_TRUE(m.reached);
  EXPECT_GE(m.steps, 100);  // relMSE 1 against the ground truth, not 2 against the reference
  EXPECT_EQ(matches.baselines[0].spec, "brute:uniform:steps=" + std::to_string(m.steps) + ":sm=512");
}

TEST_F(EqualQualityTest, NoMatchesForTheBaselinesOwnFailedOrUnmeasuredRows) {
  EXPECT_TRUE(matchRow(successfulRow("brute", 1.0, 0.5), eq, exactPlan()).baselines.empty());
  Measured failed = successfulRow("fast", 1.0, 0.5);
  failed.run.status = RunStatus::Failure;
  EXPECT_TRUE(matchRow(failed, eq, exactPlan()).baselines.empty());
  Measured unmeasured = successfulRow("fast", 1.0, 0.5);
  unmeasured.exactMeasured = false;
  EXPECT_EQ(matchedError(unmeasured, exactPlan()), -1.0);
  EXPECT_TRUE(matchRow(unmeasured, eq, exactPlan()).baselines.empty());
  RunPlan againstReference;
  EXPECT_DOUBLE_EQ(matchedError(unmeasured, againstReference), 2.0);
  EXPECT_TRUE(renders.empty());
}

TEST_F(EqualQualityTest, ColumnsOfAReachedAndAnUnreachedBaseline) {
  Measured row = successfulRow("fast", 100.0 / 200, 0.5);
  RowMatches matches = matchRow(row, eq, exactPlan());
  ASSERT_EQ(matches.baselines.size(), 2u);
  matches.baselines[0].roundMs = {2.0, 3.0, 2.5};  // uniform, timed beside the row in three rounds
  matches.baselines[1].match = {EqualQuality::kMaxSteps, 40.96, false, true};
  ResultRow out(runsColumns());
  addEqualQuality(out, row, matches, eq, exactPlan(), {0.5, 0.5, 1.0});
  EXPECT_EQ(out.get("eq_error_against"), "exact");
  EXPECT_EQ(out.get("eq_uniform_steps"), std::to_string(matches.baselines[0].match.steps));
  EXPECT_EQ(out.get("eq_uniform_ms"), "2.5");
  EXPECT_EQ(out.get("eq_uniform_round_min_ms"), "2");
  EXPECT_EQ(out.get("eq_uniform_round_max_ms"), "3");
  EXPECT_EQ(out.get("speedup_eq_uniform"), "4");  // median of 4, 6, 2.5
  EXPECT_EQ(out.get("speedup_eq_uniform_round_min"), "2.5");
  EXPECT_EQ(out.get("speedup_eq_uniform_round_max"), "6");
  EXPECT_EQ(out.get("eq_equiangular_steps"), ">=4096");
  EXPECT_EQ(out.get("eq_equiangular_ms"), ">=40.96");
  EXPECT_EQ(out.get("speedup_eq_equiangular"), ">=81.92");
  EXPECT_EQ(out.get("eq_equiangular_round_min_ms"), "");
  EXPECT_EQ(out.get("equal_time_ls_rmse_uniform"), num(1.0 / 50));  // 0.5 ms: 50 steps
}

TEST_F(EqualQualityTest, AgainstTheReferenceSaysWhy) {
  RunPlan plan;
  plan.equalQualityNote = "the ground truth cannot integrate light textures";
  Measured row = successfulRow("fast", 1.0, 0.5);
  RowMatches matches = matchRow(row, eq, plan);
  ResultRow out(runsColumns());
  addEqualQuality(out, row, matches, eq, plan, {});
  EXPECT_EQ(out.get("eq_error_against"), "reference (the ground truth cannot integrate light textures)");
  const int steps = std::stoi(out.get("eq_uniform_steps"));
  EXPECT_GE(steps, 50);  // relMSE 2 against the reference (1 against the ground truth: 100 steps)
  EXPECT_LT(steps, 100);
}

}  // namespace
}  // namespace vs::shootout
