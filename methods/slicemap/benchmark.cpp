// slicemap_benchmark: Eisemann & Decoret's Table 1 on the foliage scenes (pass times of the
// transmittance shadow maps beside the paper's), voxelization throughput beside their 1.1 M
// triangles at 70 Hz, the error against the exact ground truth as slices, slicing and resolution
// change, the two lookups, the opaque built-in scenes against every method, and L_s at equal error
// against the brute-force march with exact layered transmittance. Prints Markdown
// (results/slicemap/README.md is this output); not a test.
// Usage: slicemap_benchmark [--quick] [--equal-quality]
//   --quick: small images, for a smoke run; --equal-quality: only the equal-error table
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "harness/cli/app.hpp"
#include "harness/evaluation/ground_truth.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/runner.hpp"
#include "harness/evaluation/step_search.hpp"
#include "registry.hpp"

namespace {

using namespace vs;

double stat(const MethodRun& run, const std::string& key) {
  auto it = run.stats.find(key);
  return it == run.stats.end() ? 0.0 : it->second;
}

// The foliage tree with `cards` leaf cards of side `size` (two triangles each).
Scene treeScene(int cards, double size, const std::string& light) {
  std::string text = R"({"geometry": [
    {"name": "ground", "generator": "plane", "params": {"center": [0, 0, 0], "size": [16, 16]}, "albedo": [0.7, 0.7, 0.65]},
    {"name": "trunk", "generator": "tree", "params": {"base": [0, 0, 0], "height": 2.0, "trunk_radius": 0.14, "depth": 4, "branches": 3, "branch_angle_deg": 40, "seed": 5}, "albedo": [0.35, 0.25, 0.18]},
    {"name": "leaves", "generator": "leaf_cards", "params": {"center": [0, 3.4, 0], "radius": [1.7, 1.2, 1.7], "count": )" +
                     std::to_string(cards) + R"(, "size": )" + std::to_string(size) +
                     R"(, "seed": 11}, "albedo": [0.3, 0.55, 0.2], "opacity": 0.55}],
    "camera": {"position": [0, 2.2, 8.5], "target": [0, 2.4, 0], "up": [0, 1, 0], "fov_y_deg": 60, "near": 0.1, "far": 50},
    "light": )" + light + R"(,
    "medium": {"sigma_s": 0.05, "sigma_a": 0.01, "phase": "isotropic"}})";
  return parseSceneJson(text, ".", "tree");
}
const char* const kPointLight = R"({"type": "point", "position": [0.8, 7.5, -2.5], "color": [1, 1, 1], "intensity": 220})";
const char* const kSun = R"({"type": "directional", "direction": [-0.2, -1, 0.3], "color": [1, 1, 1], "intensity": 3})";

size_t triangles(const Scene& scene, bool opaque) {
  size_t n = 0;
  for (const Mesh& m : scene.meshes)
    if (m.isOpaque() == opaque) n += m.triangleCount();
  return n;
}

// What every section shares.
struct Bench {
  const gl::Limits& limits;
  const Scene& foliage;
  const Scene& chestnut;
  int w, h, side, frames;
  bool quick;
};

