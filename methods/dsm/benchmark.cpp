// dsm_benchmark: deep shadow maps against nested brute-force ray marching at equal L_s error, the
// error of dsm against its knobs (generation steps, view steps, knots, interpolation), and the
// paper's four data sets at their sizes with a 512² map (Shook, Table 1: 180-330 fps, GTX 465).
// Prints Markdown (results/dsm/README.md is this output); not a test.
// Usage: dsm_benchmark [--quick]   (--quick: smaller images, for a smoke run)
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "harness/cli/app.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/runner.hpp"
#include "registry.hpp"

namespace {

using namespace vs;

// The paper's visibility function: fixed opacity thresholds, straight segments in opacity.
const std::string kPaperLayout = "segments=linear:thresholds=absolute";

double stat(const MethodRun& run, const std::string& key) {
  auto it = run.stats.find(key);
  return it == run.stats.end() ? 0.0 : it->second;
}

Scene dataSetScene(const std::string& generator) {
  // One data set in a unit-sized box above a plane, a point light above and to the side.
  std::string box = generator == "cloud" ? R"("box_min": [-2, 0.8, -2], "box_max": [2, 1.05, 2])"
                                          : R"("box_min": [-1, 0.5, -1], "box_max": [1, 2.5, 1])";
  std::string text = R"({"geometry": [{"generator": "plane", "params": {"center": [0, 0, 0], "size": [12, 12]}, "albedo": [0.7, 0.7, 0.7]}],
    "volumes": [{"generator": ")" + generator + R"(", )" + box + R"(, "sigma_s": 3.0, "sigma_a": 0.3}],
    "camera": {"position": [0, 3, 6], "target": [0, 1.2, 0], "fov_y_deg": 50, "near": 0.1, "far": 40},
    "light": {"type": "point", "position": [2.5, 6, 1.5], "intensity": 80},
    "medium": {"sigma_s": 0.0, "sigma_a": 0.0}})";
  return parseSceneJson(text, ".", generator);
}

