// libFuzzer target: the scene JSON parser (procedural generators included) on arbitrary bytes.
// Any outcome but a scene or a SceneError is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "scenes/procedural.hpp"
#include "scenes/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool limited = (vs::setGeneratedTriangleLimit(200'000), true);
  (void)limited;
  std::string text(reinterpret_cast<const char*>(data), size);
  try {
    vs::Scene scene = vs::parseSceneJson(text, "/nonexistent-fuzz-folder", "fuzz.json");
    glm::vec3 lo, hi;
    scene.bounds(lo, hi);
    (void)scene.triangleCount();
  } catch (const vs::SceneError&) {
  }
  return 0;
}
