// Runs one method on one scene: warm-up, measured frames, per-pass statistics, readback.
#pragma once
#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "harness/pipeline/frame.hpp"
#include "harness/io/image.hpp"
#include "harness/pipeline/method.hpp"
#include "harness/gl/timer.hpp"

namespace vs {

struct RunOptions {
  int width = 512, height = 512;
  int frames = 20, warmup = 3;
  // > 0: the measured frames are as many as fill this many milliseconds at the last warm-up frame's
  // time, at least one and at most `frames` (needs a warm-up frame). Slow runs then take fewer
  // frames; the last frame, whose images are read back, is frame warmup + frames - 1 either way.
  double minTimeMs = 0;
  uint32_t seed = 1;
  TimerStrategy timer = TimerStrategy::WallClock;
  // false: nothing is drawn into the shadow map, so V = 1 everywhere. Gives the unshadowed L_s
  // with the same camera rays, the upper bound every method's L_s must respect.
  bool shadowCasters = true;
  // true: after the timed frames, one untimed frame with the method's work counters
  // (Method::beginWorkCount), added to MethodRun::stats. vshadow run, shootout and sweep set it.
  bool workCounters = false;
  // true: L_s is read back after every measured frame (outside its timing), for errors over a
  // moving scene's sequence (MethodRun::sequence).
  bool sequence = false;
  // One frame without a warm-up: a run whose image is what counts (errors, references, tests).
  static RunOptions singleFrame(int width, int height) {
    RunOptions o;
    o.width = width;
    o.height = height;
    o.frames = 1;
    o.warmup = 0;
    return o;
  }
};

// The per-run part of RunOptions: how many frames a run renders and what it reads back.
struct FrameSchedule {
  int frames = 20, warmup = 3;
  double minTimeMs = 0;
  bool workCounters = false, sequence = false;
  static FrameSchedule of(const RunOptions& o) { return {o.frames, o.warmup, o.minTimeMs, o.workCounters, o.sequence}; }
  void applyTo(RunOptions& o) const {
    o.frames = frames;
    o.warmup = warmup;
    o.minTimeMs = minTimeMs;
    o.workCounters = workCounters;
    o.sequence = sequence;
  }
};

enum class RunStatus { Success, Unsupported, Failure };
const char* runStatusName(RunStatus s);

// Whether a pass counts in a method's scattering time: its own passes (and the per-VPL wrapper's)
// but not the shared shadow map, G-buffer, lighting and composite (isSharedPass, as the papers
// count) nor the method's surface shading (Method::surfacePasses).
inline bool isScatteringPass(const std::string& pass, const std::vector<std::string>& surfacePasses) {
  return pass != PassTimer::kFrame && !isSharedPass(pass) &&
         std::find(surfacePasses.begin(), surfacePasses.end(), pass) == surfacePasses.end();
}

struct MethodRun {
  std::string method, params;  // params: canonical "key=value:..."
  int shadowMapSize = 0;
  RunStatus status = RunStatus::Success;
  std::string reason;
  std::vector<std::string> passes;  // passes that ran, in order
  std::vector<std::string> surfacePasses;  // Method::surfacePasses(): timed, not scattering
  std::vector<std::string> approximations;  // Method::approximations()
  double setupMs = 0;               // Method::setup, wall clock bracketed by glFinish
  std::map<std::string, TimingStats> passStats;
  TimingStats frame;
  std::map<std::string, double> stats;
  Image inscatter, final;
  // With RunOptions::sequence: every measured frame, in order, with its time in the scene's
  // animation, its frame and pass times and its L_s.
  struct SequenceFrame {
    uint32_t index = 0;
    double timeS = 0;
    std::map<std::string, double> passMs;  // the passes that ran, and "Frame"
    Image inscatter;
  };
  std::vector<SequenceFrame> sequence;
  size_t nonFinitePixels = 0;
  // Median ms of a pass, 0 when it did not run.
  double passMs(const std::string& pass) const {
    auto it = passStats.find(pass);
    return it == passStats.end() ? 0.0 : it->second.medianMs;
  }
  bool isScatteringPass(const std::string& pass) const { return vs::isScatteringPass(pass, surfacePasses); }
  // The scattering time: the sum of the medians of its scattering passes.
  double scatterMs() const {
    double total = 0.0;
    for (const auto& [pass, stats] : passStats)
      if (isScatteringPass(pass)) total += stats.medianMs;
    return total;
  }
};

// Scene-wide GPU state shared by every method run at one size.
class Runner {
 public:
  Runner(const Scene& scene, const gl::Limits& limits, RunOptions options);
  ~Runner();
  // Never throws for a method's own failure: exceptions, GL errors and non-finite pixels become a
  // Failure row with the reason; an unsupported scene becomes an Unsupported row.
  // progress(frame, total) is called after each frame.
  MethodRun run(Method& method, const ParamValues& params, const std::function<void(int, int)>& progress = {});
  // The same with this run's frames and read-backs instead of the runner's options: one runner
  // per scene state serves a row's first round and its later ones, a baseline's error and its time.
  MethodRun run(Method& method, const ParamValues& params, const FrameSchedule& schedule,
                const std::function<void(int, int)>& progress = {});
  // Why `method` cannot run this scene with `params` (empty if it can). With vpls = N > 0 the
  // method runs behind the per-VPL wrapper: once per virtual point light of the scene's area
  // light, L_s summed (passes "VPL Shadow Maps" and "VPL Accumulation" are the wrapper's).
  std::string unsupportedReason(const Method& method, const ParamValues& params) const;
  // run() one frame at a time (the viewer). setUp sizes the shadow map and sets the method up
  // (wall-clock ms; throws on failure); renderFrame runs one frame of the pipeline, every pass
  // timed (recorded when `record`). The scene's camera and light are read every frame: after moving the light call
  // shared().lightMoved() and set the method up again.
  // A moving scene (Scene::animation) is shown at t = animation.timeOf(frameIndex): renderFrame
  // moves the camera and the light there first; moving geometry is placed and uploaded inside the
  // frame (the shared pass "Geometry Update"). When the light moved, a method that fits its
  // structures to the light (Method::setupDependsOnLight) is set up again inside the frame, timed
  // as its pass "Light Refit"; when the geometry moved, one that derives state from the meshes
  // (Method::setupDependsOnGeometry), as "Geometry Refit". So the rebuild is part of the frame.
  double setUp(Method& method, const ParamValues& params);
  void renderFrame(Method& method, PassTimer& timer, uint32_t frameIndex, bool record = true);
  // The shared passes of the method set up last (the per-VPL wrapper has its own).
  SharedPasses& shared();
  const Effects& effects() const { return effects_; }
  const RunOptions& options() const { return options_; }

