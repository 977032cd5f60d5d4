// vsv_benchmark: equal quality against raymarch, and the paper's Tables 2 and 3 (pass times
// against shadow-map size and against N_theta), printed with the renderer string.
// Usage: vsv_benchmark [WxH] (default 256x192); 3 measured frames per row.
#include <cstdio>
#include <string>

#include "harness/context.hpp"
#include "harness/metrics.hpp"
#include "harness/runner.hpp"
#include "scenes/scene.hpp"

using namespace vs;

static MethodRun runSpec(Runner& runner, const gl::Limits& limits, const std::string& spec) {
  ResolvedSpec r = resolveSpec(spec, limits);
  auto method = createMethod(r.method);
  return runner.run(*method, r.params);
}

static double passMs(const MethodRun& run, const std::string& pass) {
  auto it = run.passStats.find(pass);
  return it == run.passStats.end() ? 0.0 : it->second.medianMs;
}

int main(int argc, char** argv) {
  int width = 256, height = 192;
  if (argc > 1) std::sscanf(argv[1], "%dx%d", &width, &height);
  GlContext context(false);
  gl::Limits limits = gl::queryLimits();
  std::printf("renderer: %s | %s | %dx%d, 3 frames after 1 warm-up, medians\n", context.info().glRenderer.c_str(),
              context.info().glVersion.c_str(), width, height);
  RunOptions options;
  options.width = width;
  options.height = height;
  options.frames = 3;
  options.warmup = 1;

  std::printf("\n## Equal quality against raymarch (L_s RMSE against raymarch:steps=2048)\n");
  std::printf("| scene | vsv RMSE | vsv ms | raymarch steps at equal RMSE | raymarch ms | speedup |\n|---|---|---|---|---|---|\n");
  for (const char* name : {"spheres", "room", "fence"}) {
    Scene scene = loadScene(name);
    Runner runner(scene, limits, options);
    MethodRun ref = runSpec(runner, limits, "raymarch:steps=2048:sm=1024");
    MethodRun v = runSpec(runner, limits, "vsv:sm=1024");
    double vErr = compareImages(v.inscatter, ref.inscatter).rmse;
    int steps = 0;
    double rmMs = 0;
    for (int s = 8; s <= 1024; s *= 2) {
      MethodRun r = runSpec(runner, limits, "raymarch:sm=1024:steps=" + std::to_string(s));
      steps = s;
      rmMs = r.frame.medianMs;
      if (compareImages(r.inscatter, ref.inscatter).rmse <= vErr) break;
    }
    std::printf("| %s | %.5f | %.1f | %d | %.1f | %.2fx |\n", name, vErr, v.frame.medianMs, steps, rmMs,
                rmMs / std::max(v.frame.medianMs, 1e-9));
    std::fflush(stdout);
  }

  Scene scene = loadScene("room");
  Runner runner(scene, limits, options);
  std::printf("\n## Table 2 (room): pass times (ms) against shadow-map size, vsv defaults\n");
  std::printf("| SM size | Shadow Map | G Buffer | Voxelize: From SM | Scan VSV | Compute L_s |\n|---|---|---|---|---|---|\n");
  for (int sm = 512; sm <= 8192; sm *= 2) {
    if (sm > limits.maxCubeMapSize) break;
    MethodRun r = runSpec(runner, limits, "vsv:sm=" + std::to_string(sm));
    std::printf("| %d^2 | %.1f | %.1f | %.1f | %.1f | %.1f |\n", sm, passMs(r, "Shadow Map"), passMs(r, "G Buffer"),
                passMs(r, "Voxelize: From SM"), passMs(r, "Scan VSV"), passMs(r, "Compute L_s"));
    std::fflush(stdout);
  }
  std::printf("\n## Table 3 (room): pass times (ms) against N_theta (sm=1024)\n");
  std::printf("| theta | Voxelize: From SM | Voxelize: Geometry | Scan VSV | Compute L_s |\n|---|---|---|---|---|\n");
  for (int theta = 128; theta <= 2048; theta *= 2) {
    MethodRun sm = runSpec(runner, limits, "vsv:sm=1024:theta=" + std::to_string(theta));
    MethodRun geo = runSpec(runner, limits, "vsv:sm=1024:vox=geom:theta=" + std::to_string(theta));
    std::printf("| %d | %.1f | %.1f | %.1f | %.1f |\n", theta, passMs(sm, "Voxelize: From SM"),
                passMs(geo, "Voxelize: Geometry"), passMs(sm, "Scan VSV"), passMs(sm, "Compute L_s"));
    std::fflush(stdout);
  }
  return 0;
}
