// What every method's benchmark shares: the session (GL context, the driver's threads pinned, the
// provenance preamble) and drift detection around every timed run. A benchmark creates one
// BenchmarkSession first; runs timed through it (methods/registry.hpp, benchmarkSpec) are each
// bracketed by the calibration workload and repeated when the machine's speed moved (drift.hpp),
// and driftSummary() says at the end how steady the machine was.
#pragma once
#include <memory>
#include <string>

#include "context.hpp"
#include "drift.hpp"
#include "gl.hpp"

namespace vs {

class BenchmarkSession {
 public:
  explicit BenchmarkSession(DriftPolicy policy = {});
  ~BenchmarkSession();
  BenchmarkSession(const BenchmarkSession&) = delete;
  BenchmarkSession& operator=(const BenchmarkSession&) = delete;

  const gl::Limits& limits() const { return limits_; }
  const ContextInfo& info() const { return context_.info(); }
  // "provenance: ...", "threads: ..." and "drift: ..." lines, each after `bullet` (e.g. "- ").
  std::string preamble(const std::string& bullet = "") const;
  // One line: the calibration's range over the run, the rounds repeated and those still disturbed.
  std::string driftSummary(const std::string& bullet = "") const;
  DriftGuard& drift() { return *guard_; }
  // Counts a guarded run whose kept attempt was still disturbed (for driftSummary).
  void recordRun(const GuardedRound& round) { disturbedKept_ += round.disturbed ? 1 : 0; }
  // The session of this process (null before one is made): benchmarkSpec guards its runs with it.
  static BenchmarkSession* current();

 private:
  GlContext context_;
  std::string pinning_;
  gl::Limits limits_;
  std::unique_ptr<CalibrationProbe> probe_;
  std::unique_ptr<DriftGuard> guard_;
  int disturbedKept_ = 0;
};

}  // namespace vs
