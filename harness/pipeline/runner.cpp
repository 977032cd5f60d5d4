#include "harness/pipeline/runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "harness/evaluation/image_cache.hpp"
#include "harness/io/results.hpp"
#include "scenes/content_hash.hpp"
#include "harness/pipeline/vpl.hpp"

namespace vs {

namespace fs = std::filesystem;

const char* runStatusName(RunStatus s) {
  switch (s) {
    case RunStatus::Success:
      return "Success";
    case RunStatus::Unsupported:
      return "Unsupported";
    case RunStatus::Failure:
      return "Failure";
  }
  return "?";
}

Runner::Runner(const Scene& scene, const gl::Limits& limits, RunOptions options)
    : scene_(scene), limits_(limits), options_(options), effects_(deriveEffects(scene)) {
  if (scene_.animation.moves()) moving_ = std::make_unique<Scene>(scene_);
  if (moving_ && scene_.animation.movesGeometry()) {
    // Moving geometry starts in frame 0's pose, the one the first method is set up with.
    scene_.animation.moveGeometry(0.0, scene_.meshes, moving_->meshes);
    geometryTime_ = 0.0;
  }
  geometry_ = std::make_unique<SceneGpu>(live());
  shared_ = std::make_unique<SharedPasses>(live(), *geometry_, effects_, options_.width, options_.height);
  shared_->setShadowCasters(options_.shadowCasters);
}

// The per-VPL wrapper's state: a copy of the scene whose light is one virtual point light at a
// time, its own shared passes over that copy, and the sum of L_s over the VPLs.
struct Runner::VplWrapper {
  Scene scene;
  Effects effects;
  Light centre;              // the whole area light as one cosine-lobed point: the surface term
  std::vector<Light> lights;  // one per VPL
  std::unique_ptr<SharedPasses> shared;
  gl::Texture sum, direct;
  gl::Framebuffer sumFbo;
  gl::Program accumulate;

  VplWrapper(const Scene& original, const SceneGpu& geometry, int count, const RunOptions& options)
      : scene(original) {
    place(original.light, count);
    scene.light = centre;
    effects = deriveEffects(scene);
    shared = std::make_unique<SharedPasses>(scene, geometry, effects, options.width, options.height);
    shared->setShadowCasters(options.shadowCasters);
    sum = gl::createTexture2D(GL_RGBA32F, options.width, options.height);
    direct = gl::createTexture2D(GL_RGBA32F, options.width, options.height);
    sumFbo = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, sum.id()}});
    gl::checkFramebuffer(sumFbo.id(), "VPL sum");
    accumulate = gl::buildFullscreen("harness/shaders/vpl_accumulate.frag");
  }
  // The VPLs of the area light as it is now (it may move between frames).
  void place(const Light& area, int count) {
    centre = virtualPointLight(area, area.position, 1);
    lights.clear();
    for (const glm::vec3& p : virtualPointLightPositions(area, count)) lights.push_back(virtualPointLight(area, p, count));
  }
  void useLight(const Light& light, uint32_t frameIndex, uint32_t seed) {
    scene.light = light;
    shared->lightMoved();
    shared->updateUniforms(frameIndex, seed);
  }
};

Runner::~Runner() = default;

SharedPasses& Runner::shared() { return vpl_ ? *vpl_->shared : *shared_; }

std::string Runner::unsupportedReason(const Method& method, const ParamValues& params) const {
  return vs::unsupportedReason(scene_, method, params);
}

std::string unsupportedReason(const Scene& scene, const Method& method, const ParamValues& params) {
  const Effects effects = deriveEffects(scene);
  int vpls = params.getInt("vpls");
  if (vpls == 0) {
    std::string reason = method.unsupportedReason(scene, params);
    if (!reason.empty() && effects.areaLight) {
      Scene asVpls = scene;
      asVpls.light = virtualPointLight(scene.light, scene.light.position, 1);
      if (!method.lightFixedAtSetup() && method.unsupportedReason(asVpls, params).empty())
        reason += " (vpls=N runs it once per virtual point light)";
    }
    return reason;
  }
  if (!effects.areaLight) return "vpls needs an area light; the scene's light is a " +
                                  std::string(lightTypeName(scene.light.type)) + " light";
  if (method.lightFixedAtSetup())
    return method.name() + " fits its setup to one light position, so it cannot run once per virtual point light";
  Scene asVpls = scene;
  asVpls.light = virtualPointLight(scene.light, scene.light.position, vpls);
  return method.unsupportedReason(asVpls, params);
}

