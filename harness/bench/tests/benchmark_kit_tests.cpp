// Tests for harness/benchmark_kit: a benchmark session brackets every timed run with its
// calibration workload (drift detection) and leaves error-only runs alone. Each test makes its own
// GL context through the session.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "harness/bench/benchmark_kit.hpp"
#include "methods/registry.hpp"

namespace vs {
namespace {

TEST(BenchmarkKitTest, TimedRunsAreBracketedByTheCalibrationAndErrorRunsAreNot) {
  EXPECT_EQ(BenchmarkSession::current(), nullptr);
  {
    BenchmarkSession session(BenchmarkOptions{}, DriftPolicy{15.0, 0, true});  // no repeats: a fixed number of samples
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

// --seed is taken out of argv for every benchmark; the benchmark's own arguments stay in order.
TEST(BenchmarkKitTest, SeedOptionIsTakenOutOfTheArguments) {
  std::vector<std::string> words = {"bench", "--quick", "--seed", "7", "--images", "dir"};
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  int argc = int(words.size());
  BenchmarkOptions options;
  EXPECT_EQ(parseBenchmarkOptions(argc, argv.data(), options), "");
  EXPECT_EQ(options.seed, 7u);
  ASSERT_EQ(argc, 4);
  EXPECT_STREQ(argv[1], "--quick");
  EXPECT_STREQ(argv[2], "--images");
  EXPECT_STREQ(argv[3], "dir");
  EXPECT_EQ(argv[4], nullptr);
  for (const char* bad : {"-1", "x", "4294967296", "7x", ""}) {
    std::vector<std::string> w2 = {"bench", "--seed", bad};
    std::vector<char*> a2;
    for (std::string& w : w2) a2.push_back(w.data());
    a2.push_back(nullptr);
    int n = std::string(bad).empty() ? 2 : 3;  // "--seed" last: no value
    BenchmarkOptions o;
    EXPECT_NE(parseBenchmarkOptions(n, a2.data(), o).find("--seed wants an integer"), std::string::npos) << bad;
    EXPECT_EQ(o.seed, 1u) << bad;
  }
}

}  // namespace
}  // namespace vs
