#include "harness/shootout/plan.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "harness/evaluation/ground_truth.hpp"
#include "harness/pipeline/frame.hpp"
#include "harness/pipeline/runner.hpp"

namespace vs::shootout {

std::vector<size_t> pickRungs(const std::vector<std::string>& rungs, size_t size) {
  std::vector<bool> picked(size, rungs.empty());
  for (const std::string& rung : rungs) {
    if (rung == "all") {
      picked.assign(size, true);
    } else if (rung == "first" || rung == "middle" || rung == "last") {
      if (size > 0) picked[rung == "first" ? 0 : rung == "middle" ? size / 2 : size - 1] = true;
    } else if (!rung.empty() && rung.size() < 6 && std::all_of(rung.begin(), rung.end(), [](char c) { return std::isdigit(uint8_t(c)) != 0; })) {
      if (size_t(std::stoul(rung)) < size) picked[std::stoul(rung)] = true;
    } else {
      throw UsageError("--rungs: '" + rung + "' is not all, first, middle, last or a rung index (0, 1, ...)");
    }
  }
  std::vector<size_t> out;
  for (size_t i = 0; i < size; ++i)
    if (picked[i]) out.push_back(i);
  return out;
}

RunPlan planBeforeContext(const RunRequest& req, bool shootout, const MethodRegistry& registry) {
  RunPlan plan;
  parseSize(req.size, plan.width, plan.height);
  plan.scene = loadSceneMeasured(req.scene, plan.sceneLoad);
  for (const std::string& warning : plan.scene.warnings) std::fprintf(stderr, "vshadow: warning: %s\n", warning.c_str());
  plan.effects = deriveEffects(plan.scene);
  // A moving scene is compared at the time of the last frame, the one whose images are read back.
  plan.comparedFrame = uint32_t(req.warmup + req.frames - 1);
  if (plan.scene.animation.moves()) plan.movedScene = sceneAt(plan.scene, plan.scene.animation.timeOf(plan.comparedFrame));
  for (const auto& spec : req.methods) createMethod(registry, shootout ? spec : parseMethodSpec(spec).method);
  pickRungs(req.rungs, 0);  // the words are valid
  if (req.minTimeMs > 0.0 && req.warmup < 1) throw UsageError("--min-time needs --warmup of at least 1: the warm-up frame's time sizes the run");
  plan.exactReference = req.referenceSpec == "exact";
  plan.haveExact = req.exact || plan.exactReference;
  plan.haveReference = !req.noReference;
  if (plan.haveExact && !groundTruthUnsupported(plan.scene).empty()) throw UsageError(groundTruthUnsupported(plan.scene));
  if (req.equalQuality && plan.haveReference && plan.effects.scattering) {
    plan.equalQualityNote = groundTruthUnsupported(plan.scene);
    plan.equalQualityExact = plan.equalQualityNote.empty();
    plan.haveExact = plan.haveExact || plan.equalQualityExact;
  }
  if (!plan.exactReference && !req.referenceSpec.empty())
    createMethod(registry, parseMethodSpec(req.referenceSpec).method);
  return plan;
}

namespace {

void checkLimits(const RunPlan& plan, const RunRequest& req, const gl::Limits& limits) {
  int maxSize = std::min({limits.maxTextureSize, limits.maxRenderbufferSize, limits.maxViewportW, limits.maxViewportH});
  if (plan.width > maxSize || plan.height > maxSize)
    throw UsageError("--size " + req.size + " exceeds this GL implementation's limit of " + std::to_string(maxSize) +
                     " pixels per side");
  std::string volumeProblem = volumeLimitProblem(plan.scene, limits);
  if (!volumeProblem.empty()) throw UsageError(plan.scene.source + ": " + volumeProblem);
}

// A point-light method meets an area light behind the per-VPL wrapper: its naive baseline.
std::string perVplWrap(const RunPlan& plan, const Method& method, const std::string& name,
                       const MethodRegistry& registry, const gl::Limits& limits) {
  const std::string wrap = ":vpls=" + std::to_string(kShootoutVpls);
  if (plan.effects.areaLight && !unsupportedReason(plan.scene, method, resolveSpec(name, limits, registry).params).empty() &&
      unsupportedReason(plan.scene, method, resolveSpec(name + wrap, limits, registry).params).empty())
    return wrap;
  return "";
}

// The picked rungs of every ladder of one method; a method that cannot render the scene gets one
// job (its row says why), not one per rung.
void planLadders(RunPlan& plan, const RunRequest& req, const MethodInfo& info, const MethodRegistry& registry,
                 const gl::Limits& limits) {
  auto method = info.create();
  const std::string wrap = perVplWrap(plan, *method, info.name, registry, limits);
  for (const auto& series : method->qualitySeries(plan.effects)) {
    for (size_t index : pickRungs(req.rungs, series.rungs.size())) {
      const std::string& rung = series.rungs[index];
      ResolvedSpec r = resolveSpec(info.name + (rung.empty() ? "" : ":" + rung) + wrap, limits, registry);
      plan.jobs.push_back({r.method + " " + r.params.canonical(), r.method, r.params, series.name});
      if (!unsupportedReason(plan.scene, *method, r.params).empty()) return;
    }
  }
}

}  // namespace

void planJobs(RunPlan& plan, const RunRequest& req, bool shootout, const MethodRegistry& registry,
              const gl::Limits& limits) {
  checkLimits(plan, req, limits);
  if (!shootout) {
    for (const auto& spec : req.methods) {
      ResolvedSpec r = resolveSpec(spec, limits, registry);
      plan.jobs.push_back({r.method + " " + r.params.canonical(), r.method, r.params, ""});
    }
    return;
  }
  for (const auto& info : registry) {
    if (!req.methods.empty() && std::find(req.methods.begin(), req.methods.end(), info.name) == req.methods.end())
      continue;
    planLadders(plan, req, info, registry, limits);
  }
}

RunOptions runOptionsFor(const RunRequest& req, const RunPlan& plan, TimerStrategy timer) {
  RunOptions options;
  options.width = plan.width;
  options.height = plan.height;
  options.frames = req.frames;
  options.warmup = req.warmup;
  options.minTimeMs = req.minTimeMs;
  options.seed = uint32_t(req.seed);
  options.timer = timer;
  options.workCounters = true;
  return options;
}

}  // namespace vs::shootout
