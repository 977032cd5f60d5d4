// The project's method registry, and shorthands that use it for programs and tests.
#pragma once
#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "harness/bench/benchmark_kit.hpp"
#include "harness/evaluation/metrics.hpp"
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
// One row of a benchmark table: a timed run, its scattering time and its L_s error.
struct Measured {
  MethodRun run;
  double scatterMs = 0;  // the table's scattering time (MethodRun::scatterMs unless the table says otherwise)
  double rmse = 0, relmse = 0;  // L_s against the reference (0 without one)
  bool ok = false;              // the run succeeded
};
using ScatterTime = std::function<double(const MethodRun&)>;
// A run that did not succeed prints its reason as a quoted Markdown line.
inline Measured measured(MethodRun run, const std::string& spec, const Image* reference, const ScatterTime& scatter) {
  Measured m;
  m.run = std::move(run);
  if (m.run.status != RunStatus::Success) {
    std::printf("\n> %s: %s\n\n", spec.c_str(), m.run.reason.c_str());
    std::fflush(stdout);
    return m;
  }
  m.ok = true;
  m.scatterMs = scatter ? scatter(m.run) : m.run.scatterMs();
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
                        int frames, const Image* reference, const ScatterTime& scatter = {}) {
  return measured(benchmarkSpec(scene, spec, limits, width, height, frames), spec, reference, scatter);
}
// One untimed frame on a shared runner (the points of an equal-error search, whose errors are what
// counts); its images are dropped once the error is taken.
inline Measured measureOnce(Runner& runner, const std::string& spec, const gl::Limits& limits, const Image& reference,
                            const ScatterTime& scatter = {}) {
  Measured m = measured(runSpec(runner, limits, spec), spec, &reference, scatter);
  m.run.inscatter = Image();
  m.run.final = Image();
  return m;
}
// A figure measured in several rounds: the median of the rounds and their range.
struct Spread {
  double median = 0, lo = 0, hi = 0;
};
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
inline Spread spreadOfValues(const std::vector<double>& v) {
  if (v.empty()) return {};
  auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return {medianOf(v), *lo, *hi};
}
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
// "12.3 [11.9–13.0]": a spread as a table cell.
inline std::string spreadCell(const Spread& s) {
  char text[64];
  std::snprintf(text, sizeof text, "%.1f [%.1f–%.1f]", s.median, s.lo, s.hi);
  return text;
}
inline Reference obtainReference(const Scene& scene, const gl::Limits& limits, const RunOptions& options,
                                 int shadowMapSize, const std::string& cacheDir, const std::string& overrideSpec = "") {
  return obtainReference(scene, limits, options, shadowMapSize, cacheDir, registeredMethods(), overrideSpec);
}

}  // namespace vs
