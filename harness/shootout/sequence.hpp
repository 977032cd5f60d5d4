// A moving scene's rows: the first round's measured frames, each compared with the reference of
// its own time. Takes the frames' L_s, gives per-frame errors and their summary with the temporal
// error between consecutive frames.
#pragma once
#include <cstdint>
#include <map>
#include <vector>

#include "harness/cli/progress.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/runner.hpp"
#include "harness/shootout/baselines.hpp"

namespace vs::shootout {

struct SequenceMetrics {
  bool measured = false;
  int frames = 0;
  double rmseMean = 0, rmseMax = 0, relmseMean = 0, relmseMax = 0;
  TemporalError temporal;
  std::vector<ErrorMetrics> perFrame;
};

// The errors of `frames` against `references` (alike in number and order).
SequenceMetrics sequenceMetrics(const std::vector<const Image*>& frames, const std::vector<const Image*>& references);

// The reference's L_s for the scene at a frame's time, rendered when first asked for (and cached on
// disk per time): the ray march, or with --reference exact the exact-visibility ground truth of
// that time. The compared frame's is the run's reference.
class FrameReferences {
 public:
  FrameReferences(const RunRequest& req, const RunPlan& plan, const Baselines& base, const gl::Limits& limits,
                  const MethodRegistry& registry, const RunOptions& options, Progress& progress)
      : req_(req), plan_(plan), base_(base), limits_(limits), registry_(registry), options_(options),
        progress_(progress) {}
  const Image& at(uint32_t frameIndex);

 private:
  const RunRequest& req_;
  const RunPlan& plan_;
  const Baselines& base_;
  const gl::Limits& limits_;
  const MethodRegistry& registry_;
  RunOptions options_;
  Progress& progress_;
  std::map<double, Image> byTime_;
};

}  // namespace vs::shootout
