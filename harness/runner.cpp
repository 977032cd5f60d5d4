#include "runner.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "results.hpp"
#include "scenes/content_hash.hpp"

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
  geometry_ = std::make_unique<SceneGpu>(scene_);
  shared_ = std::make_unique<SharedPasses>(scene_, *geometry_, effects_, options_.width, options_.height);
  shared_->setShadowCasters(options_.shadowCasters);
}

static size_t countNonFinite(const Image& img) {
  size_t n = 0;
  for (float v : img.rgb) n += std::isfinite(v) ? 0 : 1;
  return n;
}

double Runner::setUp(Method& method, const ParamValues& params) {
  int shadowMapSize = params.getInt("sm");
  shared_->setShadowMapSize(shadowMapSize);
  shared_->updateUniforms(0, options_.seed);
  double setupMs = 0.0;
  // Passes a scene does not call for are not built: without scattering the method is not set up.
  if (effects_.scattering) {
    SetupContext context{scene_, *geometry_, effects_, options_.width, options_.height, shadowMapSize, limits_};
    glFinish();
    auto start = std::chrono::steady_clock::now();
    method.setup(context, params);
    glFinish();
    setupMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  // A method with its own light-space structure does not pay for the shared shadow map: it is
  // cleared once (V = 1) and not rendered.
  sharedShadowMap_ = !effects_.scattering || method.needsSharedShadowMap();
  if (!sharedShadowMap_) shared_->clearShadowMap();
  gl::checkErrors("method setup");
  return setupMs;
}

void Runner::renderFrame(Method& method, PassTimer& timer, uint32_t frameIndex, bool record) {
  shared_->updateUniforms(frameIndex, options_.seed);
  gl::resetPipelineState();
  timer.beginFrame(record);
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

MethodRun Runner::run(Method& method, const ParamValues& params, const std::function<void(int, int)>& progress) {
  MethodRun result;
  result.method = method.name();
  result.params = params.canonical();
  result.shadowMapSize = params.getInt("sm");
  result.approximations = method.approximations();
  std::string unsupported = method.unsupportedReason(scene_, params);
  if (!unsupported.empty()) {
    result.status = RunStatus::Unsupported;
    result.reason = unsupported;
    return result;
  }
  gl::resetDebugErrorCount();
  try {
    result.setupMs = setUp(method, params);
    PassTimer timer(options_.timer);
    int total = options_.warmup + options_.frames;
    for (int f = 0; f < total; ++f) {
      renderFrame(method, timer, uint32_t(f), f >= options_.warmup);
      gl::checkErrors("frame");
      if (progress) progress(f + 1, total);
    }
    timer.finish();
    for (const auto& name : timer.passOrder()) {
      TimingStats s = summarise(timer.samples().at(name));
      if (name == PassTimer::kFrame) {
        result.frame = s;
      } else {
        result.passStats[name] = s;
        result.passes.push_back(name);
      }
    }
    result.stats = method.stats(result.passStats);
    result.inscatter = shared_->readInscatter();
    result.final = shared_->readFinal();
    gl::checkErrors("readback");
    if (gl::debugErrorCount() > 0) {
      result.status = RunStatus::Failure;
      result.reason = "GL error: " + gl::lastDebugError();
    }
    result.nonFinitePixels = countNonFinite(result.inscatter) + countNonFinite(result.final);
    if (result.status == RunStatus::Success && result.nonFinitePixels > 0) {
      result.status = RunStatus::Failure;
      result.reason = std::to_string(result.nonFinitePixels) + " non-finite pixel values";
    }
  } catch (const std::exception& e) {
    result.status = RunStatus::Failure;
    result.reason = e.what();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
  return result;
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

Reference obtainReference(const Scene& scene, const gl::Limits& limits, const RunOptions& options, int shadowMapSize,
                          const std::string& cacheDir, const MethodRegistry& registry, const std::string& overrideSpec) {
  std::string spec = overrideSpec;
  if (spec.empty()) {
    for (const auto& info : registry) {
      auto m = info.create();
      std::string params = m->referenceParams(deriveEffects(scene));
      if (!params.empty()) {
        spec = info.name + ":" + params + ":sm=" + std::to_string(shadowMapSize);
        break;
      }
    }
    if (spec.empty()) throw std::runtime_error("no registered method can serve as the reference");
  }
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
  fs::path base = fs::path(cacheDir) / (scene.name + "-" + ref.cacheKey);
  ref.cachePath = base.string();
  std::string lsPath = base.string() + ".ls.exr", finalPath = base.string() + ".final.exr";
  std::string jsonPath = base.string() + ".json";
  if (fs::exists(lsPath) && fs::exists(finalPath) && fs::exists(jsonPath)) {
    try {
      ref.inscatter = readImage(lsPath);
      ref.final = readImage(finalPath);
      if (ref.inscatter.width == options.width && ref.inscatter.height == options.height &&
          ref.final.width == options.width && ref.final.height == options.height) {
        ref.fromCache = true;
        return ref;
      }
    } catch (const std::exception&) {
      // An unreadable cache entry is recomputed below.
    }
  }
  auto start = std::chrono::steady_clock::now();
  auto method = createMethod(registry, resolved.method);
  RunOptions refOptions = options;
  refOptions.frames = 1;
  refOptions.warmup = 0;
  Runner runner(scene, limits, refOptions);
  MethodRun run = runner.run(*method, resolved.params);
  if (run.status != RunStatus::Success)
    throw std::runtime_error("the reference (" + spec + ") failed: " + run.reason);
  ref.inscatter = std::move(run.inscatter);
  ref.final = std::move(run.final);
  ref.computeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  try {
    fs::create_directories(cacheDir);
    writeExr(lsPath, ref.inscatter);
    writeExr(finalPath, ref.final);
    nlohmann::json meta = {{"key_text", keyText},   {"scene", scene.name}, {"scene_source", scene.source},
                           {"method", ref.method},  {"params", ref.params}, {"width", options.width},
                           {"height", options.height}, {"seed", options.seed}, {"compute_ms", ref.computeMs}};
    writeFileAtomic(jsonPath, meta.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "warning: reference not cached (%s)\n", e.what());
  }
  return ref;
}

}  // namespace vs
