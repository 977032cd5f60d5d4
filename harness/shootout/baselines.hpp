// The baselines stage: takes the plan, gives the images rows are measured against, the reference
// (a cached ray march, or the ground truth with --reference exact) and, where the plan asks for it,
// the exact-visibility ground truth. Needs a GL context for the ray-marched reference.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "harness/cli/progress.hpp"
#include "harness/evaluation/ground_truth.hpp"
#include "harness/pipeline/runner.hpp"
#include "harness/shootout/plan.hpp"

namespace vs::shootout {

struct Baselines {
  Reference reference;  // valid when plan.haveReference
  GroundTruth exact;    // valid when plan.haveExact
  std::string referenceLabel;
  float exposure = 1.0f;            // of the final image L
  float inscatterExposure = 1.0f;   // of L_s alone (a moving scene's frame images)
  int referenceShadowMap = 64;  // the shadow-map size the reference was rendered with
};

// The reference cache of the request: --cache, else defaultCacheDir().
std::string cacheDirOf(const RunRequest& req);

// How the exact-visibility ground truth of a run is rendered (every frame's alike).
GroundTruthOptions groundTruthOptions(const RunRequest& req, const RunPlan& plan, const RunOptions& options);

// Renders or reads from the cache what the plan needs, each as one progress item from `item` on
// (advanced past them), and records them in meta.json's "exact" and "reference".
Baselines prepareBaselines(const RunRequest& req, const RunPlan& plan, const gl::Limits& limits,
                           const MethodRegistry& registry, const RunOptions& options, Progress& progress, int& item,
                           nlohmann::json& meta);

}  // namespace vs::shootout
