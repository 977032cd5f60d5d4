// Randomized stress: seeded random cameras, lights and media on a small scene, every method
// checked for finite, non-negative pixels and its error against the reference.
#pragma once
#include <functional>
#include <string>

#include "harness/runner.hpp"
#include "registry.hpp"

namespace vs::testing {

// Configuration `index` of the sequence for `seed`: the same pair always gives the same scene.
Scene randomStressScene(uint32_t seed, uint32_t index);

struct StressSummary {
  std::string method;
  int tried = 0, unsupported = 0, failures = 0, nonFinite = 0, negative = 0;
  double worstRelmse = 0;      // L_s against the reference
  uint32_t worstIndex = 0;
  std::string firstFailure;    // reason of the first Failure row, if any
};

struct StressOptions {
  uint32_t seed = 1;
  int configs = 100;
  int width = 32, height = 24;
};

StressSummary runStress(const std::string& method, const StressOptions& options, const gl::Limits& limits,
                        const std::function<void(int, int)>& progress = {});

}  // namespace vs::testing
