// Tests for the rows stage and the sequence errors: a measured job's runs.csv row and summary, and
// a moving scene's errors frame by frame.
#include <gtest/gtest.h>

#include "harness/shootout/rows.hpp"
#include "harness/shootout/sequence.hpp"

namespace vs::shootout {
namespace {

Measured successfulJob() {
  Measured m;
  m.run.method = "raymarch";
  m.run.params = "steps=8";
  m.run.shadowMapSize = 512;
  m.run.passes = {"March", "Composite"};
  m.run.frame.medianMs = 12.5;
  m.run.frame.mdapePct = 1.0;
  m.run.stats = {{"rays", 768}, {"texels", 1.5}};
  m.measured = true;
  m.finalErr.rmse = 0.25;
  m.finalErr.psnr = 12;
  m.lsErr.relmse = 0.5;
  return m;
}

struct RowsTest : ::testing::Test {
  RunRequest req;
  RunPlan plan;
  Baselines base;
  RowContext rows{req, plan, base, "wall", "llvmpipe", "2026-12-07T12:00:00Z"};
  RowsTest() {
    plan.scene.name = "spheres";
    plan.width = 32;
    plan.height = 24;
    req.frames = 3;
    base.referenceLabel = "raymarch:steps=4096";
  }
};

TEST_F(RowsTest, ASuccessfulRowHasItsTimesAndErrors) {
  ResultRow row = runRow(successfulJob(), rows);
  EXPECT_EQ(row.get("scene"), "spheres");
  EXPECT_EQ(row.get("status"), "Success");
  EXPECT_EQ(row.get("passes"), "March;Composite");
  EXPECT_EQ(row.get("method_stats"), "rays=768;texels=1.5");
  EXPECT_EQ(row.get("frame_median_ms"), "12.5");
  EXPECT_EQ(row.get("unstable"), "0");
  EXPECT_EQ(row.get("rmse"), "0.25");
  EXPECT_EQ(row.get("ls_relmse"), "0.5");
  EXPECT_EQ(row.get("exact_rmse"), "");  // not measured against the ground truth
  EXPECT_EQ(row.get("width"), "32");
  EXPECT_EQ(row.get("frames"), "3");
  EXPECT_EQ(row.get("shadow_map"), "512");
  EXPECT_EQ(row.get("reference"), "raymarch:steps=4096");
  EXPECT_EQ(row.get("timer"), "wall");
  EXPECT_EQ(row.get("date"), "2026-12-07T12:00:00Z");
  EXPECT_EQ(jobSummary(successfulJob()), "12.5 ms/frame, rmse 0.25, psnr 12 dB");
}

TEST_F(RowsTest, AFailedRowSaysWhyAndHasNoFigures) {
  Measured m = successfulJob();
  m.run.status = RunStatus::Unsupported;
  m.run.reason = "no volume data";
  m.measured = false;
  ResultRow row = runRow(m, rows);
  EXPECT_EQ(row.get("status"), "Unsupported");
  EXPECT_EQ(row.get("reason"), "no volume data");
  EXPECT_EQ(row.get("frame_median_ms"), "");
  EXPECT_EQ(row.get("rmse"), "");
  EXPECT_EQ(jobSummary(m), "Unsupported: no volume data");
}

TEST_F(RowsTest, UnstableTiming) {
  Measured m = successfulJob();
  m.run.frame.mdapePct = 7.5;
  m.measured = false;
  EXPECT_EQ(runRow(m, rows).get("unstable"), "1");
  EXPECT_EQ(jobSummary(m), "12.5 ms/frame (unstable timing)");
}

Image filled(float value) {
  Image img(4, 2);
  std::fill(img.rgb.begin(), img.rgb.end(), value);
  return img;
}

TEST(SequenceMetrics, MeanAndWorstOverTheFrames) {
  Image ref = filled(1.0f), off1 = filled(1.1f), off3 = filled(1.3f);
  SequenceMetrics m = sequenceMetrics({&ref, &off1, &off3}, {&ref, &ref, &ref});
  ASSERT_TRUE(m.measured);
  EXPECT_EQ(m.frames, 3);
  ASSERT_EQ(m.perFrame.size(), 3u);
  EXPECT_NEAR(m.perFrame[0].rmse, 0.0, 1e-9);
  EXPECT_NEAR(m.perFrame[2].rmse, 0.3, 1e-6);
  EXPECT_NEAR(m.rmseMax, 0.3, 1e-6);
  EXPECT_NEAR(m.rmseMean, 0.4 / 3, 1e-6);
  EXPECT_GT(m.relmseMax, m.relmseMean);
  EXPECT_GT(m.temporal.rmse, 0.0);  // the frames flicker where the references do not
}

TEST(SequenceMetrics, NoFramesNothingMeasured) {
  SequenceMetrics m = sequenceMetrics({}, {});
  EXPECT_FALSE(m.measured);
  EXPECT_EQ(m.frames, 0);
}

}  // namespace
}  // namespace vs::shootout