 private:
  const Scene& scene_;
  // A moving scene at the current frame's time (a copy of scene_ whose camera and light follow the
  // animation); null for a still scene, which is read live (the viewer moves its camera and light).
  std::unique_ptr<Scene> moving_;
  const Scene& live() const { return moving_ ? *moving_ : scene_; }
  const gl::Limits& limits_;
  RunOptions options_;
  // What the method set up last was fitted to, to be set up again when the light or geometry moves.
  ParamValues setupParams_;
  Light lightAtSetup_;
  double geometryTimeAtSetup_ = 0.0;
  double geometryTime_ = 0.0;  // the time of the pose moving_'s meshes and geometry_ hold
  struct FrameMotion {
    double time = 0.0;
    bool geometryMoves = false;
    const char* refit = nullptr;  // the refit pass to run, or null
  };
  FrameMotion followAnimation(Method& method, uint32_t frameIndex);
  void applyMotion(Method& method, PassTimer& timer, const FrameMotion& motion);
  void refit(Method& method, PassTimer& timer, const char* pass);
  Effects effects_;
  std::unique_ptr<SceneGpu> geometry_;
  std::unique_ptr<SharedPasses> shared_;
  bool sharedShadowMap_ = true;  // of the method set up last
  float alphaTest_ = -1.0f;      // of the method set up last (alphaTestThreshold)
  struct VplWrapper;
  std::unique_ptr<VplWrapper> vpl_;  // set when the method set up last runs per VPL
  void renderFrameVpl(Method& method, PassTimer& timer, uint32_t frameIndex, bool record, const FrameMotion& motion);
  // The steps of run(): the row's approximations, the warm-up frames (returns how many frames to
  // measure), the measured frames (their per-frame pass times into a sequence).
  void noteApproximations(const Method& method, const ParamValues& params, MethodRun& result) const;
  int warmUp(Method& method, PassTimer& timer, const std::function<void(int, int)>& progress);
  void measureFrames(Method& method, PassTimer& timer, int measured, MethodRun& result,
                     const std::function<void(int, int)>& progress);
};

// The pass a frame of a moving scene runs when a method set up for one light position is set up
// again for the light's new state.
inline constexpr const char* kLightRefitPass = "Light Refit";
// ...and when a method that derives state from the meshes' pose is set up again for their new pose.
inline constexpr const char* kGeometryRefitPass = "Geometry Refit";
// The per-VPL wrapper's passes: the shared shadow map from each virtual point light, and the sum
// of the method's L_s over them (the method's scattering time: they stand in for its light).
inline constexpr const char* kVplShadowMapsPass = "VPL Shadow Maps";
inline constexpr const char* kVplAccumulationPass = "VPL Accumulation";
// The runner's own passes around a method's: refits inside the frame and the per-VPL wrapper's.
inline bool isRunnerPass(const std::string& pass) {
  return pass == kLightRefitPass || pass == kGeometryRefitPass || pass == kVplShadowMapsPass ||
         pass == kVplAccumulationPass;
}

// Runner::unsupportedReason without a Runner.
std::string unsupportedReason(const Scene& scene, const Method& method, const ParamValues& params);

// Validates a method spec against the registry and the GL limits; throws UsageError.
struct ResolvedSpec {
  std::string method;
  ParamValues params;
};
ResolvedSpec resolveSpec(const std::string& spec, const gl::Limits& limits, const MethodRegistry& registry);

// The method that serves as the reference for a scene's effects: the first registered one that
// declares referenceParams(effects), with those parameters ("key=value:..."). Throws when none does.
struct ReferenceMethod {
  std::string name, params;
};
ReferenceMethod referenceMethodFor(const Effects& effects, const MethodRegistry& registry,
                                   const ReferenceBudget& budget = {});
// Its spec at a shadow-map size: "name:params:sm=N".
std::string referenceSpecFor(const Effects& effects, int shadowMapSize, const MethodRegistry& registry);

// The ray-marched reference: referenceSpecFor(the scene's effects) at the largest shadow map of the
// run, cached on disk by a hash of everything that defines it.
struct Reference {
  std::string method, params, cacheKey, cachePath;
  bool fromCache = false;
  double computeMs = 0;
  Image inscatter, final;
};
std::string defaultCacheDir();
Reference obtainReference(const Scene& scene, const gl::Limits& limits, const RunOptions& options,
                          int shadowMapSize, const std::string& cacheDir, const MethodRegistry& registry,
                          const std::string& overrideSpec = "");

}  // namespace vs
