// The project's method registry, and shorthands that use it for programs and tests.
#pragma once
#include "harness/method.hpp"
#include "harness/runner.hpp"

namespace vs {

// Defined in registry.cpp: one line per method.
const MethodRegistry& registeredMethods();

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
// One spec on its own runner as the benchmarks measure it: wall-clock pass timer, one warm-up frame.
inline MethodRun benchmarkSpec(const Scene& scene, const std::string& spec, const gl::Limits& limits, int width,
                               int height, int frames) {
  RunOptions options;
  options.width = width;
  options.height = height;
  options.frames = frames;
  options.warmup = 1;
  options.timer = TimerStrategy::WallClock;
  Runner runner(scene, limits, options);
  return runSpec(runner, limits, spec);
}
inline Reference obtainReference(const Scene& scene, const gl::Limits& limits, const RunOptions& options,
                                 int shadowMapSize, const std::string& cacheDir, const std::string& overrideSpec = "") {
  return obtainReference(scene, limits, options, shadowMapSize, cacheDir, registeredMethods(), overrideSpec);
}

}  // namespace vs
