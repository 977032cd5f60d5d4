// The plan stage: takes a RunRequest, gives a RunPlan (the checked request, the scene, the jobs
// with their resolved parameters) before anything is written. planBeforeContext needs no GL
// context; planJobs checks the GL limits and lists the jobs. Both throw UsageError/SceneError.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/cli/scene_load.hpp"
#include "harness/gl/gl.hpp"
#include "harness/pipeline/effects.hpp"
#include "harness/pipeline/method.hpp"
#include "harness/pipeline/params.hpp"
#include "harness/pipeline/runner.hpp"
#include "harness/shootout/request.hpp"
#include "scenes/scene.hpp"

namespace vs::shootout {

// Virtual point lights per area light for the shootout's per-VPL rows (README, "vpls=N").
constexpr int kShootoutVpls = 16;

struct Job {
  std::string label;
  std::string method;
  ParamValues params;
  std::string series;  // the ladder series its rung comes from (Method::qualitySeries), if named
};

// Everything a run needs to know before it writes anything.
struct RunPlan {
  int width = 0, height = 0;
  Scene scene;
  SceneLoad sceneLoad;  // what loading `scene` took (meta.json "scene_load")
  // The scene at the time of the frame whose images are compared (the last one): the reference's
  // and the ground truth's scene. Only a moving scene holds a second copy.
  std::optional<Scene> movedScene;
  const Scene& stillScene() const { return movedScene ? *movedScene : scene; }
  uint32_t comparedFrame = 0;
  Effects effects;
  std::vector<Job> jobs;
  bool exactReference = false;  // --reference exact
  bool haveExact = false;       // the ground truth is rendered (--exact, --reference exact, --equal-quality)
  bool haveReference = true;
  // --equal-quality matches errors against the exact ground truth where it models the scene: then
  // no estimator gains from sharing the ray-marched reference's shadow-map filter. Otherwise against
  // the reference, and equalQualityNote says why.
  bool equalQualityExact = false;
  std::string equalQualityNote;
};

// The rungs of a ladder of `size` that --rungs picks, in ladder order, each once. Throws UsageError
// for a word that is none of all, first, middle, last or a 0-based index; an index past the end of a
// ladder picks nothing from it.
std::vector<size_t> pickRungs(const std::vector<std::string>& rungs, size_t size);

// Checks that need no GL context: size, scene, method names, the reference spec. Prints the
// scene's load warnings on stderr.
RunPlan planBeforeContext(const RunRequest& req, bool shootout, const MethodRegistry& registry);

// Checks against the GL limits, then the jobs: every picked rung of every ladder (shootout) or the specs.
void planJobs(RunPlan& plan, const RunRequest& req, bool shootout, const MethodRegistry& registry,
              const gl::Limits& limits);

// The runner's options of every row: the plan's size, the request's frames, warm-up, --min-time
// and seed, with work counters.
RunOptions runOptionsFor(const RunRequest& req, const RunPlan& plan, TimerStrategy timer);

}  // namespace vs::shootout