// 1. Table 1 of the paper beside ours.
void table1Section(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const Scene& foliage = b.foliage;
  const Scene& chestnut = b.chestnut;
  const int side = b.side;
  const int frames = b.frames;
  std::printf("## Table 1: transmittance shadow maps, %dx%d, %d² slicemaps\n\n", side, side, side);
  std::printf("Eisemann & Decoret report for a chestnut tree of 160,653 polygons (1,493 opaque), 512², on a GeForce 6800 "
              "(frame rate; in brackets per pass: opaque map / near-far maps / slicemap / shading):\n\n"
              "| | SSM | 1 MRT | 2 MRT | 3 MRT |\n|---|---|---|---|---|\n"
              "| uniform | 128 Hz | 60 Hz (<1 / - / 2 / 14 ms) | 50 Hz (<1 / - / 4 / 16 ms) | 40 Hz (<1 / - / 7 / 18 ms) |\n"
              "| local | | 37 Hz (<1 / 3 / 7 / 20 ms) | 29 Hz (<1 / 3 / 9 / 28 ms) | 24 Hz (<1 / 3 / 14 / 32 ms) |\n\n");
  std::printf("Ours: one MRT is one RGBA32UI target of 128 slices (theirs: RGBA8, 32 slices). SSM is the shared passes "
              "alone (Shadow Map + G Buffer + Direct Lighting + Composite, no transmittance); TSM adds Near/Far Maps, "
              "Slicemap and Shading. The scattering march (not in the paper) is listed apart and left out of the "
              "frame rates. The paper's points are lit by one point light; so are these.\n\n");
  std::printf("| scene | triangles (opaque) | slicing | targets | slices | Shadow Map | Near/Far Maps | Slicemap | Shading | SSM frame | TSM frame | TSM Hz | Scattering |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (auto* entry : {&foliage, &chestnut}) {
    const Scene& scene = *entry;
    const char* name = entry == &foliage ? "foliage" : "chestnut (ours)";
    for (const char* slicing : {"uniform", "local"})
      for (int targets : {1, 2, 3, 4, 8}) {
        // The paper's transmittance shadow maps: opaque occluders in the shadow map, the leaves alone in the slicemap.
        std::string spec = "slicemap:res=512:steps=64:opaque=shadowmap:pack=0:slicing=" + std::string(slicing) +
                           ":targets=" + std::to_string(targets);
        Measured m = measure(scene, spec, limits, side, side, frames, nullptr);
        if (!m.ok) continue;
        const MethodRun& r = m.run;
        double ssm = r.passMs(kShadowMapPass) + r.passMs(kGBufferPass) + r.passMs(kDirectLightingPass) + r.passMs(kCompositePass);
        double tsm = ssm + r.passMs("Near/Far Maps") + r.passMs("Slicemap") + r.passMs("Shading");
        std::printf("| %s | %zu (%zu) | %s | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f |\n", name,
                    triangles(scene, false) + triangles(scene, true), triangles(scene, true), slicing, targets,
                    128 * targets, r.passMs(kShadowMapPass), r.passMs("Near/Far Maps"), r.passMs("Slicemap"),
                    r.passMs("Shading"), ssm, tsm, 1000.0 / std::max(tsm, 1e-9), r.passMs("Scattering"));
        std::fflush(stdout);
      }
  }
}

// 2. Voxelization throughput.
void throughputSection(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const int frames = b.frames;
  const bool quick = b.quick;
  std::printf("\n## Voxelization throughput\n\n");
  std::printf("The paper: 1,124,571 triangles into 512×512×96 at 70 Hz uniform, 60 Hz local (≈ 79 M triangles/s, "
              "1.8 G voxels/s). Here: a tree of leaf cards under a directional light (one view), the Slicemap pass "
              "alone (Near/Far Maps beside it).\n\n");
  std::printf("| triangles | slicing | slices | Near/Far Maps ms | Slicemap ms | triangles/s | voxels/s |\n|---|---|---|---|---|---|---|\n");
  Scene big = treeScene(quick ? 20000 : 562286, 0.08, kSun);
  for (const char* slicing : {"uniform", "local"})
    for (int targets : {1, 8}) {
      std::string spec = "slicemap:res=512:steps=1:surface=0:slicing=" + std::string(slicing) + ":targets=" + std::to_string(targets);
      Measured m = measure(big, spec, limits, 64, 48, frames, nullptr);
      if (!m.ok) continue;
      std::printf("| %.0f | %s | %d | %.1f | %.1f | %.3g | %.3g |\n", stat(m.run, "slicemap_triangles"), slicing, 128 * targets,
                  m.run.passMs("Near/Far Maps"), m.run.passMs("Slicemap"), stat(m.run, "slicemap_triangles_per_s"),
                  stat(m.run, "slicemap_voxels_per_s"));
      std::fflush(stdout);
    }
}

// 3. Error against the exact ground truth.
void groundTruthSection(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const Scene& foliage = b.foliage;
  const bool quick = b.quick;
  int gw = quick ? 32 : 96, gh = quick ? 24 : 72;
  std::printf("\n## Error against the exact ground truth, foliage, %dx%d\n\n", gw, gh);
  std::printf("Ground truth: Embree any-hit transmittance through every leaf, double precision, 1024 steps. Each row "
              "changes one parameter from res=512, targets=1, slicing=uniform; steps=1024 so that the march's own noise "
              "stays below the slicemap's error; pack=0 (each class its own targets). L is the final image (surfaces through Shading).\n\n");
  GroundTruthOptions gtOptions;
  gtOptions.width = gw;
  gtOptions.height = gh;
  gtOptions.steps = 1024;
  GroundTruth gt = renderGroundTruth(foliage, gtOptions);
  std::printf("| parameter | value | L_s relMSE | L relMSE |\n|---|---|---|---|\n");
  struct Knob {
    const char* key;
    std::vector<const char*> values;
  };
  for (const Knob& knob : std::vector<Knob>{{"targets", {"1", "2", "4", "8"}},
                                             {"slicing", {"uniform", "local"}},
                                             {"res", {"64", "128", "256", "512", "1024"}}}) {
    for (const char* value : knob.values) {
      std::string spec = std::string("slicemap:steps=1024:pack=0:") + knob.key + "=" + value;
      MethodRun r = benchmarkSpec(foliage, spec, limits, gw, gh, 0);
      if (r.status != RunStatus::Success) continue;
      std::printf("| %s | %s | %.3e | %.3e |\n", knob.key, value, compareImages(r.inscatter, gt.inscatter).relmse,
                  compareImages(r.final, gt.final).relmse);
      std::fflush(stdout);
    }
  }
  MethodRun exactMarch = benchmarkSpec(foliage, baselineSpec(foliage, {"uniform", 1024}), limits, gw, gh, 0);
  std::printf("| raymarch (transmittance map) | steps=1024 | %.3e | %.3e |\n",
              compareImages(exactMarch.inscatter, gt.inscatter).relmse, compareImages(exactMarch.final, gt.final).relmse);
}

