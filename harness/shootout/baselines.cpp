#include "harness/shootout/baselines.hpp"

#include <algorithm>

#include "harness/evaluation/metrics.hpp"
#include "harness/io/results.hpp"

namespace vs::shootout {

std::string cacheDirOf(const RunRequest& req) { return req.cacheDir.empty() ? defaultCacheDir() : req.cacheDir; }

GroundTruthOptions groundTruthOptions(const RunRequest& req, const RunPlan& plan, const RunOptions& options) {
  GroundTruthOptions gt;
  gt.width = plan.width;
  gt.height = plan.height;
  gt.steps = req.exactSteps;
  gt.seed = options.seed;
  return gt;
}

namespace {

std::string origin(bool fromCache, double computeMs) {
  return fromCache ? std::string("from cache") : "computed in " + num(computeMs / 1000.0) + " s";
}

GroundTruth prepareGroundTruth(const RunRequest& req, const RunPlan& plan, const RunOptions& options,
                               Progress& progress, int item, nlohmann::json& meta) {
  progress.item(item, "exact-visibility ground truth");
  GroundTruth exact = obtainGroundTruth(plan.stillScene(), groundTruthOptions(req, plan, options), cacheDirOf(req),
                                        [&](int done, int total) { progress.frames(done, total); });
  progress.finished(origin(exact.fromCache, exact.computeMs) + " (" + std::to_string(req.exactSteps) +
                    " steps per ray, Embree visibility)");
  meta["exact"] = {{"steps", req.exactSteps},      {"compute_ms", exact.computeMs},
                   {"from_cache", exact.fromCache}, {"cache_key", exact.cacheKey},
                   {"cache_path", exact.cachePath}};
  return exact;
}

Reference referenceFromGroundTruth(const RunRequest& req, const GroundTruth& exact, nlohmann::json& meta) {
  Reference ref;
  ref.method = "exact";
  ref.params = "steps=" + std::to_string(req.exactSteps);
  ref.computeMs = exact.computeMs;
  ref.inscatter = exact.inscatter;
  ref.final = exact.final;
  meta["reference"] = {{"method", ref.method}, {"params", ref.params}, {"compute_ms", ref.computeMs}};
  return ref;
}

Reference rayMarchedReference(const RunRequest& req, const RunPlan& plan, const gl::Limits& limits,
                              const MethodRegistry& registry, const RunOptions& options, Progress& progress, int item,
                              int shadowMap, nlohmann::json& meta) {
  progress.item(item, "reference");
  Reference ref =
      obtainReference(plan.stillScene(), limits, options, shadowMap, cacheDirOf(req), registry, req.referenceSpec);
  progress.finished(ref.method + " " + ref.params + " (" + origin(ref.fromCache, ref.computeMs) + ")");
  meta["reference"] = {{"method", ref.method},       {"params", ref.params},
                       {"cache_key", ref.cacheKey},  {"cache_path", ref.cachePath},
                       {"from_cache", ref.fromCache}, {"compute_ms", ref.computeMs}};
  return ref;
}

}  // namespace

Baselines prepareBaselines(const RunRequest& req, const RunPlan& plan, const gl::Limits& limits,
                           const MethodRegistry& registry, const RunOptions& options, Progress& progress, int& item,
                           nlohmann::json& meta) {
  Baselines base;
  if (plan.haveExact) {
    base.exact = prepareGroundTruth(req, plan, options, progress, item, meta);
    if (!plan.exactReference) ++item;
  }
  if (!plan.haveReference) return base;
  if (plan.exactReference) {
    base.reference = referenceFromGroundTruth(req, base.exact, meta);
  } else {
    int sm = 0;
    for (const auto& j : plan.jobs) sm = std::max(sm, j.params.getInt("sm"));
    base.referenceShadowMap = std::max(sm, 64);
    base.reference =
        rayMarchedReference(req, plan, limits, registry, options, progress, item, base.referenceShadowMap, meta);
  }
  ++item;
  const Reference& ref = base.reference;
  base.referenceLabel = ref.method + ":" + ref.params;
  base.exposure = autoExposure(ref.final);
  base.inscatterExposure = autoExposure(ref.inscatter);
  return base;
}

}  // namespace vs::shootout
