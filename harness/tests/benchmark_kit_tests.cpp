// Tests for harness/benchmark_kit: a benchmark session brackets every timed run with its
// calibration workload (drift detection) and leaves error-only runs alone. Each test makes its own
// GL context through the session.
#include <gtest/gtest.h>

#include "harness/benchmark_kit.hpp"
#include "methods/registry.hpp"

namespace vs {
namespace {

TEST(BenchmarkKitTest, TimedRunsAreBracketedByTheCalibrationAndErrorRunsAreNot) {
  EXPECT_EQ(BenchmarkSession::current(), nullptr);
  {
    BenchmarkSession session(DriftPolicy{15.0, 0, true});  // no repeats: a fixed number of samples
    EXPECT_EQ(BenchmarkSession::current(), &session);
    const std::string preamble = session.preamble("- ");
    for (const char* line : {"- provenance: ", "- threads: ", "- drift: "})
      EXPECT_NE(preamble.find(line), std::string::npos) << preamble;
    Scene scene = loadScene("spheres");
    const std::string spec = "raymarch:steps=4:sm=64";
    MethodRun errorOnly = benchmarkSpec(scene, spec, session.limits(), 16, 12, 0);
    ASSERT_EQ(errorOnly.status, RunStatus::Success) << errorOnly.reason;
    EXPECT_TRUE(session.drift().history().empty());
    MethodRun timed = benchmarkSpec(scene, spec, session.limits(), 16, 12, 1);
    ASSERT_EQ(timed.status, RunStatus::Success) << timed.reason;
    // The run's first calibration before it, one after it.
    ASSERT_EQ(session.drift().history().size(), 2u);
    for (const CalibrationSample& s : session.drift().history()) {
      EXPECT_GT(s.drawMs, 0.0);
      EXPECT_GT(s.computeMs, 0.0);
    }
    EXPECT_NE(session.driftSummary().find("over 2 samples"), std::string::npos) << session.driftSummary();
    // A run that fails times nothing: no calibration after it.
    MethodRun bad = benchmarkSpec(scene, "dsm", session.limits(), 16, 12, 1);
    EXPECT_EQ(bad.status, RunStatus::Unsupported);
    EXPECT_EQ(session.drift().history().size(), 2u);
  }
  EXPECT_EQ(BenchmarkSession::current(), nullptr);
}

}  // namespace
}  // namespace vs
