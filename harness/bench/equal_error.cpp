#include "harness/bench/equal_error.hpp"

#include <algorithm>
#include <cstdio>

#include "harness/evaluation/step_search.hpp"
#include "harness/gl/timer.hpp"
#include "harness/pipeline/effects.hpp"

namespace vs {

Spread spreadOfValues(const std::vector<double>& values) {
  if (values.empty()) return {};
  auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return {medianOf(values), *lo, *hi};
}

Spread ratioSpread(const std::vector<double>& numerator, const std::vector<double>& denominator) {
  std::vector<double> ratios;
  for (size_t i = 0; i < std::min(numerator.size(), denominator.size()); ++i)
    if (denominator[i] > 0.0) ratios.push_back(numerator[i] / denominator[i]);
  return spreadOfValues(ratios);
}

std::string spreadCell(const Spread& s) {
  char text[64];
  std::snprintf(text, sizeof text, "%.1f [%.1f–%.1f]", s.median, s.lo, s.hi);
  return text;
}

std::string speedupCell(const Spread& s) {
  char text[64];
  std::snprintf(text, sizeof text, "%.2fx [%.2f–%.2f]", s.median, s.lo, s.hi);
  return text;
}

BruteForceMatcher::BruteForceMatcher(const Scene& scene, const Image& reference, const gl::Limits& limits,
                                     const MethodRegistry& registry, int width, int height, uint32_t seed,
                                     std::string sharedParams)
    : reference_(reference), limits_(limits), registry_(registry), sharedParams_(std::move(sharedParams)) {
  const Effects effects = deriveEffects(scene);
  method_ = referenceMethodFor(effects, registry).name;
  baseline_ = createMethod(registry, method_);
  for (const auto& s : baseline_->qualitySeries(effects))
    if (!baseline_->baselineParams({s.name, 1}).empty()) series_.push_back(s.name);
  RunOptions once = RunOptions::singleFrame(width, height);
  once.seed = seed;
  once.timer = TimerStrategy::WallClock;
  runner_ = std::make_unique<Runner>(scene, limits, once);
}

BruteForceMatcher::~BruteForceMatcher() = default;

std::string BruteForceMatcher::spec(const BaselinePoint& point) const {
  std::string params = baseline_->baselineParams(point);
  if (params.empty()) throw UsageError(method_ + " offers no baseline in series '" + point.series + "'");
  return method_ + ":" + params + (sharedParams_.empty() ? "" : ":" + sharedParams_);
}

ErrorMetrics BruteForceMatcher::errorAt(const BaselinePoint& point) {
  auto key = std::make_tuple(point.series, point.steps, point.lightSamples);
  auto it = errors_.find(key);
  if (it != errors_.end()) return it->second;
  ResolvedSpec resolved = resolveSpec(spec(point), limits_, registry_);
  auto method = createMethod(registry_, resolved.method);
  MethodRun run = runner_->run(*method, resolved.params);
  ErrorMetrics e;
  if (run.status == RunStatus::Success) {
    e = compareImages(run.inscatter, reference_);
  } else {  // a failed point never passes
    e.nonFinite = 1;
    e.rmse = e.relmse = 1e300;
  }
  return errors_[key] = e;
}

BaselineMatch BruteForceMatcher::finish(BaselinePoint point, bool reached) {
  BaselineMatch m;
  ErrorMetrics e = errorAt(point);
  m.point = std::move(point);
  m.spec = spec(m.point);
  m.relmse = e.relmse;
  m.rmse = e.rmse;
  m.reached = reached;
  return m;
}

BaselineMatch BruteForceMatcher::matchSteps(const std::string& series, double target, int lightSamples, int maxSteps) {
  auto passes = [&](int n) {
    ErrorMetrics e = errorAt({series, n, lightSamples});
    return e.nonFinite == 0 && e.relmse <= target;
  };
  int steps = smallestPassingSteps(passes, maxSteps, 16, kStepTolerance);
  return finish({series, steps > 0 ? steps : maxSteps, lightSamples}, steps > 0);
}

BaselineMatch BruteForceMatcher::matchLightSamples(const std::string& series, int steps, double target,
                                                   int maxLightSamples) {
  auto passes = [&](int n) {
    ErrorMetrics e = errorAt({series, steps, n});
    return e.nonFinite == 0 && e.relmse <= target;
  };
  int samples = smallestPassingSteps(passes, maxLightSamples, 8, kStepTolerance);
  return finish({series, steps, samples > 0 ? samples : maxLightSamples}, samples > 0);
}

}  // namespace vs

namespace vs {

namespace {
std::string format(const char* pattern, double v) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, v);
  return text;
}
std::string baselineCell(const BaselineMatch& m) {
  std::string text = "`" + m.spec + "`";
  return m.reached ? text : text + " (does not reach it)";
}
}  // namespace

std::string equalQualityTable(const std::vector<std::pair<std::string, EqualQualityRow>>& rows,
                              const std::string& labelHeader) {
  std::string out = "| " + labelHeader +
                    " | L_s relMSE | ms | baseline at equal relMSE | its relMSE | its ms | speed-up |\n"
                    "|---|---|---|---|---|---|---|\n";
  for (const auto& [label, row] : rows) {
    if (!row.method.ok) {
      out += "| " + label + " | failed | | | | | |\n";
      continue;
    }
    const std::string own = "| " + label + " | " + format("%.2e", row.method.relmse) + " | " +
                            spreadCell(row.timing.methodMs) + " |";
    for (size_t i = 0; i < row.matches.size(); ++i) {
      const BaselineMatch& m = row.matches[i];
      const bool timed = i < row.timing.speedup.size() && row.timing.speedup[i].median > 0.0;
      // The strongest baseline (the cheapest at equal error) in bold; a baseline that never reached
      // the error gives a lower bound.
      const std::string bold = int(i) == row.timing.cheapest ? "**" : "";
      const Spread& s = timed ? row.timing.speedup[i] : Spread{};
      // Untimed: a match that missed the error beside others that reached it.
      const bool skipped = !timed && !m.reached;
      std::string speedup = skipped ? "-" : !timed ? "failed"
                                   : bold + (m.reached ? "" : ">= ") + format("%.2fx", s.median) + bold + " [" +
                                         format("%.2f", s.lo) + "–" + format("%.2f", s.hi) + "]";
      out += (i == 0 ? own : "| | | |") + " " + baselineCell(m) + " | " + format("%.2e", m.relmse) + " | " +
             (timed ? spreadCell(row.timing.baselineMs[i]) : skipped ? "-" : "failed") + " | " + speedup + " |\n";
    }
  }
  return out;
}

}  // namespace vs
