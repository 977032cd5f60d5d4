// Equal-error matching for the benchmarks: the cheapest brute-force baseline (the registered
// reference method, through Method::baselineParams) whose L_s error reaches a method's, found by
// the step search of the shootout (step_search.hpp) on untimed frames, then timed against the method
// in interleaved rounds, so that a speed-up is the median of per-round ratios with their range.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/method.hpp"
#include "harness/pipeline/runner.hpp"

namespace vs {

// A figure over rounds: their median and range.
struct Spread {
  double median = 0, lo = 0, hi = 0;
};
Spread spreadOfValues(const std::vector<double>& values);
// Per round, numerator / denominator (rounds where either is missing or the denominator is not
// positive are left out): a speed-up measured in the same round on both sides.
Spread ratioSpread(const std::vector<double>& numerator, const std::vector<double>& denominator);
// "12.3 [11.9–13.0]": a spread as a table cell.
std::string spreadCell(const Spread& s);
// "4.20x [3.90–4.51]".
std::string speedupCell(const Spread& s);

struct BaselineMatch {
  BaselinePoint point;
  std::string spec;  // "raymarch:steps=...": the reference method at `point`, with the shared parameters
  double relmse = 0, rmse = 0;
  // false: not even the most steps (light samples) reach the target; the spec is then the dearest
  // point tried, and a speed-up against it is a lower bound.
  bool reached = false;
};

// The brute-force baselines of one scene, matched by L_s relMSE against `reference`. Every point
// is rendered once (one frame without a warm-up, the benchmark's seed) and its error memoised.
class BruteForceMatcher {
 public:
  // `sharedParams` ("sm=1024", may be empty) are added to every spec, so a baseline sees the same
  // shadow map as the method it is matched with.
  BruteForceMatcher(const Scene& scene, const Image& reference, const gl::Limits& limits,
                    const MethodRegistry& registry, int width, int height, uint32_t seed,
                    std::string sharedParams = "");
  ~BruteForceMatcher();
  const std::string& method() const { return method_; }
  // The series the reference method offers as baselines for this scene ("uniform", and
  // "equiangular" for point and spot lights: the strong one).
  const std::vector<std::string>& series() const { return series_; }
  std::string spec(const BaselinePoint& point) const;
  // L_s error of one point (memoised); nonFinite set when the run failed.
  ErrorMetrics errorAt(const BaselinePoint& point);
  // The smallest step count in [1, maxSteps] (light samples fixed) whose relMSE is at most `target`.
  BaselineMatch matchSteps(const std::string& series, double target, int lightSamples = 0, int maxSteps = 4096);
  // The smallest light-sample count in [1, maxLightSamples] at `steps` (area lights).
  BaselineMatch matchLightSamples(const std::string& series, int steps, double target, int maxLightSamples);

 private:
  BaselineMatch finish(BaselinePoint point, bool reached);

  const Image& reference_;
  const gl::Limits& limits_;
  const MethodRegistry& registry_;
  std::string method_, sharedParams_;
  std::unique_ptr<Method> baseline_;
  std::vector<std::string> series_;
  std::unique_ptr<Runner> runner_;
  std::map<std::tuple<std::string, int, int>, ErrorMetrics> errors_;
};

// One row of a benchmark table: a timed run, its scattering time and its L_s error.
struct Measured {
  MethodRun run;
  double scatterMs = 0;  // MethodRun::scatterMs
  double rmse = 0, relmse = 0;  // L_s against the reference (0 without one)
  bool ok = false;              // the run succeeded
};

struct EqualQualityTiming {
  Spread methodMs;
  std::vector<Spread> baselineMs, speedup;  // per candidate; zeros for one that failed a round
  int cheapest = -1;  // the candidate with the smallest median time among those that ran every round
};

// One row of an equal-quality table: the method's error from one frame (its images kept), its
// baselines matched on L_s relMSE, and all of them timed in interleaved rounds.
struct EqualQualityRow {
  std::string spec;
  Measured method;
  std::vector<BaselineMatch> matches;
  EqualQualityTiming timing;
};

// The table of equal-quality rows, in Markdown: a label, the method's error and time, then per match
// its parameters, error, time and speed-up ("≥" where the baseline never reached the error), and
// the strongest baseline's speed-up last.
std::string equalQualityTable(const std::vector<std::pair<std::string, EqualQualityRow>>& rows,
                              const std::string& labelHeader);

}  // namespace vs
