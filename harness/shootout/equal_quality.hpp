// The equal-quality stage (--equal-quality): takes a measured row, gives the brute-force baselines'
// step counts and times at the row's L_s error and their error at the row's scattering time.
//
// The baseline is ray marching (the registered reference method) with uniform or equiangular steps,
// at the row's shadow-map size, bisected on its step count to reach the row's L_s relMSE (RMSE would
// be decided by the few pixels next to an on-screen light, where uniform steps are worst) to within
// kStepTolerance. Errors are taken against the exact-visibility ground truth where it models the
// scene, since the ray-marched reference shares raymarch's 2x2 PCF shadow-map filter and would
// favour it. Each baseline point is rendered once per run (memoised): its error from one frame
// without a warm-up, its time, where one is needed, from min(frames, 2) frames after one warm-up.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "harness/cli/progress.hpp"
#include "harness/io/results.hpp"
#include "harness/pipeline/runner.hpp"
#include "harness/shootout/measured.hpp"
#include "harness/shootout/plan.hpp"

namespace vs::shootout {

// The baseline's L_s error at one step count.
struct BaselineError {
  double lsRmse = 0, lsRelmse = 0;
  bool ok = false;  // it rendered
};

// The brute-force baseline as the search sees it. RenderedBaseline renders it; tests give their own.
class BaselineSource {
 public:
  virtual ~BaselineSource() = default;
  virtual const std::string& method() const = 0;
  virtual const std::vector<std::string>& samplings() const = 0;  // its ladder series offered as baselines
  virtual std::string spec(const std::string& sampling, int sm, int steps) const = 0;
  virtual BaselineError error(const std::string& sampling, int sm, int steps) = 0;
  virtual double time(const std::string& sampling, int sm, int steps) = 0;  // scattering ms; negative: failed
};

// The reference method of the plan's effects, rendered on the rows' runners, its L_s compared
// with `truth`: its errors from one frame of `still` (the scene as the rows' compared frame shows
// it; the rows' own runner for a still scene), its times on `scene` after a warm-up frame.
class RenderedBaseline : public BaselineSource {
 public:
  RenderedBaseline(const RunPlan& plan, const gl::Limits& limits, const MethodRegistry& registry,
                   const RunOptions& options, const Image& truth, Runner& scene, Runner& still);
  const std::string& method() const override { return method_; }
  const std::vector<std::string>& samplings() const override { return samplings_; }
  std::string spec(const std::string& sampling, int sm, int steps) const override;
  BaselineError error(const std::string& sampling, int sm, int steps) override;
  double time(const std::string& sampling, int sm, int steps) override;

 private:
  MethodRun run(Runner& runner, const FrameSchedule& schedule, const std::string& sampling, int sm, int steps);
  // Each point's spec resolved once (its error and its time are two runs of it).
  const ResolvedSpec& resolved(const std::string& sampling, int sm, int steps);

  const gl::Limits& limits_;
  const MethodRegistry& registry_;
  const Image& truth_;
  Runner &sceneRunner_, &stillRunner_;
  FrameSchedule timed_, once_;
  std::string method_;
  std::unique_ptr<Method> baselineMethod_;
  std::vector<std::string> samplings_;
  std::map<std::tuple<std::string, int, int>, ResolvedSpec> resolved_;
};

class EqualQuality {
 public:
  struct Match {
    int steps = 0;
    double ms = 0;  // a baseline not reached: its time at kMaxSteps, a lower bound (reached: timed in rounds)
    bool reached = false, any = false;
  };
  static constexpr int kMaxSteps = 4096;

  EqualQuality(std::unique_ptr<BaselineSource> source, Progress& progress)
      : source_(std::move(source)), progress_(progress) {}
  const std::string& baseline() const { return source_->method(); }
  const std::vector<std::string>& samplings() const { return source_->samplings(); }
  std::string spec(const std::string& sampling, int sm, int steps) const { return source_->spec(sampling, sm, steps); }

  BaselineError at(const std::string& sampling, int sm, int steps);
  // The baseline's scattering time at `steps`; negative when it failed.
  double timeAt(const std::string& sampling, int sm, int steps);
  // Smallest step count whose L_s relMSE is at most `target` (doubling to a bracket, then bisection
  // in log(steps), up to kMaxSteps; the error taken as non-increasing in the step count).
  Match match(const std::string& sampling, int sm, double target);
  // The baseline's L_s RMSE at the largest step count that runs within `rowMs` (time taken as
  // increasing in the step count).
  double equalTimeLsRmse(const std::string& sampling, int sm, double rowMs);

 private:
  std::string describe(const std::string& sampling, int sm, int steps) const;

  std::unique_ptr<BaselineSource> source_;
  Progress& progress_;
  std::map<std::tuple<std::string, int, int>, BaselineError> errors_;
  std::map<std::tuple<std::string, int, int>, double> times_;
};

// The baselines a row is matched with: per sampling the matched step count, and the matched
// baseline's scattering time per round, timed right after the row in each round.
struct RowMatches {
  struct Timed {
    std::string sampling, spec;
    EqualQuality::Match match;
    std::vector<double> roundMs;
    std::optional<ResolvedSpec> resolved;  // `spec` resolved, once, by the first round that times it
  };
  std::vector<Timed> baselines;
};

// The error a row is matched on (see RunPlan::equalQualityExact); negative when it has none.
double matchedError(const Measured& m, const RunPlan& plan);

// Bisects the baseline to a successful row's error (first round); none for the baseline's own rows.
RowMatches matchRow(const Measured& m, EqualQuality& eq, const RunPlan& plan);

// Times each reached baseline of a row once more, as the rows are timed: the speedups are ratios
// of figures measured side by side in every round (a baseline never reached keeps the bisection's
// time, a lower bound). Returns this round's time per baseline of `matches` (0 for one not reached).
std::vector<double> timeMatchedBaselines(RowMatches& matches, Runner& runner, const FrameSchedule& schedule,
                                         const MethodRegistry& registry, const gl::Limits& limits, EqualQuality& eq,
                                         int sm, Progress& progress);

// Fills the equal-quality columns of a successful row from its matches and the rounds' times
// (`rowRoundMs`: the row's scattering time per round).
void addEqualQuality(ResultRow& row, const Measured& m, const RowMatches& matches, EqualQuality& eq,
                     const RunPlan& plan, const std::vector<double>& rowRoundMs);

}  // namespace vs::shootout
