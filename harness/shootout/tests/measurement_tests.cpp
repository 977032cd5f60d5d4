// Tests for the stages that render, on tiny images: the rendered equal-quality baseline, and the
// stages end to end (plan, baselines, measurement over rounds, result files).
#include <gtest/gtest.h>

#include <filesystem>

#include "gl_test.hpp"
#include "harness/shootout/baselines.hpp"
#include "harness/shootout/measurement.hpp"
#include "harness/shootout/plan.hpp"

namespace vs::shootout {
namespace {

using vs::testing::GlTest;
using vs::testing::renderScene;

class ShootoutStagesTest : public GlTest {
 protected:
  RunRequest request() const {
    RunRequest r;
    r.scene = "spheres";
    r.size = "32x24";
    r.frames = 1;
    r.warmup = 1;
    r.methods = {"raymarch"};
    r.rungs = {"first"};
    r.noImages = true;
    r.driftThresholdPct = 0;  // no calibration workload
    return r;
  }
  RunPlan plan(const RunRequest& r) const {
    RunPlan p = planBeforeContext(r, true, registeredMethods());
    planJobs(p, r, true, registeredMethods(), limits());
    return p;
  }
};

TEST_F(ShootoutStagesTest, RenderedBaselineOffersBothSamplingsAndErrorFallsWithSteps) {
  RunRequest r = request();
  RunPlan p = plan(r);
  RunOptions options = runOptionsFor(r, p, TimerStrategy::WallClock);
  Image truth = renderScene(p.scene, "raymarch:steps=512:sm=256", options).inscatter;
  Runner runner(p.scene, limits(), options);
  RenderedBaseline baseline(p, limits(), registeredMethods(), options, truth, runner, runner);
  EXPECT_EQ(baseline.method(), "raymarch");
  EXPECT_EQ(baseline.samplings(), (std::vector<std::string>{"uniform", "equiangular"}));
  EXPECT_EQ(baseline.spec("uniform", 256, 64).rfind("raymarch:", 0), 0u);
  EXPECT_NE(baseline.spec("uniform", 256, 64).find("steps=64"), std::string::npos);
  BaselineError coarse = baseline.error("uniform", 256, 4), fine = baseline.error("uniform", 256, 256);
  ASSERT_TRUE(coarse.ok && fine.ok);
  EXPECT_LT(fine.lsRelmse, coarse.lsRelmse);
  EXPECT_GE(baseline.time("uniform", 256, 16), 0.0);
}

// The rows' runner serves the baselines too: a baseline point rendered after another method and
// after a timed run with other frame counts is the one a runner of its own renders.
TEST_F(ShootoutStagesTest, OneRunnerServesRowsAndBaselinesAlike) {
  RunRequest r = request();
  RunPlan p = plan(r);
  RunOptions options = runOptionsFor(r, p, TimerStrategy::WallClock);
  Image truth = renderScene(p.scene, "raymarch:steps=512:sm=256", options).inscatter;
  Runner fresh(p.scene, limits(), options);
  RenderedBaseline alone(p, limits(), registeredMethods(), options, truth, fresh, fresh);
  const BaselineError expected = alone.error("equiangular", 256, 24);
  Runner shared(p.scene, limits(), options);
  auto minmax = createMethod(registeredMethods(), "minmax");
  ResolvedSpec spec = resolveSpec("minmax:sm=256", limits(), registeredMethods());
  FrameSchedule longer = FrameSchedule::of(options);
  longer.frames = 3;
  longer.warmup = 2;
  ASSERT_EQ(shared.run(*minmax, spec.params, longer).status, RunStatus::Success);
  EXPECT_EQ(shared.options().frames, options.frames) << "the schedule is the run's alone";
  EXPECT_EQ(shared.options().warmup, options.warmup);
  RenderedBaseline reused(p, limits(), registeredMethods(), options, truth, shared, shared);
  EXPECT_GE(reused.time("equiangular", 256, 24), 0.0);
  const BaselineError got = reused.error("equiangular", 256, 24);
  ASSERT_TRUE(expected.ok && got.ok);
  EXPECT_DOUBLE_EQ(got.lsRelmse, expected.lsRelmse);
  EXPECT_DOUBLE_EQ(got.lsRmse, expected.lsRmse);
}

TEST_F(ShootoutStagesTest, EveryJobMeasuredInEveryRound) {
  RunRequest r = request();
  r.rounds = 2;
  r.out = vs::testing::makeTempDir("shootout-stages");
  RunPlan p = plan(r);
  ASSERT_EQ(p.jobs.size(), 2u);  // the first rung of uniform and of equiangular steps
  RunOptions options = runOptionsFor(r, p, TimerStrategy::WallClock);
  ResultFiles files(r.out, p.scene.name, !r.noImages);
  Progress progress(int(p.jobs.size()) * r.rounds + 1);
  int item = 0;
  nlohmann::json meta;
  Baselines base = prepareBaselines(r, p, limits(), registeredMethods(), options, progress, item, meta);
  EXPECT_EQ(item, 1);
  EXPECT_EQ(meta["reference"]["method"], "raymarch");
  RowContext rows{r, p, base, "wall", "test", "2026-12-07T12:00:00Z"};
  Measurement measurement(rows, registeredMethods(), limits(), options, files, progress);
  EXPECT_FALSE(measurement.equalQuality());
  EXPECT_EQ(measurement.runAll(item), 0);
  EXPECT_EQ(item, 5);

  auto runs = CsvTable::parse(vs::testing::readFile(r.out + "/runs.csv"));
  ASSERT_EQ(runs.size(), 3u);
  auto column = [&](const std::string& name) {
    return size_t(std::find(runs[0].begin(), runs[0].end(), name) - runs[0].begin());
  };
  for (size_t k = 1; k < runs.size(); ++k) {
    EXPECT_EQ(runs[k][column("status")], "Success");
    EXPECT_EQ(runs[k][column("rounds")], "2");
    EXPECT_EQ(runs[k][column("series")], k == 1 ? "uniform" : "equiangular");
    EXPECT_LE(std::stod(runs[k][column("frame_round_min_ms")]), std::stod(runs[k][column("frame_round_max_ms")]));
    EXPECT_GT(std::stod(runs[k][column("ls_rmse")]), 0.0);
    EXPECT_EQ(runs[k][column("disturbed")], "");  // drift detection off
  }
  EXPECT_FALSE(measurement.driftJson()["enabled"].get<bool>());
  std::filesystem::remove_all(r.out);
}

}  // namespace
}  // namespace vs::shootout
