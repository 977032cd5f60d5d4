#include "stress.hpp"

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>

#include "harness/pipeline/effects.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/params.hpp"

namespace vs::testing {

namespace {
using json = nlohmann::json;

// Uniform doubles from mt19937_64 bits (std distributions differ between standard libraries).
struct Random {
  std::mt19937_64 engine;
  double uniform(double lo, double hi) { return lo + (hi - lo) * (double(engine() >> 11) * 0x1.0p-53); }
  double logUniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  json point(double lo, double hi, double ylo, double yhi) {
    return json::array({uniform(lo, hi), uniform(ylo, yhi), uniform(lo, hi)});
  }
  bool chance(double p) { return uniform(0, 1) < p; }
};
}  // namespace

std::string randomStressSceneJson(uint32_t seed, uint32_t index) {
  Random r{std::mt19937_64((uint64_t(seed) << 32) ^ (index * 0x9E3779B97F4A7C15ull))};
  json scene = {
      {"geometry",
       json::array({{{"generator", "plane"}, {"params", {{"size", {16, 16}}}}},
                    {{"generator", "box"}, {"params", {{"center", r.point(-3, 3, 0.5, 2)}, {"size", r.point(0.2, 2, 0.2, 3)}}}},
                    {{"generator", "sphere"}, {"params", {{"center", r.point(-3, 3, 0.5, 3)}, {"radius", r.uniform(0.2, 1.5)}, {"segments", 16}}}},
                    {{"generator", "torus"}, {"params", {{"center", r.point(-3, 3, 1, 4)}, {"rotate_deg", r.point(0, 180, 0, 180)}}}}})}};
  json eye = r.point(-8, 8, 0.05, 6);
  json target = r.point(-3, 3, 0, 3);
  scene["camera"] = {{"position", eye},
                     {"target", target},
                     {"fov_y_deg", r.uniform(20, 110)},
                     {"near", r.logUniform(1e-3, 0.5)},
                     {"far", r.uniform(20, 200)}};
  double pick = r.uniform(0, 3);
  json light;
  if (pick < 1) {
    light = {{"type", "point"}, {"position", r.chance(0.1) ? eye : r.point(-6, 6, 0.2, 8)}};
  } else if (pick < 2) {
    double outer = r.uniform(5, 85);
    light = {{"type", "spot"},      {"position", r.point(-6, 6, 0.2, 8)}, {"target", r.point(-3, 3, 0, 1)},
             {"spot_outer_deg", outer}, {"spot_inner_deg", outer * r.uniform(0, 1)}};
  } else if (pick > 2.7) {  // area lights (rect or disk), for ivsv and the per-VPL wrapper
    json dir = r.point(-1, 1, -1, 0.3);
    if (std::fabs(dir[0].get<double>()) + std::fabs(dir[1].get<double>()) + std::fabs(dir[2].get<double>()) < 1e-3)
      dir = json::array({0, -1, 0});
    bool rect = r.chance(0.5);
    light = {{"type", rect ? "rect" : "disk"}, {"position", r.point(-6, 6, 0.2, 8)}, {"direction", dir},
             {"two_sided", r.chance(0.2)}};
    if (rect) {
      light["width"] = r.logUniform(1e-4, 3);
      light["height"] = r.logUniform(1e-4, 3);
    } else {
      light["radius"] = r.logUniform(1e-4, 1.5);
    }
  } else {
    json dir = r.point(-1, 1, -1, 0.3);
    if (std::fabs(dir[0].get<double>()) + std::fabs(dir[1].get<double>()) + std::fabs(dir[2].get<double>()) < 1e-3)
      dir = json::array({0, -1, 0});
    light = {{"type", "directional"}, {"direction", dir}};
  }
  light["intensity"] = light["type"] == "directional" ? r.logUniform(0.1, 10) : r.logUniform(1, 200);
  if (light["type"] == "rect" || light["type"] == "disk") {
    // Power, as a one-sided emitter of head-on intensity 1..50 W/sr (the scene turns it into radiance
    // over the area): a radiance drawn directly left a light of side 1e-4 lighting nothing, and the
    // report's error of area lights said nothing.
    light.erase("intensity");
    light["power"] = M_PI * r.logUniform(1, 50);
  }
  light["color"] = json::array({r.uniform(0.2, 1), r.uniform(0.2, 1), r.uniform(0.2, 1)});
  scene["light"] = light;
  json medium = {{"sigma_s", r.chance(0.1) ? 0.0 : r.logUniform(1e-4, 2)},
                 {"sigma_a", r.chance(0.3) ? 0.0 : r.logUniform(1e-4, 1)}};
  if (r.chance(0.4)) {
    medium["phase"] = "hg";
    medium["g"] = r.uniform(-0.9, 0.9);
  }
  scene["medium"] = medium;
  if (r.chance(0.3)) {  // volume data, for the methods that march it
    const char* generators[] = {"density_box", "bucky", "rods", "cloud"};
    json lo = r.point(-4, 2, -0.5, 3);
    json hi = json::array({lo[0].get<double>() + r.logUniform(0.05, 8), lo[1].get<double>() + r.logUniform(0.05, 8),
                           lo[2].get<double>() + r.logUniform(0.05, 8)});
    scene["volumes"] = json::array({{{"generator", generators[int(r.uniform(0, 3.999))]},
                                     {"box_min", lo},
                                     {"box_max", hi},
                                     {"sigma_s", r.logUniform(1e-3, 20)},
                                     {"sigma_a", r.chance(0.3) ? 0.0 : r.logUniform(1e-3, 5)}}});
    if (r.chance(0.4)) {  // tinted: per-channel absorption (coloured shadows); drawn last, so the rest stays
      double a = r.logUniform(1e-3, 5);
      scene["volumes"][0]["sigma_a"] = json::array({a * r.uniform(0.05, 1.0), a, a * r.uniform(1.0, 4.0)});
    }
  }
  return scene.dump(2);
}

Scene randomStressScene(uint32_t seed, uint32_t index) {
  return parseSceneJson(randomStressSceneJson(seed, index), ".",
                        "stress config " + std::to_string(seed) + "/" + std::to_string(index));
}

void StressSummary::merge(const StressSummary& other) {
  tried += other.tried;
  seconds += other.seconds;
  unsupported += other.unsupported;
  throughVpls += other.throughVpls;
  failures += other.failures;
  nonFinite += other.nonFinite;
  negative += other.negative;
  if (other.worstRelmse > worstRelmse || (other.worstRelmse == worstRelmse && other.worstIndex < worstIndex &&
                                          other.worstRelmse > 0.0)) {
    worstRelmse = other.worstRelmse;
    worstIndex = other.worstIndex;
  }
  if (other.mostNegative < mostNegative) {
    mostNegative = other.mostNegative;
    mostNegativeIndex = other.mostNegativeIndex;
  }
  if (!other.firstFailure.empty() && (firstFailure.empty() || other.firstFailureIndex < firstFailureIndex)) {
    firstFailure = other.firstFailure;
    firstFailureIndex = other.firstFailureIndex;
  }
}

std::vector<StressSummary> runStress(const std::vector<std::string>& methods, const StressOptions& options,
                                     const gl::Limits& limits, const std::function<void(int, int)>& progress,
                                     double* referenceSeconds) {
  using Clock = std::chrono::steady_clock;
  auto secondsSince = [](Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); };
  std::vector<StressSummary> summaries(methods.size());
  std::vector<ResolvedSpec> specs;
  std::vector<ResolvedSpec> wrappedSpecs;  // the same behind the per-VPL wrapper, for area lights
  for (size_t m = 0; m < methods.size(); ++m) {
    summaries[m].method = methods[m];
    std::string spec = methods[m] + ":sm=" + std::to_string(kStressShadowMap);
    ResolvedSpec resolved = resolveSpec(spec, limits);
    // A method's own maps ("res": dsm's deep shadow map, slicemap's slicemaps) at most that size too:
    // dsm's 512² map per face was two thirds of the methods' time.
    if (resolved.params.has("res") && resolved.params.getInt("res") > kStressShadowMap) {
      spec += ":res=" + std::to_string(kStressShadowMap);
      resolved = resolveSpec(spec, limits);
    }
    specs.push_back(resolved);
    wrappedSpecs.push_back(resolveSpec(spec + ":vpls=" + std::to_string(kStressVpls), limits));
  }
  // The reference: referenceMethodFor(the configuration's effects) within the stress's budget: at
  // most kStressReferenceSteps steps (kStressAreaReferenceSteps for area lights), its own shadow
  // maps (the area lights' too) at the methods' size.
  std::map<std::string, ResolvedSpec> referenceSpecs;  // by the reference's spec text
  auto referenceFor = [&](const Scene& scene) -> const ResolvedSpec& {
    Effects effects = deriveEffects(scene);
    ReferenceBudget budget;
    budget.maxSteps = effects.areaLight ? kStressAreaReferenceSteps : kStressReferenceSteps;
    budget.maxShadowMapSize = kStressShadowMap;
    ReferenceMethod reference = referenceMethodFor(effects, registeredMethods(), budget);
    std::string text = reference.name + ":" + reference.params + ":sm=" + std::to_string(kStressShadowMap);
    auto found = referenceSpecs.find(text);
    if (found != referenceSpecs.end()) return found->second;
    return referenceSpecs.emplace(text, resolveSpec(text, limits)).first->second;
  };
  RunOptions run = RunOptions::singleFrame(options.width, options.height);
  int shards = std::max(options.shards, 1);
  int total = 0;
  for (int i = options.shard; i < options.configs; i += shards) ++total;
  int done = 0;
  for (int i = options.shard; i < options.configs; i += shards) {
    Scene scene = randomStressScene(options.seed, uint32_t(i));
    Runner runner(scene, limits, run);
    // Light on the camera ray origin: the integral diverges, no reference to be close to.
    bool singular = scene.light.type != LightType::Directional &&
                    glm::length(scene.light.position - scene.camera.position) < 1e-3f;
    bool referenceTried = false;
    MethodRun ref;
    for (size_t m = 0; m < methods.size(); ++m) {
      StressSummary& summary = summaries[m];
      auto method = createMethod(methods[m]);
      const ResolvedSpec* spec = &specs[m];
      if (!runner.unsupportedReason(*method, spec->params).empty()) {
        // A point-light method meets an area light behind the per-VPL wrapper, as in the shootout.
        if (!isAreaLight(scene.light.type) || !runner.unsupportedReason(*method, wrappedSpecs[m].params).empty()) {
          ++summary.unsupported;
          continue;
        }
        spec = &wrappedSpecs[m];
        ++summary.throughVpls;
      }
      ++summary.tried;
      auto start = Clock::now();
      MethodRun result = runner.run(*method, spec->params);
      summary.seconds += secondsSince(start);
      if (result.status != RunStatus::Success) {
        ++summary.failures;
        if (result.nonFinitePixels > 0) ++summary.nonFinite;
        if (summary.firstFailure.empty()) {
          summary.firstFailure = "config " + std::to_string(i) + ": " + result.reason;
          summary.firstFailureIndex = uint32_t(i);
        }
        continue;
      }
      float lowest = 0.0f;
      for (float v : result.final.rgb) lowest = std::min(lowest, v);
      for (float v : result.inscatter.rgb) lowest = std::min(lowest, v);
      summary.negative += lowest < 0.0f;
      if (lowest < summary.mostNegative) {
        summary.mostNegative = lowest;
        summary.mostNegativeIndex = uint32_t(i);
      }
      if (singular) continue;
      if (!referenceTried) {
        referenceTried = true;
        auto start = Clock::now();
        const ResolvedSpec& reference = referenceFor(scene);
        auto refMethod = createMethod(reference.method);
        ref = runner.run(*refMethod, reference.params);
        if (referenceSeconds) *referenceSeconds += secondsSince(start);
      }
      if (ref.status != RunStatus::Success) continue;
      double relmse = compareImages(result.inscatter, ref.inscatter).relmse;
      if (relmse > summary.worstRelmse) {
        summary.worstRelmse = relmse;
        summary.worstIndex = uint32_t(i);
      }
    }
    if (progress) progress(++done, total);
  }
  return summaries;
}

}  // namespace vs::testing
