// minmax_benchmark: the paper's equal-quality comparison (Chen et al. 2011, Table 1 / Fig. 6) on the
// built-in scenes room, trees and terrain, a shadow-map resolution sweep, and the pass breakdown.
// Usage: minmax_benchmark [WIDTHxHEIGHT] (default 256x192). Prints tables; not a test.
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "harness/app.hpp"
#include "harness/context.hpp"
#include "harness/metrics.hpp"
#include "harness/runner.hpp"
#include "harness/thread_pinning.hpp"
#include "registry.hpp"

namespace {

using namespace vs;

struct Measured {
  MethodRun run;
  double scatterMs = 0;  // the method's own passes (everything but the shared ones)
  double rmse = 0;
};

const std::vector<std::string> kSharedPasses = {"Shadow Map", "G Buffer", "Direct Lighting", "Composite", "Frame"};

Measured measure(const Scene& scene, const std::string& spec, const gl::Limits& limits, int w, int h, int frames,
                 const Image* reference) {
  Measured m;
  m.run = benchmarkSpec(scene, spec, limits, w, h, frames);
  if (m.run.status != RunStatus::Success) {
    std::printf("  %s: %s\n", spec.c_str(), m.run.reason.c_str());
    return m;
  }
  for (const auto& [name, stats] : m.run.passStats) {
    bool shared = false;
    for (const auto& s : kSharedPasses) shared = shared || s == name;
    if (!shared) m.scatterMs += stats.medianMs;
  }
  if (reference) m.rmse = compareImages(m.run.inscatter, *reference).rmse;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  int w = 256, h = 192;
  if (argc > 1 && std::sscanf(argv[1], "%dx%d", &w, &h) != 2) {
    std::fprintf(stderr, "usage: minmax_benchmark [WIDTHxHEIGHT]\n");
    return 2;
  }
  GlContext context(false);
  // Passes are timed by glFinish and the wall clock: the driver's workers, one per CPU.
  const std::string pinning = describe(pinDriverThreads("on", true));
  gl::installDebugOutput(false);
  gl::Limits limits = gl::queryLimits();
  std::printf("provenance: %s\n", provenanceLine(context.info()).c_str());
  std::printf("threads: %s\n", pinning.c_str());
  std::printf("image %dx%d, wall-clock pass timer (glFinish-bracketed), %s\n", w, h, benchmarkFramesNote(3).c_str());
  std::printf("reference: raymarch steps=4096 at the same shadow map; scattering time = the method's own passes\n\n");

  const std::vector<std::string> scenes = {"room", "trees", "terrain"};
  const std::vector<int> steps = {8, 16, 32, 64, 128, 256, 512, 1024};
  std::map<std::string, Measured> minmaxRuns;

  std::printf("== Equal quality (Table 1 / Fig. 6), sm=1024 ==\n");
  std::printf("%-8s %12s %12s %14s %12s %12s %9s\n", "scene", "minmax_rmse", "minmax_ms", "raymarch_steps",
              "rm_rmse", "raymarch_ms", "speedup");
  for (const auto& name : scenes) {
    Scene scene = loadScene(name);
    Measured ref = measure(scene, "raymarch:steps=4096:sm=1024", limits, w, h, 0, nullptr);
    Measured mm = measure(scene, "minmax:sm=1024", limits, w, h, 3, &ref.run.inscatter);
    minmaxRuns[name] = mm;
    Measured match;
    int matchSteps = 0;
    for (int n : steps) {
      match = measure(scene, "raymarch:sm=1024:steps=" + std::to_string(n), limits, w, h, 3, &ref.run.inscatter);
      matchSteps = n;
      if (match.rmse <= mm.rmse) break;
    }
    std::printf("%-8s %12.4e %12.1f %14d %12.4e %12.1f %8.2fx\n", name.c_str(), mm.rmse, mm.scatterMs, matchSteps,
                match.rmse, match.scatterMs, mm.scatterMs > 0 ? match.scatterMs / mm.scatterMs : 0.0);
    std::fflush(stdout);
  }

  // The tables below: every figure the median of kRounds rounds, the rows measured in turn in
  // each round (no row pays for being first), [min-max] over the rounds beside it.
  const int kRounds = 3;
  auto scatterOf = [](const MethodRun& r) {
    double ms = 0.0;
    for (const auto& [name, stats] : r.passStats)
      if (std::find(kSharedPasses.begin(), kSharedPasses.end(), name) == kSharedPasses.end()) ms += stats.medianMs;
    return ms;
  };

  std::printf("\n== Shadow-map resolution: minmax scattering time (ms), median [min–max] of %d interleaved rounds ==\n",
              kRounds);
  std::printf("%-8s %20s %20s %20s\n", "scene", "1K", "2K", "4K");
  for (const auto& name : scenes) {
    Scene scene = loadScene(name);
    std::vector<std::string> specs = {"minmax:sm=1024", "minmax:sm=2048", "minmax:sm=4096"};
    auto ms = measureInterleaved(scene, specs, limits, w, h, 2, kRounds, scatterOf);
    std::printf("%-8s", name.c_str());
    for (const Spread& t : ms) std::printf(" %20s", spreadCell(t).c_str());
    std::printf("\n");
    std::fflush(stdout);
  }

  // Rows of the pass breakdown: the three scenes, and room under a textured light (a checker gobo
  // on its light), which adds Light Texture Precomputation and per-slice prefix tables (§4.2).
  std::vector<std::pair<std::string, Scene>> rows;
  for (const auto& name : scenes) rows.emplace_back(name, loadScene(name));
  Scene textured = loadScene("room");
  textured.light.textureWidth = textured.light.textureHeight = 16;
  textured.light.textureRGB.resize(16 * 16 * 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c)
        textured.light.textureRGB[size_t((y * 16 + x) * 3 + c)] = ((x / 4 + y / 4) % 2 == 0) ? 1.0f : 0.25f;
  rows.emplace_back("room+tex", std::move(textured));
  std::vector<std::vector<MethodRun>> runs(rows.size());
  for (int round = 0; round < kRounds; ++round)
    for (size_t i = 0; i < rows.size(); ++i) {
      MethodRun r = benchmarkSpec(rows[i].second, "minmax:sm=1024", limits, w, h, 3);
      if (r.status == RunStatus::Success) runs[i].push_back(std::move(r));
      else std::printf("  %s: %s\n", rows[i].first.c_str(), r.reason.c_str());
    }

  std::printf("\n== Pass breakdown at sm=1024 (ms, layout of Table 1), median [min–max] of %d interleaved rounds ==\n",
              kRounds);
  const std::vector<std::pair<std::string, std::string>> columns = {
      {"Shadow Map", "ShadowMap"},      {"Shadow Map Rectification", "Rectify"}, {"Low-Rank Approximation", "LowRank"},
      {"Light Texture Precomputation", "LightTex"}, {"Mipmap Construction", "Mipmap"}, {"Integration", "Integrate"},
      {"Near Epipole", "NearEpi"}};
  std::printf("%-9s", "scene");
  for (const auto& c : columns) std::printf(" %18s", c.second.c_str());
  std::printf(" %18s %18s\n", "Scatter", "Frame");
  for (size_t i = 0; i < rows.size(); ++i) {
    std::printf("%-9s", rows[i].first.c_str());
    for (const auto& c : columns) {
      const std::string pass = c.first;
      std::printf(" %18s", spreadCell(spreadOf(runs[i], [&pass](const MethodRun& r) { return r.passMs(pass); })).c_str());
    }
    std::printf(" %18s %18s\n", spreadCell(spreadOf(runs[i], scatterOf)).c_str(),
                spreadCell(spreadOf(runs[i], [](const MethodRun& r) { return r.frame.medianMs; })).c_str());
  }
  return 0;
}
