// The project's method registry, and shorthands that use it for programs and tests.
#pragma once
#include <algorithm>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "harness/bench/benchmark_kit.hpp"
#include "harness/bench/equal_error.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/evaluation/step_search.hpp"
#include "harness/pipeline/method.hpp"
#include "harness/pipeline/runner.hpp"

namespace vs {

// Every method linked into the program, in listing order (the order of `vshadow list`, of the
// default shootout's rows and of the stress). A method adds itself from its own .cpp:
//   VS_REGISTER_METHOD(MyMethod, 70);
// the number is its listing position (raymarch, the reference, is 0; the papers' methods follow in
// tens). Programs link vs_methods, which keeps every method's object file although nothing calls
// into it by name (methods/CMakeLists.txt).
const MethodRegistry& registeredMethods();

struct MethodRegistration {
  MethodRegistration(int position, std::function<std::unique_ptr<Method>()> create);
};
#define VS_REGISTER_METHOD(Type, position)                 \
  static const ::vs::MethodRegistration vsRegistration##Type( \
      position, [] { return std::unique_ptr<::vs::Method>(std::make_unique<Type>()); })

inline std::unique_ptr<Method> createMethod(const std::string& name) { return createMethod(registeredMethods(), name); }
inline ResolvedSpec resolveSpec(const std::string& spec, const gl::Limits& limits) {
  return resolveSpec(spec, limits, registeredMethods());
}
// Runs one method spec on a runner's scene (benchmarks and tools).
inline MethodRun runSpec(Runner& runner, const gl::Limits& limits, const std::string& spec) {
  ResolvedSpec r = resolveSpec(spec, limits);
  auto method = createMethod(r.method);
  return runner.run(*method, r.params);
}
// A timed run of a spec on a runner: inside a benchmark session (harness/bench/benchmark_kit.hpp) it is
// bracketed by the session's calibration and repeated when the machine's speed moved meanwhile.
inline MethodRun timedRunSpec(Runner& runner, const gl::Limits& limits, const std::string& spec) {
  BenchmarkSession* session = BenchmarkSession::current();
  if (!session) return runSpec(runner, limits, spec);
  MethodRun run;
  session->recordRun(session->drift().run([&](int) {
    run = runSpec(runner, limits, spec);
    return run.status == RunStatus::Success;
  }));
  return run;
}
// The benchmarks measure as many of their frames as fill this long at the warm-up frame's time
// (RunOptions::minTimeMs): a run of a second or more measures one frame per round.
constexpr double kBenchmarkMinTimeMs = 400;
// "medians of up to 3 frames (...) after 1 warm-up": how benchmarkSpec measures, for their headers.
inline std::string benchmarkFramesNote(int frames) {
  if (frames <= 1) return "1 frame after 1 warm-up";
  return "medians of up to " + std::to_string(frames) + " frames after 1 warm-up (as many as fill " +
         std::to_string(int(kBenchmarkMinTimeMs)) + " ms at the warm-up frame's time)";
}
// One spec on its own runner as the benchmarks measure it: wall-clock pass timer, one warm-up frame.
// frames 0: one frame without a warm-up, for runs whose images are all that is kept (references,
// the errors of a step search).
inline MethodRun benchmarkSpec(const Scene& scene, const std::string& spec, const gl::Limits& limits, int width,
                               int height, int frames) {
  RunOptions options;
  options.width = width;
  options.height = height;
  options.frames = std::max(frames, 1);
  options.warmup = frames > 0 ? 1 : 0;
  options.minTimeMs = kBenchmarkMinTimeMs;
  options.timer = TimerStrategy::WallClock;
  if (const BenchmarkSession* session = BenchmarkSession::current()) options.seed = session->seed();
  Runner runner(scene, limits, options);
  return frames > 0 ? timedRunSpec(runner, limits, spec) : runSpec(runner, limits, spec);
}
// A run that did not succeed prints its reason as a quoted Markdown line.
inline Measured measured(MethodRun run, const std::string& spec, const Image* reference) {
  Measured m;
  m.run = std::move(run);
  if (m.run.status != RunStatus::Success) {
    std::printf("\n> %s: %s\n\n", spec.c_str(), m.run.reason.c_str());
    std::fflush(stdout);
    return m;
  }
  m.ok = true;
  m.scatterMs = m.run.scatterMs();
  if (reference) {
    ErrorMetrics e = compareImages(m.run.inscatter, *reference);
    m.rmse = e.rmse;
    m.relmse = e.relmse;
  }
  std::fflush(stdout);
  return m;
}
// benchmarkSpec as a table row.
inline Measured measure(const Scene& scene, const std::string& spec, const gl::Limits& limits, int width, int height,
                        int frames, const Image* reference) {
  return measured(benchmarkSpec(scene, spec, limits, width, height, frames), spec, reference);
}
// One untimed frame on a shared runner (the points of an equal-error search, whose errors are what
// counts); its images are dropped once the error is taken.
inline Measured measureOnce(Runner& runner, const std::string& spec, const gl::Limits& limits, const Image& reference) {
  Measured m = measured(runSpec(runner, limits, spec), spec, &reference);
  m.run.inscatter = Image();
  m.run.final = Image();
  return m;
}
// Runs every spec `rounds` times in turn (A B C, A B C, ...) so that each sees the same machine
// and no row pays for being first; per spec its successful runs in round order.
inline std::vector<std::vector<MethodRun>> runInterleaved(const Scene& scene, const std::vector<std::string>& specs,
                                                          const gl::Limits& limits, int width, int height, int frames,
                                                          int rounds) {
  std::vector<std::vector<MethodRun>> runs(specs.size());
  for (int round = 0; round < rounds; ++round)
    for (size_t i = 0; i < specs.size(); ++i) {
      MethodRun run = benchmarkSpec(scene, specs[i], limits, width, height, frames);
      run.inscatter = Image();  // the timings are what is kept
      run.final = Image();
      if (run.status == RunStatus::Success) runs[i].push_back(std::move(run));
    }
  return runs;
}
// The spread of figure(run) over the runs of one spec (zeros without any).
inline Spread spreadOf(const std::vector<MethodRun>& runs, const std::function<double(const MethodRun&)>& figure) {
  std::vector<double> v;
  for (const MethodRun& run : runs) v.push_back(figure(run));
  return spreadOfValues(v);
}
inline std::vector<Spread> measureInterleaved(const Scene& scene, const std::vector<std::string>& specs,
                                              const gl::Limits& limits, int width, int height, int frames, int rounds,
                                              const std::function<double(const MethodRun&)>& figure) {
  std::vector<Spread> out;
  for (const auto& runs : runInterleaved(scene, specs, limits, width, height, frames, rounds))
    out.push_back(spreadOf(runs, figure));
  return out;
}
// A method against brute force at equal L_s error, timed: the method and every candidate baseline
// run in interleaved rounds (A B C, A B C, ...), so each speed-up is the median of per-round ratios
// of the baseline's time to the method's, with their range.
inline EqualQualityTiming timeAgainstBaselines(const Scene& scene, const std::string& methodSpec,
                                               const std::vector<std::string>& baselineSpecs, const gl::Limits& limits,
                                               int width, int height, int frames, int rounds) {
  std::vector<std::string> specs = {methodSpec};
  specs.insert(specs.end(), baselineSpecs.begin(), baselineSpecs.end());
  auto runs = runInterleaved(scene, specs, limits, width, height, frames, rounds);
  auto times = [&](const std::vector<MethodRun>& r) {
    std::vector<double> ms;
    for (const MethodRun& run : r) ms.push_back(run.scatterMs());
    return ms;
  };
  EqualQualityTiming t;
  const std::vector<double> own = times(runs[0]);
  t.methodMs = spreadOfValues(own);
  for (size_t i = 1; i < runs.size(); ++i) {
    const bool complete = runs[i].size() == size_t(rounds) && own.size() == size_t(rounds);
    t.baselineMs.push_back(complete ? spreadOfValues(times(runs[i])) : Spread{});
    t.speedup.push_back(complete ? ratioSpread(times(runs[i]), own) : Spread{});
    if (complete && (t.cheapest < 0 || t.baselineMs.back().median < t.baselineMs[size_t(t.cheapest)].median))
      t.cheapest = int(i - 1);
  }
  return t;
}
// The reference method's spec for a scene (Method::referenceParams), with shared parameters
// ("sm=1024") appended: the benchmarks' references.
inline std::string referenceSpec(const Scene& scene, const std::string& shared = "", const ReferenceBudget& budget = {}) {
  ReferenceMethod m = referenceMethodFor(deriveEffects(scene), registeredMethods(), budget);
  return m.name + ":" + m.params + (shared.empty() ? "" : ":" + shared);
}
// The reference method as brute force at one baseline point on a scene, with shared parameters.
inline std::string baselineSpec(const Scene& scene, const BaselinePoint& point, const std::string& shared = "") {
  ReferenceMethod m = referenceMethodFor(deriveEffects(scene), registeredMethods());
  std::string params = createMethod(m.name)->baselineParams(point);
  if (params.empty()) throw UsageError(m.name + " offers no baseline in series '" + point.series + "'");
  return m.name + ":" + params + (shared.empty() ? "" : ":" + shared);
}
// Which baselines a row is matched with: by default each series the reference method offers at
// the method's error (matchSteps); a benchmark may match on light samples instead.
using MatchBaselines = std::function<std::vector<BaselineMatch>(BruteForceMatcher&, double target)>;
inline std::vector<BaselineMatch> matchEverySeries(BruteForceMatcher& matcher, double target) {
  std::vector<BaselineMatch> matches;
  for (const std::string& series : matcher.series()) matches.push_back(matcher.matchSteps(series, target));
  return matches;
}
struct EqualQualitySetup {
  int width = 0, height = 0, frames = 3, rounds = 3;
  std::string shared;  // parameters every spec of the row gets ("sm=1024")
  MatchBaselines match = matchEverySeries;
};
inline EqualQualityRow equalQualityRow(const Scene& scene, const std::string& spec, const Image& reference,
                                       const gl::Limits& limits, const EqualQualitySetup& setup) {
  EqualQualityRow row;
  row.spec = spec;
  row.method = measure(scene, spec, limits, setup.width, setup.height, 0, &reference);
  if (!row.method.ok) return row;
  const uint32_t seed = BenchmarkSession::current() ? BenchmarkSession::current()->seed() : 1;
  BruteForceMatcher matcher(scene, reference, limits, registeredMethods(), setup.width, setup.height, seed, setup.shared);
  row.matches = setup.match(matcher, row.method.relmse);
  // The matches that reach the error are timed; where none does, all of them (lower bounds). The
  // others keep their line untimed, so every row of a table has as many lines in every process.
  const bool anyReached = std::any_of(row.matches.begin(), row.matches.end(), [](auto& m) { return m.reached; });
  std::vector<std::string> specs;
  std::vector<size_t> timed;
  for (size_t i = 0; i < row.matches.size(); ++i)
    if (row.matches[i].reached || !anyReached) {
      specs.push_back(row.matches[i].spec);
      timed.push_back(i);
    }
  EqualQualityTiming t = timeAgainstBaselines(scene, spec, specs, limits, setup.width, setup.height, setup.frames,
                                              setup.rounds);
  row.timing.methodMs = t.methodMs;
  row.timing.baselineMs.assign(row.matches.size(), Spread{});
  row.timing.speedup.assign(row.matches.size(), Spread{});
  for (size_t k = 0; k < timed.size(); ++k) {
    row.timing.baselineMs[timed[k]] = t.baselineMs[k];
    row.timing.speedup[timed[k]] = t.speedup[k];
  }
  row.timing.cheapest = t.cheapest < 0 ? -1 : int(timed[size_t(t.cheapest)]);
  return row;
}
// Equal time: the most steps n in [1, most] whose scattering time stays within `budgetMs` (time
// taken as increasing in n), by the step search, each point timed once; n and its timed run.
inline std::pair<int, Measured> equalTimeBaseline(const Scene& scene, const std::function<std::string(int)>& specAt,
                                                  double budgetMs, const Image& reference, const gl::Limits& limits,
                                                  int width, int height, int frames, int most = 4096) {
  std::map<int, Measured> tried;
  auto at = [&](int n) -> const Measured& {
    auto it = tried.find(n);
    if (it == tried.end()) it = tried.emplace(n, measure(scene, specAt(n), limits, width, height, frames, &reference)).first;
    return it->second;
  };
  smallestPassingSteps([&](int n) { return !at(n).ok || at(n).scatterMs > budgetMs; }, most, 16, kStepTolerance);
  int n = 1;  // the largest point tried that fits (the search narrows to within kStepTolerance)
  for (const auto& [steps, m] : tried)
    if (m.ok && m.scatterMs <= budgetMs) n = std::max(n, steps);
  return {n, at(n)};
}
inline Reference obtainReference(const Scene& scene, const gl::Limits& limits, const RunOptions& options,
                                 int shadowMapSize, const std::string& cacheDir, const std::string& overrideSpec = "") {
  return obtainReference(scene, limits, options, shadowMapSize, cacheDir, registeredMethods(), overrideSpec);
}

}  // namespace vs
