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
  RenderedBaseline baseline(p, limits(), registeredMethods(), options, truth);
  EXPECT_EQ(baseline.method(), "raymarch");
  EXPECT_EQ(baseline.samplings(), (std::vector<std::string>{"uniform", "equiangular"}));
  EXPECT_EQ(baseline.spec("uniform", 256, 64).rfind("raymarch:", 0), 0u);
  EXPECT_NE(baseline.spec("uniform", 256, 64).find("steps=64"), std::string::npos);
  BaselineError coarse = baseline.error("uniform", 256, 4), fine = baseline.error("uniform", 256, 256);
  ASSERT_TRUE(coarse.ok && fine.ok);
  EXPECT_LT(fine.lsRelmse, coarse.lsRelmse);
  EXPECT_GE(baseline.time("uniform", 256, 16), 0.0);
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