// 4. Counting the bits in front: scan or prefix counts.
void lookupSection(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const Scene& foliage = b.foliage;
  const int w = b.w;
  const int h = b.h;
  const int frames = b.frames;
  std::printf("\n## Counting the bits in front: scan (the paper) or prefix counts (ours), foliage %dx%d, 128 steps\n\n", w, h);
  std::printf("| targets | slices | lookup | Prefix Counts ms | Scattering ms |\n|---|---|---|---|---|\n");
  for (int targets : {1, 2, 4, 8})
    for (const char* lookup : {"scan", "prefix"}) {
      Measured m = measure(foliage, "slicemap:steps=128:pack=0:targets=" + std::to_string(targets) + ":lookup=" + lookup, limits,
                           w, h, frames, nullptr);
      if (!m.ok) continue;
      std::printf("| %d | %d | %s | %.1f | %.1f |\n", targets, 128 * targets, lookup, m.run.passMs("Prefix Counts"),
                  m.run.passMs("Scattering"));
      std::fflush(stdout);
    }
}

// 4b. Shared column fetches.
void shareSection(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const Scene& foliage = b.foliage;
  const int w = b.w;
  const int h = b.h;
  const int frames = b.frames;
  std::printf("\n## Visibility of several samples from one column fetch (share), foliage %dx%d, 128 steps\n\n", w, h);
  std::printf("share=S: S consecutive samples take their visibility from the column at the group's middle, each at "
              "its own light depth. L_s relMSE against the reference method's own (`%s`).\n\n", referenceSpec(foliage).c_str());
  std::printf("| res | share | L_s relMSE | Scattering ms |\n|---|---|---|---|\n");
  Measured shareRef = measure(foliage, referenceSpec(foliage), limits, w, h, 0, nullptr);
  for (int res : {128, 512})
    for (int share : {1, 2, 4, 8}) {
      Measured m = measure(foliage, "slicemap:res=" + std::to_string(res) + ":share=" + std::to_string(share), limits, w, h,
                           frames, shareRef.ok ? &shareRef.run.inscatter : nullptr);
      if (!m.ok) continue;
      std::printf("| %d | %d | %.2e | %.1f |\n", res, share, m.relmse, m.run.passMs("Scattering"));
      std::fflush(stdout);
    }
}

// 5. Opaque scenes, every method at its defaults.
void opaqueScenesSection(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const int w = b.w;
  const int h = b.h;
  const int frames = b.frames;
  std::printf("\n## Opaque built-in scenes: every method at its defaults, %dx%d\n\n", w / 2, h / 2);
  std::printf("L_s relMSE against the ray-marched reference (the reference method's own at sm=2048, `%s` on spheres) and "
              "scattering time (the method's own passes). slicemap voxelizes the opaque occluders (opaque=auto).\n\n",
              referenceSpec(loadScene("spheres"), "sm=2048").c_str());
  std::printf("| scene | method | L_s relMSE | scattering ms |\n|---|---|---|---|\n");
  for (const char* name : {"spheres", "room", "fence", "trees", "terrain"}) {
    Scene scene = loadScene(name);
    Measured ref = measure(scene, referenceSpec(scene, "sm=2048"), limits, w / 2, h / 2, 0, nullptr);
    if (!ref.ok) continue;
    for (const auto& info : registeredMethods()) {
      MethodRun r = benchmarkSpec(scene, info.name + ":sm=2048", limits, w / 2, h / 2, frames);
      if (r.status != RunStatus::Success) continue;
      double ms = r.scatterMs();
      std::printf("| %s | %s | %.2e | %.1f |\n", name, info.name.c_str(), compareImages(r.inscatter, ref.run.inscatter).relmse, ms);
      std::fflush(stdout);
    }
  }
}

