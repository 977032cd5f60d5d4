#include "harness/shootout/equal_quality.hpp"

#include <algorithm>

#include "harness/evaluation/metrics.hpp"
#include "harness/evaluation/step_search.hpp"

namespace vs::shootout {

RenderedBaseline::RenderedBaseline(const RunPlan& plan, const gl::Limits& limits, const MethodRegistry& registry,
                                   const RunOptions& options, const Image& truth, Runner& scene, Runner& still)
    : limits_(limits), registry_(registry), truth_(truth), sceneRunner_(scene), stillRunner_(still) {
  timed_ = FrameSchedule::of(options);
  timed_.workCounters = timed_.sequence = false;
  timed_.frames = std::min(options.frames, 2);
  timed_.warmup = 1;
  once_ = timed_;
  once_.frames = 1;
  once_.warmup = 0;
  once_.minTimeMs = 0;
  method_ = referenceMethodFor(plan.effects, registry).name;
  baselineMethod_ = createMethod(registry, method_);
  // The samplings it is matched with: the reference method's ladder series that it offers as
  // brute-force baselines (raymarch: uniform, the papers', and equiangular, the strong one, for
  // point and spot lights).
  for (const auto& series : baselineMethod_->qualitySeries(plan.effects))
    if (!baselineMethod_->baselineParams({series.name, 1}).empty()) samplings_.push_back(series.name);
}

std::string RenderedBaseline::spec(const std::string& sampling, int sm, int steps) const {
  return method_ + ":" + baselineMethod_->baselineParams({sampling, steps}) + ":sm=" + std::to_string(sm);
}

BaselineError RenderedBaseline::error(const std::string& sampling, int sm, int steps) {
  MethodRun r = run(stillRunner_, once_, sampling, sm, steps);
  BaselineError p;
  if (r.status == RunStatus::Success) {
    p.ok = true;
    ErrorMetrics e = compareImages(r.inscatter, truth_);
    p.lsRmse = e.rmse;
    p.lsRelmse = e.relmse;
  }
  return p;
}

double RenderedBaseline::time(const std::string& sampling, int sm, int steps) {
  MethodRun r = run(sceneRunner_, timed_, sampling, sm, steps);
  return r.status == RunStatus::Success ? r.scatterMs() : -1.0;
}

const ResolvedSpec& RenderedBaseline::resolved(const std::string& sampling, int sm, int steps) {
  auto key = std::make_tuple(sampling, sm, steps);
  auto it = resolved_.find(key);
  if (it == resolved_.end()) it = resolved_.emplace(key, resolveSpec(spec(sampling, sm, steps), limits_, registry_)).first;
  return it->second;
}

MethodRun RenderedBaseline::run(Runner& runner, const FrameSchedule& schedule, const std::string& sampling, int sm,
                                int steps) {
  const ResolvedSpec& spec = resolved(sampling, sm, steps);
  auto method = createMethod(registry_, method_);
  return runner.run(*method, spec.params, schedule);
}

std::string EqualQuality::describe(const std::string& sampling, int sm, int steps) const {
  return "equal quality: " + baseline() + " " + sampling + " steps=" + std::to_string(steps) +
         " sm=" + std::to_string(sm);
}

BaselineError EqualQuality::at(const std::string& sampling, int sm, int steps) {
  auto key = std::make_tuple(sampling, sm, steps);
  auto it = errors_.find(key);
  if (it != errors_.end()) return it->second;
  progress_.note(describe(sampling, sm, steps));
  return errors_[key] = source_->error(sampling, sm, steps);
}

double EqualQuality::timeAt(const std::string& sampling, int sm, int steps) {
  auto key = std::make_tuple(sampling, sm, steps);
  auto it = times_.find(key);
  if (it != times_.end()) return it->second;
  progress_.note(describe(sampling, sm, steps) + ", its time");
  return times_[key] = source_->time(sampling, sm, steps);
}

EqualQuality::Match EqualQuality::match(const std::string& sampling, int sm, double target) {
  Match m;
  int steps = smallestPassingSteps(
      [&](int n) {
        BaselineError p = at(sampling, sm, n);
        return p.ok && p.lsRelmse <= target;
      },
      kMaxSteps, 16, kStepTolerance);
  if (steps > 0) {
    m.any = m.reached = true;
    m.steps = steps;
    return m;
  }
  BaselineError top = at(sampling, sm, kMaxSteps);  // evaluated last by the search
  double topMs = top.ok ? timeAt(sampling, sm, kMaxSteps) : -1.0;
  if (topMs < 0.0) return m;
  m.any = true;
  m.steps = kMaxSteps;  // not reached: the time is a lower bound
  m.ms = topMs;
  return m;
}

double EqualQuality::equalTimeLsRmse(const std::string& sampling, int sm, double rowMs) {
  int over = smallestPassingSteps([&](int n) { return timeAt(sampling, sm, n) > rowMs; }, kMaxSteps, 16,
                                  kStepTolerance);
  return at(sampling, sm, over == 0 ? kMaxSteps : std::max(over - 1, 1)).lsRmse;
}

double matchedError(const Measured& m, const RunPlan& plan) {
  if (!m.measured || (plan.equalQualityExact && !m.exactMeasured)) return -1.0;
  return plan.equalQualityExact ? m.exactLsErr.relmse : m.lsErr.relmse;
}

RowMatches matchRow(const Measured& m, EqualQuality& eq, const RunPlan& plan) {
  RowMatches out;
  const MethodRun& r = m.run;
  double target = matchedError(m, plan);
  if (r.status != RunStatus::Success || target < 0.0 || r.method == eq.baseline() || eq.baseline().empty()) return out;
  for (const std::string& sampling : eq.samplings()) {
    EqualQuality::Match match = eq.match(sampling, r.shadowMapSize, target);
    if (match.any) out.baselines.push_back({sampling, eq.spec(sampling, r.shadowMapSize, match.steps), match, {}});
  }
  return out;
}

std::vector<double> timeMatchedBaselines(RowMatches& matches, Runner& runner, const FrameSchedule& schedule,
                                         const MethodRegistry& registry, const gl::Limits& limits, EqualQuality& eq,
                                         int sm, Progress& progress) {
  std::vector<double> ms;
  for (auto& b : matches.baselines) {
    if (!b.match.reached) {
      ms.push_back(0.0);
      continue;
    }
    progress.note("equal quality: timing " + b.spec);
    if (!b.resolved) b.resolved = resolveSpec(b.spec, limits, registry);
    auto method = createMethod(registry, b.resolved->method);
    MethodRun run = runner.run(*method, b.resolved->params, schedule);
    // A round whose run failed keeps the rounds aligned with the search's own timing of the match.
    ms.push_back(run.status == RunStatus::Success ? run.scatterMs()
                                                  : std::max(eq.timeAt(b.sampling, sm, b.match.steps), 0.0));
  }
  return ms;
}

namespace {

// The columns of one matched baseline whose time was measured in rounds beside the row's: the
// median time and speedup over the rounds and their ranges. Updates `baseMs` and `speedup`.
void setRoundColumns(ResultRow& row, const RowMatches::Timed& b, const std::vector<double>& rowRoundMs,
                     double& baseMs, double& speedup) {
  const std::string& sampling = b.sampling;
  std::vector<double> ratios;
  for (size_t k = 0; k < std::min(b.roundMs.size(), rowRoundMs.size()); ++k)
    ratios.push_back(rowRoundMs[k] > 0.0 ? b.roundMs[k] / rowRoundMs[k] : 0.0);
  baseMs = medianOf(b.roundMs);
  speedup = ratios.empty() ? speedup : medianOf(ratios);
  row.set("eq_" + sampling + "_round_min_ms", *std::min_element(b.roundMs.begin(), b.roundMs.end()));
  row.set("eq_" + sampling + "_round_max_ms", *std::max_element(b.roundMs.begin(), b.roundMs.end()));
  if (!ratios.empty()) {
    row.set("speedup_eq_" + sampling + "_round_min", *std::min_element(ratios.begin(), ratios.end()));
    row.set("speedup_eq_" + sampling + "_round_max", *std::max_element(ratios.begin(), ratios.end()));
  }
}

}  // namespace

void addEqualQuality(ResultRow& row, const Measured& m, const RowMatches& matches, EqualQuality& eq,
                     const RunPlan& plan, const std::vector<double>& rowRoundMs) {
  if (matches.baselines.empty()) return;
  const MethodRun& r = m.run;
  const double ms = r.scatterMs();  // the row's scatter_ms (the median over the rounds)
  row.set("eq_error_against", plan.equalQualityExact ? "exact" : "reference (" + plan.equalQualityNote + ")");
  for (const auto& b : matches.baselines) {
    const std::string& sampling = b.sampling;
    double baseMs = b.match.ms, speedup = ms > 0.0 ? b.match.ms / ms : 0.0;
    if (!b.roundMs.empty()) setRoundColumns(row, b, rowRoundMs, baseMs, speedup);
    // A baseline that never reaches the row's error within kMaxSteps gives a lower bound: ">=".
    const std::string bound = b.match.reached ? "" : ">=";
    row.set("eq_" + sampling + "_steps", bound + std::to_string(b.match.steps));
    row.set("eq_" + sampling + "_ms", bound + num(baseMs));
    row.set("speedup_eq_" + sampling, bound + num(speedup));
    // At the row's final time, the median over the rounds.
    row.set("equal_time_ls_rmse_" + sampling, eq.equalTimeLsRmse(sampling, r.shadowMapSize, ms));
  }
}

}  // namespace vs::shootout
