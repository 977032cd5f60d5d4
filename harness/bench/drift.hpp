// Drift detection: a fixed calibration workload timed before the first round and after every round
// of a row, so that a machine whose speed changed while the row was timed is seen (shared hosts,
// CPU frequency, other tenants). A round during which the calibration moved more than a threshold
// is disturbed and run again, a bounded number of times; rows still measured in a disturbed state
// say so. The policy (DriftGuard) is plain C++ with the probe as a function, so it is tested with a
// synthetic slowdown; CalibrationProbe is the GL workload.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace vs {

// One timing of the calibration workload (wall clock between glFinish calls, ms).
struct CalibrationSample {
  double drawMs = 0, computeMs = 0;
};

// The larger relative change of the two workloads from `from` to `to`, in percent (0 when either
// has no time).
double calibrationChangePct(const CalibrationSample& from, const CalibrationSample& to);

// A fragment pass and a compute dispatch of fixed size (harness/shaders/calibrate.*), sized once
// to about `targetMs` each on this machine; measure() times each as the median of a few runs.
class CalibrationProbe {
 public:
  explicit CalibrationProbe(double targetMs = 2.0);
  ~CalibrationProbe();
  CalibrationProbe(const CalibrationProbe&) = delete;
  CalibrationProbe& operator=(const CalibrationProbe&) = delete;
  CalibrationSample measure();
  int drawIterations() const;
  int computeIterations() const;

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
};

struct DriftPolicy {
  double thresholdPct = 15.0;  // a round whose calibration moved more than this is disturbed
  int maxRetries = 2;          // a disturbed round runs again at most this many times
  bool enabled = true;
};

// What became of one guarded round.
struct GuardedRound {
  CalibrationSample before, after;  // around the attempt that was kept (the last one)
  double driftPct = 0;              // calibrationChangePct(before, after) of that attempt
  double shiftPct = 0;              // change of the mean of before and after from the run's first calibration
  int retries = 0;                  // attempts discarded as disturbed
  bool disturbed = false;           // the kept attempt is still disturbed (drift or shift over the threshold)
};

class DriftGuard {
 public:
  DriftGuard(std::function<CalibrationSample()> probe, DriftPolicy policy);
  // Runs attempt(k) for k = 0, 1, ...: once, and again while the calibration around it moved more
  // than the threshold, at most maxRetries more times. The caller keeps what the last attempt
  // measured. attempt returns false when it timed nothing (e.g. the row failed): then no retry.
  // The calibration after one round is the one before the next.
  GuardedRound run(const std::function<bool(int attempt)>& attempt);
  const DriftPolicy& policy() const { return policy_; }
  // Every calibration taken, in order; the first, the run's baseline, is the median of three probes.
  const std::vector<CalibrationSample>& history() const { return history_; }
  int disturbedRounds() const { return disturbedRounds_; }  // rounds seen disturbed, repeated or not
  int retries() const { return retries_; }
  // True once, on the first disturbed round: the caller warns the user then.
  bool takeFirstWarning();
  // How far the calibration had moved in that first disturbed attempt (drift or shift, percent).
  double firstDisturbancePct() const { return firstDisturbancePct_; }

 private:
  CalibrationSample sample();
  std::function<CalibrationSample()> probe_;
  DriftPolicy policy_;
  std::vector<CalibrationSample> history_;
  int disturbedRounds_ = 0, retries_ = 0;
  bool warned_ = false, pendingWarning_ = false;
  double firstDisturbancePct_ = 0;
};

// A row's calibration over its rounds: the largest drift and shift, retries, whether any kept round
// was disturbed.
struct RowDrift {
  double driftPct = 0, shiftPct = 0;
  int retries = 0;
  bool disturbed = false;
  CalibrationSample last;  // after the row's last round
  void add(const GuardedRound& round);
};

}  // namespace vs
