#include "harness/cli/scene_load.hpp"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "harness/cli/progress.hpp"

namespace vs {

namespace {

// A "Vm...:  N kB" line of /proc/self/status, in bytes; -1 when there is none.
long long statusBytes(const char* key) {
  std::ifstream status("/proc/self/status");
  const std::string prefix = std::string(key) + ":";
  for (std::string line; std::getline(status, line);)
    if (line.rfind(prefix, 0) == 0) {
      long long kb = -1;
      return std::sscanf(line.c_str() + prefix.size(), "%lld", &kb) == 1 && kb >= 0 ? kb * 1024 : -1;
    }
  return -1;
}

// Resets the peak resident set to the current one (Linux >= 4.0); false where not allowed.
bool resetPeakRss() {
  std::ofstream clearRefs("/proc/self/clear_refs");
  return clearRefs && (clearRefs << "5").flush().good();
}

std::string formatSeconds(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", ms / 1000.0);
  return text;
}

}  // namespace

Scene loadSceneMeasured(const std::string& nameOrPath, SceneLoad& figures) {
  const long long peakBefore = resetPeakRss() ? -1 : statusBytes("VmHWM");
  const long long rssBefore = statusBytes("VmRSS");
  StepProgress progress("loading scene " + nameOrPath);
  const auto start = std::chrono::steady_clock::now();
  Scene scene = loadScene(nameOrPath, [&](const std::string& stage, double fraction) { progress.update(stage, fraction); });
  figures.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  figures.triangles = scene.triangleCount();
  figures.vertices = scene.vertexCount();
  figures.bytes = scene.dataBytes();
  const long long peakAfter = statusBytes("VmHWM");
  const long long base = peakBefore >= 0 ? peakBefore : rssBefore;
  figures.peakRssDeltaBytes = peakAfter >= 0 && base >= 0 ? (peakAfter > base ? peakAfter - base : 0) : -1;
  progress.finish(std::to_string(figures.triangles) + " triangles in " + formatSeconds(figures.ms));
  return scene;
}

nlohmann::json toJson(const SceneLoad& figures) {
  return {{"ms", figures.ms},
          {"triangles", figures.triangles},
          {"vertices", figures.vertices},
          {"bytes", figures.bytes},
          {"peak_rss_delta_bytes",
           figures.peakRssDeltaBytes >= 0 ? nlohmann::json(figures.peakRssDeltaBytes) : nlohmann::json(nullptr)}};
}

}  // namespace vs
