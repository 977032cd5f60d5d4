// What every method's benchmark shares: the session (GL context, the driver's threads pinned, the
// provenance preamble) and drift detection around every timed run. A benchmark creates one
// BenchmarkSession first; runs timed through it (methods/registry.hpp, benchmarkSpec) are each
// bracketed by the calibration workload and repeated when the machine's speed moved (drift.hpp),
// and driftSummary() says at the end how steady the machine was.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "harness/gl/context.hpp"
#include "harness/bench/drift.hpp"
#include "harness/gl/gl.hpp"

namespace vs {

// What every benchmark accepts besides its own arguments.
struct BenchmarkOptions {
  // --seed N: the jitter seed of every run. scripts/reproduce runs each table in processes with
  // different seeds, so a figure that holds only for one noise pattern shows as a disagreement.
  uint32_t seed = 1;
};
// Takes the common options out of argv (argc shrinks), leaving the benchmark's own in order.
// Returns the error's one line, empty when the options were good.
std::string parseBenchmarkOptions(int& argc, char** argv, BenchmarkOptions& options);
// parseBenchmarkOptions for a benchmark's main: a bad value prints its line and exits with 2.
BenchmarkOptions takeBenchmarkOptions(int& argc, char** argv);

class BenchmarkSession {
 public:
  explicit BenchmarkSession(BenchmarkOptions options = {}, DriftPolicy policy = {});
  ~BenchmarkSession();
  BenchmarkSession(const BenchmarkSession&) = delete;
  BenchmarkSession& operator=(const BenchmarkSession&) = delete;

  const gl::Limits& limits() const { return limits_; }
  uint32_t seed() const { return options_.seed; }
  const ContextInfo& info() const { return context_.info(); }
  // "provenance: ...", "seed: ...", "threads: ..." and "drift: ..." lines, each after `bullet` (e.g. "- ").
  std::string preamble(const std::string& bullet = "") const;
  // One line: the calibration's range over the run, the rounds repeated and those still disturbed.
  std::string driftSummary(const std::string& bullet = "") const;
  DriftGuard& drift() { return *guard_; }
  // Counts a guarded run whose kept attempt was still disturbed (for driftSummary).
  void recordRun(const GuardedRound& round) { disturbedKept_ += round.disturbed ? 1 : 0; }
  // The session of this process (null before one is made): benchmarkSpec guards its runs with it.
  static BenchmarkSession* current();

 private:
  BenchmarkOptions options_;
  GlContext context_;
  std::string pinning_;
  gl::Limits limits_;
  std::unique_ptr<CalibrationProbe> probe_;
  std::unique_ptr<DriftGuard> guard_;
  int disturbedKept_ = 0;
};

}  // namespace vs
