// Ground truth with exact visibility: the same single-scattering model as every method
// (README "What is computed"), integrated on the CPU in double precision, with first hits and
// light visibility traced by Embree against the real triangles instead of a shadow map. For small
// images: it checks the ray-marched reference itself and separates shadow-map aliasing from a
// method's own error.
#pragma once
#include <functional>
#include <string>

#include "harness/io/image.hpp"
#include "scenes/scene.hpp"

namespace vs {

struct GroundTruthOptions {
  int width = 64, height = 48;
  int steps = 2048;   // stratified samples per camera ray
  int lightSamples = 64;  // area lights: points on the light per sample (rounded to a square)
  uint32_t seed = 1;
  int threads = 0;    // 0: hardware threads
};

struct GroundTruth {
  Image inscatter, final;
  double computeMs = 0;
  bool fromCache = false;
  std::string cacheKey, cachePath;  // set by obtainGroundTruth
};

// Empty when the ground truth can integrate `scene`; otherwise why not (e.g. light textures).
std::string groundTruthUnsupported(const Scene& scene);
// Throws std::runtime_error when unsupported. progress(rowsDone, rows) is called from one thread.
GroundTruth renderGroundTruth(const Scene& scene, const GroundTruthOptions& options,
                              const std::function<void(int, int)>& progress = {});
// renderGroundTruth through an on-disk cache in `cacheDir`, keyed by the scene's content, size,
// steps, light samples, seed and this code's source (a second run at the same settings reads it).
// The number of threads does not change the result and is not part of the key.
GroundTruth obtainGroundTruth(const Scene& scene, const GroundTruthOptions& options, const std::string& cacheDir,
                              const std::function<void(int, int)>& progress = {});

}  // namespace vs
