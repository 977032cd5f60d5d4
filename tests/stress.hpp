// Randomized stress: seeded random cameras, lights and media on a small scene, every method
// checked for finite, non-negative pixels and its error against the reference.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "harness/pipeline/runner.hpp"
#include "registry.hpp"

namespace vs::testing {

// Configuration `index` of the sequence for `seed`: the same pair always gives the same scene.
Scene randomStressScene(uint32_t seed, uint32_t index);
// Its scene file (JSON), for `vshadow run --scene`: the configuration a report names, reproduced.
std::string randomStressSceneJson(uint32_t seed, uint32_t index);

struct StressSummary {
  std::string method;
  int tried = 0, unsupported = 0, failures = 0, nonFinite = 0, negative = 0;
  int throughVpls = 0;         // of `tried`: area-light configurations run behind the per-VPL wrapper
  double worstRelmse = 0;      // L_s against the reference
  uint32_t worstIndex = 0;
  std::string firstFailure;    // reason of the first Failure row (lowest config index), if any
  uint32_t firstFailureIndex = 0;
  double mostNegative = 0;     // the most negative value in any image (0: none)
  uint32_t mostNegativeIndex = 0;
  double seconds = 0;          // wall-clock time of its runs (shards: summed)

  // Adds another slice's summary of the same method (e.g. another shard's).
  void merge(const StressSummary& other);
};

// Steps of the stress's ray-marched reference at most, for a third of 4096's time: at the stress's
// 32x24, within L_s relMSE 4.3e-6 of 4096 over 150 configurations (every light type, volume data);
// 1.7e-3 in the densest haze of the 10,000 (config 9458, where 64 uniform steps are at 1.4).
constexpr int kStressReferenceSteps = 1024;
// The same for area lights, whose reference marches 64 light samples per step, each with its own
// shadow map: 256 steps took 290-450 ms a configuration, about two fifths of the reference's time over
// the 10,000. Equiangular 128 steps take 190-300 ms and are within L_s relMSE 8.9e-7 of 4096 on config
// 1152, ivsv's worst (ivsv: 1.7e-3 there; 1.63e-3 against 128 steps, 1.45e-3 against 64), and at
// least 120x below ivsv's error on the first 13 area-light configurations of seed 1, where 64 steps
// are only 29x below (`scripts/stress-reference-check --area`).
constexpr int kStressAreaReferenceSteps = 128;
// Shadow-map size of every method in the stress, and of the reference (area lights: every light sample's);
// the most texels per side of a method's own maps (its "res").
constexpr int kStressShadowMap = 256;

// Virtual point lights of the per-VPL wrapper when a point-light method meets an area light, as
// the shootout runs it: 16 on the hard cases (the tests and the report's cells); 4 in the stress,
// which checks finiteness over a thousand area-light configurations: at 32x24 a wrapped run costs
// about 11 ms per VPL (minmax: 175 ms a frame at 16), and 16 tripled the stress's time.
constexpr int kHardCaseVpls = 16;
constexpr int kStressVpls = 4;

struct StressOptions {
  uint32_t seed = 1;
  int configs = 100;
  int width = 32, height = 24;
  // Shard `shard` of `shards`: the configurations whose index modulo `shards` is `shard`.
  int shard = 0, shards = 1;
};

// Every method on each configuration of the options' slice, in turn; the reference is rendered once
// per configuration for all of them, its wall-clock time added to *referenceSeconds if given.
// progress(done, total) counts configurations.
std::vector<StressSummary> runStress(const std::vector<std::string>& methods, const StressOptions& options,
                                     const gl::Limits& limits, const std::function<void(int, int)>& progress = {},
                                     double* referenceSeconds = nullptr);
inline StressSummary runStress(const std::string& method, const StressOptions& options, const gl::Limits& limits,
                               const std::function<void(int, int)>& progress = {}) {
  return runStress(std::vector<std::string>{method}, options, limits, progress).front();
}

}  // namespace vs::testing
