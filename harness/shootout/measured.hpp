// One job measured once: takes a job and the baselines, gives its run with its error metrics
// against the reference and the ground truth (what every later stage reads).
#pragma once
#include "harness/cli/progress.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/runner.hpp"
#include "harness/shootout/baselines.hpp"
#include "harness/shootout/plan.hpp"

namespace vs::shootout {

struct Measured {
  MethodRun run;
  ErrorMetrics finalErr, lsErr, exactErr, exactLsErr;
  bool measured = false, exactMeasured = false;  // the errors against the reference, the ground truth
};

// Runs `job` through `runner` and compares a successful run's images with the plan's baselines.
Measured measureJob(Runner& runner, const Job& job, const MethodRegistry& registry, const RunPlan& plan,
                    const Baselines& base, Progress& progress);

}  // namespace vs::shootout