// Two stacked slabs of different colours under a sun: a tinted absorber above a grey scatterer.
Scene twoColourScene() {
  std::string text = R"({"geometry": [{"generator": "plane", "params": {"center": [0, 0, 0], "size": [40, 40]}, "albedo": [0.6, 0.6, 0.6]}],
    "volumes": [{"generator": "cloud", "scale": 0.5, "box_min": [-6, 2.2, -6], "box_max": [6, 3, 6], "sigma_s": 0, "sigma_a": [0.3, 3, 6]},
                {"dims": [1, 1, 1], "density": [1], "box_min": [-6, 0.6, -6], "box_max": [6, 2, 6], "sigma_s": 0.6, "sigma_a": 0}],
    "camera": {"position": [0, 1.3, 7], "target": [0, 1.6, 0], "fov_y_deg": 50, "near": 0.1, "far": 40},
    "light": {"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 2}})";
  return parseSceneJson(text, ".", "two_colours");
}

// Coloured shadows: one map of the mean extinction (each channel a power of it) against one map
// per colour channel, error against time, the pairs timed in turn.
void colouredShadows(const gl::Limits& limits, int w, int h, int frames, int rounds) {
  std::printf("\n## Coloured shadows: one map or one per colour channel, %dx%d\n\n", w, h);
  std::printf("A cloud absorbing with sigma_a (0.3, 3, 6) per unit density above a grey scattering slab, sun from above: "
              "the slab's light is tinted by the cloud alone, so one map of the mean extinction (`channels=1`, each "
              "channel's transmittance T^ratio) is only an approximation; `channels=3` (the default `auto` here) "
              "generates and reads one map per channel. Times: median [range] over %d rounds in turn.\n\n", rounds);
  Scene scene = twoColourScene();
  Measured ref = measure(scene, referenceSpec(scene), limits, w, h, 0, nullptr);
  if (!ref.ok) return;
  std::printf("| setting | channels | L_s relMSE | L relMSE | DSM Generation ms | Volume March ms | scattering ms |\n"
              "|---|---|---|---|---|---|---|\n");
  for (const char* setting : {"res=256:gen_step=1:view_steps=64", "res=512:gen_step=0.5:view_steps=128"}) {
    std::vector<std::string> specs;
    for (const char* channels : {"1", "3"}) specs.push_back(std::string("dsm:") + setting + ":channels=" + channels);
    auto timed = runInterleaved(scene, specs, limits, w, h, frames, rounds);
    for (size_t i = 0; i < specs.size(); ++i) {
      Measured m = measure(scene, specs[i], limits, w, h, 0, &ref.run.inscatter);
      if (!m.ok || timed[i].empty()) continue;
      double finalErr = compareImages(m.run.final, ref.run.final).relmse;
      std::printf("| %s | %s | %.2e | %.2e | %s | %s | %s |\n", setting, i == 0 ? "1" : "3", m.relmse, finalErr,
                  spreadCell(spreadOf(timed[i], [](const MethodRun& r) { return r.passMs("DSM Generation"); })).c_str(),
                  spreadCell(spreadOf(timed[i], [](const MethodRun& r) { return r.passMs("Volume March"); })).c_str(),
                  spreadCell(spreadOf(timed[i], &MethodRun::scatterMs)).c_str());
      std::fflush(stdout);
    }
  }
}

// What every section shares.
struct Bench {
  const gl::Limits& limits;
  int w, h, sw, sh, frames, rounds;
  bool quick;
};

// The matches' grid of one scene: step counts (factors of sqrt 2 from 16), light steps per voxel and,
// for point lights, uniform and equiangular sampling, each a frame without a warm-up. Each column
// stops at the first step count that reaches every rung's error (down to `lowest`), or that costs
// more than a grid setting that did: no slower setting can be a match, nor its `at least`.
struct Grid {
  std::vector<Measured> baselines;
  std::vector<std::string> specs;
};
Grid baselineGrid(const Bench& b, const Scene& scene, Runner& gridRunner, const Image& reference, double lowest) {
  Grid g;
  double servesAll = 1e300;
  for (double vsteps : {0.25, 0.5, 1.0})
    for (const char* sampling : {"uniform", "equiangular"}) {
      if (scene.light.type == LightType::Directional && std::string(sampling) == "equiangular") continue;
      for (double steps = 16; steps <= (b.quick ? 64 : 1100); steps *= std::sqrt(2.0)) {
        BaselinePoint point{sampling, int(std::lround(steps))};
        point.lightRaySteps = vsteps;
        std::string spec = baselineSpec(scene, point);
        g.baselines.push_back(measureOnce(gridRunner, spec, b.limits, reference));
        g.specs.push_back(spec);
        const Measured& m = g.baselines.back();
        if (!m.ok) continue;
        if (m.relmse <= lowest) servesAll = std::min(servesAll, m.scatterMs);
        if (m.relmse <= lowest || m.scatterMs > servesAll) break;
      }
    }
  return g;
}

// The timed rounds of dsm at its defaults and of their match, per scene (the pass breakdown).
struct DefaultsRuns {
  std::map<std::string, std::vector<MethodRun>> dsm, match;
};

// One rung against the grid: the cheapest grid setting reaching its error, the slowest cheaper one
// that misses it (`at least`), all three timed in turn.
void matchRung(const Bench& b, const Scene& scene, const char* name, const std::string& setting, const std::string& label,
               const Measured& m, const Grid& g, bool isDefaults, DefaultsRuns& defaults) {
  const char* params = label.c_str();
  const auto& baselines = g.baselines;
  int best = -1;
  for (size_t i = 0; i < baselines.size(); ++i)
    if (baselines[i].ok && baselines[i].relmse <= m.relmse &&
        (best < 0 || baselines[i].scatterMs < baselines[size_t(best)].scatterMs))
      best = int(i);
  if (best < 0) {
    std::printf("| %s | %s | %.2e | %.1f | none of the grid reaches it | | | | |\n", name, params, m.relmse, m.scatterMs);
    return;
  }
  int miss = -1;
  for (size_t i = 0; i < baselines.size(); ++i)
    if (baselines[i].ok && baselines[i].relmse > m.relmse && baselines[i].scatterMs < baselines[size_t(best)].scatterMs &&
        (miss < 0 || baselines[i].scatterMs > baselines[size_t(miss)].scatterMs))
      miss = int(i);
  std::vector<std::string> specs = {"dsm:" + setting, g.specs[size_t(best)]};
  if (miss >= 0) specs.push_back(g.specs[size_t(miss)]);
  auto timed = runInterleaved(scene, specs, b.limits, b.w, b.h, b.frames, b.rounds);
  std::vector<double> own, base;
  for (const MethodRun& r : timed[0]) own.push_back(r.scatterMs());
  for (const MethodRun& r : timed[1]) base.push_back(r.scatterMs());
  Spread ratio = ratioSpread(base, own);
  if (ratio.median <= 0.0) return;
  Spread ownMs = spreadOfValues(own), baseMs = spreadOfValues(base);
  if (isDefaults) {
    defaults.dsm[name] = timed[0];
    defaults.match[name] = timed[1];
  }
  std::printf("| %s | %s | %.2e | %s | %s | %.2e | %s | **%.2fx** [%.2f–%.2f] | %.2fx |\n", name, params, m.relmse,
              spreadCell(ownMs).c_str(), g.specs[size_t(best)].substr(9).c_str(), baselines[size_t(best)].relmse,
              spreadCell(baseMs).c_str(), ratio.median, ratio.lo, ratio.hi,
              // A miss that timed slower than the match in the rounds bounds nothing: the match does.
              miss >= 0 ? std::min(spreadOf(timed[2], &MethodRun::scatterMs).median, baseMs.median) / std::max(ownMs.median, 1e-9)
                        : 0.0);
  std::fflush(stdout);
}

// 1. Equal quality on cloud and volumes; returns the defaults' runs for the pass breakdown.
DefaultsRuns equalQualitySection(const Bench& b) {
  const int w = b.w, h = b.h, rounds = b.rounds;
  std::printf("## Equal L_s error against nested ray marching, %dx%d\n\n", w, h);
  std::printf("Each dsm setting is matched with the cheapest raymarch whose L_s relMSE is at most dsm's, on a grid of "
              "step counts (factors of sqrt 2 from 16), light steps per voxel (`vsteps` 0.25, 0.5, 1) and, for point "
              "lights, uniform and equiangular sampling; each (vsteps, sampling) column of the grid stops at the "
              "first step count that reaches every dsm setting's error, or that costs more than a grid setting that did "
              "(no slower setting can be a match); a grid point is one frame without a warm-up, its time only picks the "
              "match. The pair is then timed in turn over %d "
              "rounds: the speedup is the median of the rounds' ratios, with their range. `at least` divides the "
              "median time of the slowest grid setting that still misses dsm's error, and cost less than the match "
              "(timed in the same rounds; the match's own time where that one timed slower), by dsm's median: the grid "
              "steps by sqrt 2, so the true speedup lies between the two (0: no cheaper setting).\n\n",
              rounds);
  std::printf("| scene | dsm params | dsm relMSE | dsm ms | raymarch params | raymarch relMSE | raymarch ms | speedup | at least |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  DefaultsRuns defaults;
  std::vector<std::string> ladder = createMethod("dsm")->qualityLadder();
  const size_t defaultsRung = 2;  // the ladder's middle rung spells out the defaults
  ladder.insert(ladder.begin() + defaultsRung + 1, kPaperLayout);
  for (const char* name : {"cloud", "volumes"}) {
    Scene scene = loadScene(name);
    Measured ref = measure(scene, referenceSpec(scene), b.limits, w, h, 0, nullptr);
    if (!ref.ok) continue;
    RunOptions once = RunOptions::singleFrame(w, h);
    once.seed = BenchmarkSession::current()->seed();
    Runner gridRunner(scene, b.limits, once);
    std::vector<Measured> rungs;
    double lowest = 1e30;
    for (const std::string& setting : ladder) {
      rungs.push_back(measureOnce(gridRunner, "dsm:" + setting, b.limits, ref.run.inscatter));
      if (rungs.back().ok) lowest = std::min(lowest, rungs.back().relmse);
    }
    Grid grid = baselineGrid(b, scene, gridRunner, ref.run.inscatter, lowest);
    for (size_t r = 0; r < ladder.size(); ++r) {
      if (!rungs[r].ok) continue;
      std::string label = r == defaultsRung ? "defaults (" + ladder[r] + ")" : ladder[r];
      matchRung(b, scene, name, ladder[r], label, rungs[r], grid, r == defaultsRung, defaults);
    }
  }
  return defaults;
}

void passBreakdownSection(DefaultsRuns& d) {
  auto& defaults = d.dsm;
  auto& defaultsMatch = d.match;
  std::printf("\nPass breakdown of dsm at its defaults (ms, median [range] over the rounds above). Throughput: dsm's "
              "voxel samples per second in DSM Generation, beside the camera-ray samples per second of the raymarch "
              "that matched the defaults (each of its samples also marches the volume towards the light): \n\n");
  std::printf("| scene | DSM Generation | Volume March | Surface Shadows | Shadow Map | G Buffer | Direct Lighting | frame |"
              " voxel samples/s (generation) | raymarch samples/s (its match) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (auto& [name, runs] : defaults) {
    std::printf("| %s", name.c_str());
    for (const char* pass : {"DSM Generation", "Volume March", "Surface Shadows", kShadowMapPass, kGBufferPass, kDirectLightingPass})
      std::printf(" | %s", spreadCell(spreadOf(runs, [pass](const MethodRun& run) { return run.passMs(pass); })).c_str());
    std::printf(" | %s | %.3g | %.3g |\n", spreadCell(spreadOf(runs, [](const MethodRun& run) { return run.frame.medianMs; })).c_str(),
                spreadOf(runs, [](const MethodRun& run) { return stat(run, "dsm_voxel_samples_per_s"); }).median,
                spreadOf(defaultsMatch[name], [](const MethodRun& run) { return stat(run, "shadow_map_samples_per_s"); }).median);
  }
}

// 2. Error against the knobs.
void knobsSection(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const int sw = b.sw, sh = b.sh, frames = b.frames;
  std::printf("\n## L_s relMSE against the knobs, %dx%d\n\n", sw, sh);
  std::printf("Each row varies one parameter from the defaults (res=512, gen_step=0.5 voxels, gen_steps=512, view_steps=128, "
              "haze_steps=64, knots=3, segments=exponential, thresholds=relative, interp=linear, filter=hardware).\n\n");
  std::printf("| parameter | value | volumes relMSE | volumes ms | cloud relMSE | cloud ms |\n|---|---|---|---|---|---|\n");
  struct Knob {
    const char* key;
    std::vector<const char*> values;
  };
  const std::vector<Knob> knobs = {{"gen_step", {"4", "1", "0.5", "0.25"}},
                                   {"res", {"128", "256", "512", "1024"}},
                                   {"view_steps", {"16", "64", "128", "512"}},
                                   {"haze_steps", {"16", "32", "64", "128"}},
                                   {"segments", {"linear", "exponential"}},
                                   {"thresholds", {"absolute", "relative"}},
                                   {"knots", {"3", "4", "8", "16"}},
                                   {"interp", {"bucket", "smoothstep", "linear"}},
                                   {"filter", {"texels", "hardware"}}};
  std::map<std::string, std::pair<Scene, Image>> refs;
  for (const char* name : {"volumes", "cloud"}) {
    Scene scene = loadScene(name);
    Measured ref = measure(scene, referenceSpec(scene), limits, sw, sh, 0, nullptr);
    if (!ref.ok) continue;
    refs.emplace(name, std::make_pair(scene, ref.run.inscatter));
  }
  for (const auto& knob : knobs)
    for (const char* value : knob.values) {
      std::printf("| %s | %s", knob.key, value);
      for (const char* name : {"volumes", "cloud"}) {
        auto& [scene, ref] = refs.at(name);
        Measured m = measure(scene, std::string("dsm:") + knob.key + "=" + value, limits, sw, sh, frames, &ref);
        std::printf(" | %.2e | %.1f", m.relmse, m.scatterMs);
      }
      std::printf(" |\n");
      std::fflush(stdout);
    }

}

// 3. The paper's data sets.
void dataSetsSection(const Bench& b) {
  const gl::Limits& limits = b.limits;
  const int frames = b.frames;
  const bool quick = b.quick;
  std::printf("\n## The paper's data sets (512² DSM, steps of half a voxel up to 512, 128 view steps, the paper's 3 knots, smoothstep), %dx%d\n\n",
              quick ? 96 : 512, quick ? 96 : 512);
  std::printf("Shook reports 180-330 fps (3.0-5.6 ms per frame) for these on a GTX 465 (DirectX 9).\n\n");
  std::printf("| data set | voxels | DSM Generation ms | Volume March ms | Surface Shadows ms | frame ms | fps | voxel samples/s |\n"
              "|---|---|---|---|---|---|---|---|\n");
  for (const char* generator : {"density_box", "bucky", "rods", "cloud"}) {
    Scene scene = dataSetScene(generator);
    const Volume& v = scene.volumes[0];
    int side = quick ? 96 : 512;
    Measured m = measure(scene, "dsm:res=512:gen_step=0.5:gen_steps=512:view_steps=128:haze_steps=0:interp=smoothstep:" + kPaperLayout, limits, side,
                         side, frames, nullptr);
    if (!m.ok) continue;
    std::printf("| %s | %dx%dx%d | %.1f | %.1f | %.1f | %.1f | %.1f | %.3g |\n", generator, v.dims[0], v.dims[1],
                v.dims[2], m.run.passMs("DSM Generation"), m.run.passMs("Volume March"),
                m.run.passMs("Surface Shadows"), m.run.frame.medianMs, 1000.0 / std::max(m.run.frame.medianMs, 1e-9),
                stat(m.run, "dsm_voxel_samples_per_s"));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  BenchmarkOptions common = takeBenchmarkOptions(argc, argv);
  bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  bool colouredOnly = argc > 1 && std::strcmp(argv[1], "--coloured") == 0;
  if (argc > 2 || (argc > 1 && !quick && !colouredOnly)) {
    std::fprintf(stderr, "usage: dsm_benchmark [--seed N] [--quick | --coloured]\n");
    return 2;
  }
  BenchmarkSession session(common);
  const Bench b{session.limits(), quick ? 96 : 384, quick ? 72 : 288, quick ? 64 : 192, quick ? 48 : 144,
                quick ? 1 : 3, quick ? 1 : 3, quick};
  if (colouredOnly) {
    std::printf("# dsm: coloured shadows, measured\n\n");
    std::printf("Regenerate: `scripts/reproduce dsm` (two processes of `dsm_benchmark --coloured` with "
                "different seeds, merged; under a minute each on 2 cores).\n\n");
    std::printf("%s", session.preamble("- ").c_str());
    std::printf("- timer: wall clock around each pass (glFinish), %s\n", benchmarkFramesNote(b.frames).c_str());
    std::printf("- reference: raymarch steps=4096, vsteps=2 (nested march towards the light)\n");
    colouredShadows(b.limits, b.sw, b.sh, b.frames, b.rounds);
    std::printf("\n%s", session.driftSummary("- ").c_str());
    return 0;
  }
  std::printf("# dsm: deep shadow maps, measured\n\n");
  std::printf("Regenerate: `scripts/reproduce dsm` (two processes of `dsm_benchmark` with different seeds, merged; about "
              "8 minutes each on 2 cores).\n\n");
  std::printf("%s", session.preamble("- ").c_str());
  std::printf("- timer: wall clock around each pass (glFinish), %s\n", benchmarkFramesNote(b.frames).c_str());
  std::printf("- reference: raymarch steps=4096, vsteps=2 (nested march towards the light), same shadow map\n");
  std::printf("- scattering time: DSM Generation + Volume March (dsm), Ray Marching (raymarch); the shared\n"
              "  passes and dsm's Surface Shadows are listed apart\n\n");
  DefaultsRuns defaults = equalQualitySection(b);
  passBreakdownSection(defaults);
  knobsSection(b);
  std::printf("\nColoured shadows (one map or one per colour channel): `dsm_benchmark --coloured`, results/dsm/coloured.md.\n");
  dataSetsSection(b);
  std::printf("\n%s", session.driftSummary("- ").c_str());
  return 0;
}
