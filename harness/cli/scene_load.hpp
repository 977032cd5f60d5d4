// Loading the scene of a command: a progress bar on a terminal while a large scene loads, and what
// the load took, for meta.json's "scene_load".
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "scenes/scene.hpp"

namespace vs {

struct SceneLoad {
  double ms = 0.0;                   // wall-clock time of loadScene
  size_t triangles = 0, vertices = 0;
  size_t bytes = 0;                  // Scene::dataBytes(): vertices, indices, textures, volumes
  // Growth of the process's peak resident set over its resident set before the load (Linux
  // /proc/self/status VmHWM and VmRSS; the peak is reset before the load through
  // /proc/self/clear_refs where allowed, otherwise the growth of the peak so far). -1: unknown.
  long long peakRssDeltaBytes = -1;
};

// loadScene with a StepProgress ("loading scene NAME") fed by the loaders' stages; fills `figures`.
// Throws what loadScene throws.
Scene loadSceneMeasured(const std::string& nameOrPath, SceneLoad& figures);

// {"ms", "triangles", "vertices", "bytes", "peak_rss_delta_bytes"} (null when unknown).
nlohmann::json toJson(const SceneLoad& figures);

}  // namespace vs