static size_t countNonFinite(const Image& img) {
  size_t n = 0;
  for (float v : img.rgb) n += std::isfinite(v) ? 0 : 1;
  return n;
}

double Runner::setUp(Method& method, const ParamValues& params) {
  int shadowMapSize = params.getInt("sm");
  int vpls = params.getInt("vpls");
  // The wrapper is rebuilt at every set-up: the scene's light may have moved (the viewer).
  vpl_.reset();
  if (vpls > 0) {
    if (!effects_.areaLight) throw std::runtime_error("vpls needs an area light");
    vpl_ = std::make_unique<VplWrapper>(live(), *geometry_, vpls, options_);
  }
  shared_->lightMoved();
  setupParams_ = params;
  lightAtSetup_ = live().light;
  geometryTimeAtSetup_ = geometryTime_;
  const Scene& scene = vpl_ ? vpl_->scene : live();
  const Effects& effects = vpl_ ? vpl_->effects : effects_;
  shared().setShadowMapSize(shadowMapSize);
  alphaTest_ = alphaTestThreshold(method, effects, params);
  shared().setAlphaTest(alphaTest_);
  shared().updateUniforms(0, options_.seed);
  double setupMs = 0.0;
  // Passes a scene does not call for are not built: without scattering the method is not set up.
  if (effects.scattering) {
    SetupContext context{scene, *geometry_, effects, options_.width, options_.height, shadowMapSize, limits_, alphaTest_};
    glFinish();
    auto start = std::chrono::steady_clock::now();
    method.setup(context, params);
    glFinish();
    setupMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  // A method with its own light-space structure does not pay for the shared shadow map: it is
  // cleared once (V = 1) and not rendered.
  sharedShadowMap_ = !effects.scattering || method.needsSharedShadowMap();
  if (!sharedShadowMap_) shared().clearShadowMap();
  gl::checkErrors("method setup");
  return setupMs;
}

static bool sameLight(const Light& a, const Light& b) {
  return a.position == b.position && a.direction == b.direction && a.tangent == b.tangent &&
         a.intensity == b.intensity && a.width == b.width && a.height == b.height && a.radius == b.radius;
}

// Moves the camera and the light to the frame's time, and says whether the geometry moves and
// whether the method must be set up again: fitted to the light at its set-up when the light moved,
// or to the meshes' pose when the geometry did.
Runner::FrameMotion Runner::followAnimation(Method& method, uint32_t frameIndex) {
  FrameMotion motion;
  if (!moving_) return motion;
  Scene& scene = *moving_;
  const Animation& animation = scene_.animation;
  motion.time = animation.timeOf(frameIndex);
  const Light before = scene.light;
  animation.apply(motion.time, scene.camera, scene.light);
  if (vpl_) vpl_->scene.camera = scene.camera;
  motion.geometryMoves = animation.movesGeometry() && motion.time != geometryTime_;
  const Effects& effects = vpl_ ? vpl_->effects : effects_;
  if (!sameLight(before, scene.light)) {
    shared_->lightMoved();
    if (vpl_) vpl_->place(scene.light, setupParams_.getInt("vpls"));
    if (method.setupDependsOnLight(effects) && !sameLight(lightAtSetup_, scene.light)) motion.refit = kLightRefitPass;
  }
  if (!motion.refit && animation.movesGeometry() && method.setupDependsOnGeometry(effects) &&
      motion.time != geometryTimeAtSetup_)
    motion.refit = kGeometryRefitPass;
  return motion;
}

// Inside the frame: the geometry placed at the frame's time and uploaded (a shared pass), then the
// method set up again where it must be.
void Runner::applyMotion(Method& method, PassTimer& timer, const FrameMotion& motion) {
  if (motion.geometryMoves) {
    auto scope = timer.scope(kGeometryUpdatePass);
    scene_.animation.moveGeometry(motion.time, scene_.meshes, moving_->meshes);
    geometry_->updateVertices(*moving_);
    geometryTime_ = motion.time;
  }
  if (motion.refit) refit(method, timer, motion.refit);
}

// Sets the method up again for the light and geometry where they are now, inside the frame: its
// cost is the frame's (programs come from the in-process binary cache, so this is the rebuild, not
// a compile).
void Runner::refit(Method& method, PassTimer& timer, const char* pass) {
  if (!effects_.scattering) return;
  auto scope = timer.scope(pass);
  const Scene& scene = vpl_ ? vpl_->scene : live();
  const Effects& effects = vpl_ ? vpl_->effects : effects_;
  SetupContext context{scene,   *geometry_, effects, options_.width, options_.height, setupParams_.getInt("sm"),
                       limits_, alphaTest_};
  method.setup(context, setupParams_);
  lightAtSetup_ = live().light;
  geometryTimeAtSetup_ = geometryTime_;
  gl::resetPipelineState();
}

void Runner::renderFrame(Method& method, PassTimer& timer, uint32_t frameIndex, bool record) {
  const FrameMotion motion = followAnimation(method, frameIndex);
  if (vpl_) return renderFrameVpl(method, timer, frameIndex, record, motion);
  shared_->updateUniforms(frameIndex, options_.seed);
  gl::resetPipelineState();
  timer.beginFrame(record);
  applyMotion(method, timer, motion);
  if (sharedShadowMap_) shared_->renderShadowMap(timer);
  shared_->renderGBuffer(timer);
  shared_->renderDirect(timer);
  if (effects_.scattering) {
    method.render(shared_->frame(), timer);
    gl::resetPipelineState();
  } else {
    shared_->clearInscatter();
  }
  shared_->composite(timer);
  timer.endFrame();
}

// One frame behind the per-VPL wrapper. Surfaces are shaded once, with the area light as the
// shared passes always see it (a cosine-lobed point light at its centre); then per VPL its shadow
// map and the method's passes, and L_s is added up. The method's own surface shadows are not
// summed over VPLs: the shared Direct Lighting is restored after the loop.
void Runner::renderFrameVpl(Method& method, PassTimer& timer, uint32_t frameIndex, bool record,
                            const FrameMotion& motion) {
  VplWrapper& w = *vpl_;
  SharedPasses& shared = *w.shared;
  w.useLight(w.centre, frameIndex, options_.seed);
  gl::resetPipelineState();
  timer.beginFrame(record);
  applyMotion(method, timer, motion);
  if (sharedShadowMap_) shared.renderShadowMap(timer);
  shared.renderGBuffer(timer);
  shared.renderDirect(timer);
  if (effects_.scattering) {
    Frame frame = shared.frame();
    const float zero[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    glClearNamedFramebufferfv(w.sumFbo.id(), GL_COLOR, 0, zero);
    glCopyImageSubData(frame.direct, GL_TEXTURE_2D, 0, 0, 0, 0, w.direct.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                       options_.width, options_.height, 1);
    for (const Light& light : w.lights) {
      w.useLight(light, frameIndex, options_.seed);
      if (sharedShadowMap_) shared.renderShadowMap(timer, kVplShadowMapsPass);
      method.render(shared.frame(), timer);
      gl::resetPipelineState();
      auto scope = timer.scope(kVplAccumulationPass);
      // rgb: sum over VPLs; alpha: the camera ray's volume transmittance, the same for every VPL.
      glBindFramebuffer(GL_FRAMEBUFFER, w.sumFbo.id());
      glViewport(0, 0, options_.width, options_.height);
      glEnable(GL_BLEND);
      glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ZERO);
      glUseProgram(w.accumulate.id());
      glBindTextureUnit(bind::kInscatter, frame.inscatter);
      gl::drawFullscreenTriangle();
      glDisable(GL_BLEND);
    }
    {
      auto scope = timer.scope(kVplAccumulationPass);
      glCopyImageSubData(w.sum.id(), GL_TEXTURE_2D, 0, 0, 0, 0, frame.inscatter, GL_TEXTURE_2D, 0, 0, 0, 0,
                         options_.width, options_.height, 1);
      glCopyImageSubData(w.direct.id(), GL_TEXTURE_2D, 0, 0, 0, 0, frame.direct, GL_TEXTURE_2D, 0, 0, 0, 0,
                         options_.width, options_.height, 1);
    }
    w.useLight(w.centre, frameIndex, options_.seed);
    gl::resetPipelineState();
  } else {
    shared.clearInscatter();
  }
  shared.composite(timer);
  timer.endFrame();
}

void Runner::noteApproximations(const Method& method, const ParamValues& params, MethodRun& result) const {
  result.approximations = method.approximations();
  if (params.getInt("vpls") > 0)
    result.approximations.push_back("area light as " + std::to_string(params.getInt("vpls")) +
                                    " virtual point lights (per-VPL wrapper)");
  std::string alphaTested = alphaTestApproximation(scene_, alphaTestThreshold(method, effects_, params));
  if (!alphaTested.empty()) result.approximations.push_back(alphaTested);
}

int Runner::warmUp(Method& method, PassTimer& timer, const std::function<void(int, int)>& progress) {
  int total = options_.warmup + options_.frames;
  int measured = options_.frames;
  for (int f = 0; f < options_.warmup; ++f) {
    // --min-time: the last warm-up frame's time says how many frames fill it.
    bool sizing = options_.minTimeMs > 0.0 && f == options_.warmup - 1;
    if (sizing) glFinish();
    auto start = std::chrono::steady_clock::now();
    renderFrame(method, timer, uint32_t(f), false);
    if (sizing) {
      glFinish();
      double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      measured = std::clamp(int(std::ceil(options_.minTimeMs / std::max(ms, 1e-3))), 1, options_.frames);
    }
    gl::checkErrors("frame");
    if (progress) progress(f + 1, total);
  }
  return measured;
}

void Runner::measureFrames(Method& method, PassTimer& timer, int measured, MethodRun& result,
                           const std::function<void(int, int)>& progress) {
  int total = options_.warmup + options_.frames;
  // The measured frames are the last ones of a full run, so the images do not depend on `measured`.
  for (int f = total - measured; f < total; ++f) {
    renderFrame(method, timer, uint32_t(f), true);
    gl::checkErrors("frame");
    if (options_.sequence)
      result.sequence.push_back({uint32_t(f), scene_.animation.timeOf(uint32_t(f)), {}, shared().readInscatter()});
    if (progress) progress(f + 1, total);
  }
  timer.finish();
  // The recorded frames are the measured ones, in order.
  for (size_t k = 0; k < result.sequence.size() && k < timer.frames().size(); ++k)
    result.sequence[k].passMs = timer.frames()[k];
}

// The timed passes into the row, in the order they ran; a pass the method did not declare fails it.
static void collectPasses(const Method& method, const PassTimer& timer, MethodRun& result) {
  const std::vector<std::string> declared = method.passes();
  result.surfacePasses = method.surfacePasses();
  for (const auto& name : timer.passOrder()) {
    if (name != PassTimer::kFrame && !isSharedPass(name) && !isRunnerPass(name) &&
        std::find(declared.begin(), declared.end(), name) == declared.end())
      throw std::runtime_error("pass '" + name + "' is not among the passes " + method.name() +
                               " declares (Method::passes)");
    TimingStats s = summarise(timer.samples().at(name));
    if (name == PassTimer::kFrame) {
      result.frame = s;
    } else {
      result.passStats[name] = s;
      result.passes.push_back(name);
    }
  }
}

// A GL error or a non-finite pixel in any recorded image fails the row.
static void checkImages(MethodRun& result) {
  if (gl::debugErrorCount() > 0) {
    result.status = RunStatus::Failure;
    result.reason = "GL error: " + gl::lastDebugError();
  }
  result.nonFinitePixels = countNonFinite(result.inscatter) + countNonFinite(result.final);
  // The earlier frames of a sequence too (its last frame is the one read back).
  for (size_t k = 0; k + 1 < result.sequence.size(); ++k) result.nonFinitePixels += countNonFinite(result.sequence[k].inscatter);
  if (result.status == RunStatus::Success && result.nonFinitePixels > 0) {
    result.status = RunStatus::Failure;
    result.reason = std::to_string(result.nonFinitePixels) + " non-finite pixel values";
  }
}

MethodRun Runner::run(Method& method, const ParamValues& params, const std::function<void(int, int)>& progress) {
  MethodRun result;
  result.method = method.name();
  result.params = params.canonical();
  result.shadowMapSize = params.getInt("sm");
  noteApproximations(method, params, result);
  std::string unsupported = unsupportedReason(method, params);
  if (!unsupported.empty()) {
    result.status = RunStatus::Unsupported;
    result.reason = unsupported;
    return result;
  }
  gl::resetDebugErrorCount();
  try {
    result.setupMs = setUp(method, params);
    noteApproximations(method, params, result);  // setup may know more (the scene's and parameters' departures)
    PassTimer timer(options_.timer);
    int measured = warmUp(method, timer, progress);
    measureFrames(method, timer, measured, result, progress);
    collectPasses(method, timer, result);
    result.stats = method.stats(result.passStats);
    result.inscatter = shared().readInscatter();
    result.final = shared().readFinal();
    gl::checkErrors("readback");
    // The method's work counters, from one more frame that is neither timed nor read back.
    if (options_.workCounters && method.beginWorkCount(options_.width, options_.height)) {
      PassTimer untimed(TimerStrategy::WallClock);
      renderFrame(method, untimed, uint32_t(options_.warmup + options_.frames - 1), false);
      gl::checkErrors("work counters");
      for (const auto& [key, value] : method.endWorkCount()) result.stats[key] = value;
    }
    checkImages(result);
  } catch (const std::exception& e) {
    result.status = RunStatus::Failure;
    result.reason = e.what();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
  return result;
}

MethodRun Runner::run(Method& method, const ParamValues& params, const FrameSchedule& schedule,
                     const std::function<void(int, int)>& progress) {
  const FrameSchedule own = FrameSchedule::of(options_);
  schedule.applyTo(options_);
  struct Restore {
    RunOptions& options;
    FrameSchedule saved;
    ~Restore() { saved.applyTo(options); }
  } restore{options_, own};
  return run(method, params, progress);
}

ResolvedSpec resolveSpec(const std::string& text, const gl::Limits& limits, const MethodRegistry& registry) {
  MethodSpec spec = parseMethodSpec(text);
  auto method = createMethod(registry, spec.method);
  int maxShadow = std::min(limits.maxTextureSize, limits.maxCubeMapSize);
  return {spec.method, ParamValues::parse(spec.method, allParams(*method, maxShadow), spec.params)};
}

// ---- reference

std::string defaultCacheDir() {
  if (const char* dir = std::getenv("VSHADOW_CACHE")) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME")) return std::string(xdg) + "/vshadow";
  if (const char* home = std::getenv("HOME")) return std::string(home) + "/.cache/vshadow";
  return ".vshadow-cache";
}

ReferenceMethod referenceMethodFor(const Effects& effects, const MethodRegistry& registry,
                                   const ReferenceBudget& budget) {
  for (const auto& info : registry) {
    std::string params = info.create()->referenceParams(effects, budget);
    if (!params.empty()) return {info.name, params};
  }
  throw std::runtime_error("no registered method can serve as the reference");
}

std::string referenceSpecFor(const Effects& effects, int shadowMapSize, const MethodRegistry& registry) {
  ReferenceMethod m = referenceMethodFor(effects, registry);
  return m.name + ":" + m.params + ":sm=" + std::to_string(shadowMapSize);
}

Reference obtainReference(const Scene& scene, const gl::Limits& limits, const RunOptions& options, int shadowMapSize,
                          const std::string& cacheDir, const MethodRegistry& registry, const std::string& overrideSpec) {
  std::string spec = overrideSpec.empty() ? referenceSpecFor(deriveEffects(scene), shadowMapSize, registry) : overrideSpec;
  ResolvedSpec resolved = resolveSpec(spec, limits, registry);
  Reference ref;
  ref.method = resolved.method;
  ref.params = resolved.params.canonical();
  std::string keyText = "vshadow-reference-v1\n" + scene.contentHash + "\n" + std::to_string(options.width) + "x" +
                        std::to_string(options.height) + "\n" + ref.method + ":" + ref.params + "\nseed=" +
                        std::to_string(options.seed) + "\nshaders=" + gl::shaderSourcesHash();
  ContentHasher hasher;
  hasher.addBlock(keyText);
  ref.cacheKey = hasher.hex();
  const std::string base = (fs::path(cacheDir) / (scene.name + "-" + ref.cacheKey)).string();
  ref.cachePath = base;
  if (auto cached = readCachedImages(base, keyText, options.width, options.height)) {
    ref.inscatter = std::move(cached->inscatter);
    ref.final = std::move(cached->final);
    ref.fromCache = true;
    return ref;
  }
  auto start = std::chrono::steady_clock::now();
  auto method = createMethod(registry, resolved.method);
  RunOptions refOptions = options;
  refOptions.frames = 1;
  refOptions.warmup = 0;
  refOptions.workCounters = false;
  Runner runner(scene, limits, refOptions);
  MethodRun run = runner.run(*method, resolved.params);
  if (run.status != RunStatus::Success)
    throw std::runtime_error("the reference (" + spec + ") failed: " + run.reason);
  ref.inscatter = std::move(run.inscatter);
  ref.final = std::move(run.final);
  ref.computeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  writeCachedImages(base, keyText, ref.inscatter, ref.final,
                    {{"scene", scene.name},
                     {"scene_source", scene.source},
                     {"method", ref.method},
                     {"params", ref.params},
                     {"width", options.width},
                     {"height", options.height},
                     {"seed", options.seed},
                     {"compute_ms", ref.computeMs}});
  return ref;
}

}  // namespace vs
