// The one interface every volumetric-shadow method implements. The harness knows methods only
// through this header and the registry (methods/registry.hpp); it never names one.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "harness/pipeline/frame.hpp"
#include "harness/pipeline/params.hpp"
#include "harness/gl/timer.hpp"

namespace vs {

// What a method supports, declared once; missingCapability() matches it against a scene's Effects.
struct Capabilities {
  bool pointLight = false, spotLight = false, directionalLight = false, areaLight = false;
  bool cosineLobe = false;  // point lights with cosine emission: the per-VPL wrapper's lights
  bool texturedLight = false;
  bool homogeneousMedium = true;
  bool henyeyGreenstein = false;
  bool volumeData = false;
  bool semiTransparentOccluders = false;
  // Binary visibility only, but semi-transparent scenes run with their occluders alpha-tested into
  // the shared shadow map (opacity >= `alpha_test` blocks, below it lets light through): a declared
  // approximation in every such row. Methods with structures of their own built from the meshes
  // follow SetupContext::alphaTest.
  bool alphaTestedOccluders = false;
  bool coloredShadows = false;
  bool surfaceShadows = false;
  std::string describe() const;
  // Per effect a method may meet, how it meets it: "native", "approximated: how" or "no"; for
  // `vshadow list` and the method READMEs.
  struct EffectSupport {
    std::string effect, support;
  };
  std::vector<EffectSupport> effectSupport() const;
};

// The one place a method's capabilities meet a scene's effects: empty when every effect is
// covered, otherwise a reason naming the first missing effect ("needs volume data").
std::string missingCapability(const Capabilities& capabilities, const Effects& effects);

struct SetupContext {
  const Scene& scene;
  const SceneGpu& geometry;
  const Effects& effects;
  int width, height;
  int shadowMapSize;
  const gl::Limits& limits;
  // >= 0: the scene's semi-transparent occluders are alpha-tested at this opacity (the shared shadow
  // map holds those at or above it and no transmittance map is built); a method that builds its own
  // occluder structure from the meshes does the same. -1: occluders as the scene has them.
  float alphaTest = -1.0f;
};

// One of a method's own GL buffers as the viewer shows it (vshadow view): the viewer reads the
// chosen layer and level back and maps it to grey (or red-green, rgb).
struct DebugView {
  enum class Kind {
    Value,  // float or depth texels; `channels` of them mapped from [lo, hi] to [0, 1]
    Bits,   // RGBA32UI bit grid: 128 bits per texel and array layer; one bit shown per "layer"
  };
  std::string name;
  GLuint texture = 0;  // 2D, 2D array, 3D or cube map, owned by the method
  Kind kind = Kind::Value;
  int layers = 1;      // Value: array layers, 3D slices or cube faces; Bits: bits per texel column
  int levels = 1;      // mip levels to choose from
  int channels = 1;    // Value: 1 grey (red), 2 red-green, 3 rgb
  float lo = 0.0f, hi = 0.0f;  // lo >= hi: the range of the values read (auto)
};

// A cap on the reference's cost (Method::referenceParams); 0: no cap.
struct ReferenceBudget {
  int maxSteps = 0;          // samples per camera ray
  int maxShadowMapSize = 0;  // its own shadow maps (an area light's per-sample maps)
  int lightSamples = 0;      // area lights: points on the light (0: the method's choice)
};
// One brute-force baseline: the reference method in one of its ladder series (a name from
// qualitySeries(effects), e.g. "uniform", "equiangular") at `steps` samples per camera ray and, for
// area lights, `lightSamples` points on the light (0: the method's default); with volume data,
// `lightRaySteps` per voxel of the nested march towards the light.
struct BaselinePoint {
  std::string series;
  int steps = 0;
  int lightSamples = 0;
  double lightRaySteps = 0;  // volume data: steps per voxel of the march towards the light (0: the default)
};

class Method {
 public:
  virtual ~Method() = default;
  virtual std::string name() const = 0;
  virtual std::string description() const = 0;  // one line: paper and what it does
  virtual Capabilities capabilities() const = 0;
  // The method's own knobs. The harness adds the shared ones (sm = shadow-map resolution).
  virtual std::vector<ParamSpec> params() const = 0;
  // Every pass render() may time (timer.scope), named as the paper's tables name them: the row's
  // pass columns. A run that times a
  // pass not listed here fails, so tables and benchmarks can rely on the list.
  virtual std::vector<std::string> passes() const = 0;
  // The passes among passes() that shade surfaces (L_surf from the method's own structure, e.g.
  // surface shadows) rather than compute L_s: timed and listed, but not scattering time. The one
  // definition of scattering time: the method's passes minus these (MethodRun::scatterMs).
  virtual std::vector<std::string> surfacePasses() const { return {}; }
  // Parameter sets for `vshadow shootout`, cheapest first (each "key=value:key=value").
  virtual std::vector<std::string> qualityLadder() const { return {""}; }
  // The ladder for a scene with these effects, as one or more named series, each cheapest first
  // (e.g. the reference method's uniform and equiangular steps: two brute-force curves). --rungs
  // picks within each series. The default: qualityLadder() as one unnamed series.
  struct QualitySeries {
    std::string name;
    std::vector<std::string> rungs;
  };
  virtual std::vector<QualitySeries> qualitySeries(const Effects& effects) const {
    (void)effects;
    return {{"", qualityLadder()}};
  }
  // Parameters that make this method the ray-marched reference for a scene with these effects;
  // empty when it cannot be one. A budget caps its cost (the stress's small images); 0: no cap.
  virtual std::string referenceParams(const Effects& effects, const ReferenceBudget& budget = {}) const {
    (void)effects;
    (void)budget;
    return "";
  }
  // The reference method as brute force: its parameters at one baseline point. The equal-quality
  // baselines of the shootout and the benchmarks are these; empty when the method has no such
  // baseline (or not in that series). So no code outside the method writes its parameter names.
  virtual std::string baselineParams(const BaselinePoint& point) const {
    (void)point;
    return "";
  }
  // Why this method cannot render `scene` with `params`; empty when it can. The default is
  // missingCapability(capabilities(), effects of the scene); override only for reasons that depend
  // on the parameters, and call the default too.
  virtual std::string unsupportedReason(const Scene& scene, const ParamValues& params) const;
  // false: the method builds its own light-space structure, so the runner neither renders nor
  // times the shared shadow map (Direct Lighting then sees V = 1 and the method must re-shade
  // L_surf with its own surface shadows, Frame::directFbo).
  virtual bool needsSharedShadowMap() const { return true; }
  // true: setup() fits the method's structures to the light's position, so render() is only right
  // for the light it was set up with. Such a method cannot run behind the per-VPL wrapper, which
  // moves the light between renders (harness/pipeline/vpl.hpp).
  virtual bool lightFixedAtSetup() const { return false; }
  // true: setup() derives state from the light (its position, size or frame), so when the light of
  // a moving scene changes, the runner sets the method up again inside the frame ("Light Refit",
  // timed as the method's own pass). Every light-fixed method does; others may for some effects.
  virtual bool setupDependsOnLight(const Effects& effects) const {
    (void)effects;
    return lightFixedAtSetup();
  }
  // true: setup() derives state from where the meshes are (a point cloud, depth ranges), so when
  // a moving scene's geometry moves, the runner sets the method up again inside the frame
  // ("Geometry Refit", the method's own pass). Structures rebuilt from the shared passes every
  // frame follow the geometry by themselves.
  virtual bool setupDependsOnGeometry(const Effects& effects) const {
    (void)effects;
    return false;
  }
  // Where the method departs from the model (README "What is computed"), one short phrase each,
  // e.g. "homogeneous extinction along light rays"; recorded in every result row. Read before
  // setup and again after it, which may add the departures of this scene and these parameters.
  virtual std::vector<std::string> approximations() const { return {}; }
  // Allocate and compile; called once before the frames. Throw to fail the run with a reason.
  virtual void setup(const SetupContext& context, const ParamValues& params) = 0;
  // Write L_s into frame.inscatterFbo (rgb) and, with volume data, the camera ray's rgb
  // transmittance through the volumes into its draw buffer 1 (frame.volumeTransmittance; the
  // homogeneous medium is applied by the composite); every
  // pass inside timer.scope("Paper's pass name"). Called only when the scene scatters light
  // (Effects::scattering). setup() is timed on its own (the setup_ms column).
  virtual void render(const Frame& frame, PassTimer& timer) = 0;
  // The largest relMSE of L_s against the reference this method promises at its default
  // parameters on every regular case of the hard-case suite (tests/stability_tests.cpp).
  virtual double declaredRelMseBound() const { return 0.05; }
  // The method's own buffers for the viewer, valid after render(); the viewer adds the shared
  // shadow map itself. Called only by the viewer, never inside a timed pass.
  virtual std::vector<DebugView> debugViews() const { return {}; }
  // Work counters for the result row (e.g. traversal steps per pixel, mean and max). After the
  // timed frames and the image readback the runner calls beginWorkCount(); if it returns true,
  // it renders one more, untimed frame, during which render() runs instrumented passes, and adds
  // endWorkCount() to the row's stats.
  virtual bool beginWorkCount(int width, int height) {
    (void)width;
    (void)height;
    return false;
  }
  virtual std::map<std::string, double> endWorkCount() { return {}; }
  // Figures for the result row, from the measured pass medians (e.g. samples per second).
  virtual std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const {
    (void)passes;
    return {};
  }
};

struct MethodInfo {
  std::string name;
  std::function<std::unique_ptr<Method>()> create;
};
// The methods a program can run. The harness never names a method: the program passes the
// registry in (methods/registry.hpp defines the project's).
using MethodRegistry = std::vector<MethodInfo>;

// Shared parameters every method accepts, appended to its own: `sm` and `vpls` (the per-VPL
// wrapper, harness/pipeline/vpl.hpp).
constexpr int kMaxVirtualPointLights = 4096;
std::vector<ParamSpec> sharedParams(int maxShadowMapSize);
std::vector<ParamSpec> allParams(const Method& method, int maxShadowMapSize);
// The opacity at which this method's run alpha-tests the scene's semi-transparent occluders, or -1
// when it does not (no such occluders, or the method models them).
float alphaTestThreshold(const Method& method, const Effects& effects, const ParamValues& params);
// The row's approximation for an alpha-tested run; empty when alpha testing is exact (only MASK
// cut-outs, whose texels are opaque or absent).
std::string alphaTestApproximation(const Scene& scene, float threshold);
std::unique_ptr<Method> createMethod(const MethodRegistry& registry, const std::string& name);  // UsageError if unknown
std::string knownMethodNames(const MethodRegistry& registry);

}  // namespace vs