// 6. Equal L_s error against the brute-force march with exact layered transmittance: the kit's
// step search on equiangular steps, then each setting and its match timed in interleaved rounds.
void equalQualitySection(const Bench& b) {
  const int rounds = b.quick ? 1 : 3;
  std::printf("\n## Equal L_s error against the brute-force march with exact layered transmittance, %dx%d\n\n", b.w, b.h);
  std::printf("Reference: the reference method's own (`%s`). Baseline: raymarch (the reference estimator: the "
              "transmittance map's exact product over every crossing) at fewer steps, equiangular (the stronger march "
              "near a point light; uniform steps are not run), its step count bisected in log(steps) until its L_s "
              "relMSE is at most slicemap's (to within 1/64 of the count above 64 steps). The Transmittance Map "
              "(shared, built for every method) and slicemap's Shading are not counted. Times: each row's two runs "
              "measured in turn, %d rounds of %d frames; the median of the rounds [range], the speed-up the median of "
              "the rounds' ratios [range].\n\n",
              referenceSpec(b.foliage).c_str(), rounds, b.frames);
  EqualQualitySetup setup;
  setup.width = b.w;
  setup.height = b.h;
  setup.frames = b.frames;
  setup.rounds = rounds;
  setup.match = [](BruteForceMatcher& matcher, double target) {
    return std::vector<BaselineMatch>{matcher.matchSteps("equiangular", target)};
  };
  std::vector<std::pair<std::string, EqualQualityRow>> rows;
  for (const Scene* scene : {&b.foliage, &b.chestnut}) {
    const std::string name = scene == &b.foliage ? "foliage" : "chestnut";
    Measured ref = measure(*scene, referenceSpec(*scene), b.limits, b.w, b.h, 0, nullptr);
    if (!ref.ok) continue;
    std::vector<std::string> settings = {"steps=32", "steps=64", "", "steps=256", "res=256", "res=256:steps=64",
                                         "opaque=shadowmap:pack=0", "equiangular=0"};
    if (scene == &b.chestnut) settings = {""};
    for (const std::string& params : settings) {
      std::string spec = "slicemap" + (params.empty() ? "" : ":" + params);
      rows.emplace_back(name + " " + (params.empty() ? "defaults" : params),
                        equalQualityRow(*scene, spec, ref.run.inscatter, b.limits, setup));
    }
  }
  std::printf("%s", equalQualityTable(rows, "scene and slicemap params").c_str());
}

}  // namespace

int main(int argc, char** argv) {
  BenchmarkOptions common = takeBenchmarkOptions(argc, argv);
  bool quick = false, equalOnly = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    else if (std::strcmp(argv[i], "--equal-quality") == 0) equalOnly = true;
    else {
      std::fprintf(stderr, "usage: slicemap_benchmark [--seed N] [--quick] [--equal-quality]\n");
      return 2;
    }
  }
  BenchmarkSession session(common);
  std::printf("# slicemap: slicemaps and transmittance shadow maps, measured\n\n");
  std::printf("Regenerate: `scripts/reproduce slicemap` (two processes of `slicemap_benchmark` with different seeds, "
              "merged).\n\n");
  std::printf("%s", session.preamble("- ").c_str());
  const int frames = quick ? 1 : 3;
  std::printf("- timer: wall clock around each pass (glFinish), %s\n", benchmarkFramesNote(frames).c_str());
  std::printf("- scattering time: Near/Far Maps + Slicemap + Prefix Counts + Scattering (slicemap), Ray Marching (raymarch);\n"
              "  the shared passes (Shadow Map, Transmittance Map, G Buffer, Direct Lighting, Composite) and slicemap's\n"
              "  Shading are listed apart\n\n");
  Scene foliage = loadScene("foliage");
  Scene chestnut = treeScene(quick ? 8000 : 80000, 0.12, kPointLight);
  const Bench b{session.limits(), foliage, chestnut, quick ? 96 : 256, quick ? 72 : 192, quick ? 128 : 512, frames, quick};
  if (!equalOnly) {
    table1Section(b);
    throughputSection(b);
    groundTruthSection(b);
    lookupSection(b);
    shareSection(b);
    opaqueScenesSection(b);
  }
  equalQualitySection(b);
  std::printf("\n%s", session.driftSummary("- ").c_str());
  return 0;
}
