// libFuzzer target: raw volume files. The first 8 bytes choose the voxel type, the dims (1-16 per
// axis) and the header size; the rest is the file. Any outcome but a volume of the stated size
// with finite, non-negative densities, or a SceneError, is a finding.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "scenes/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 8) return 0;
  static const std::string dir = std::filesystem::temp_directory_path().string();
  static const std::string raw = dir + "/vshadow-volume-fuzz-" + std::to_string(::getpid()) + ".raw";
  FILE* f = std::fopen(raw.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 8, 1, size - 8, f);
  std::fclose(f);
  static const char* types[4] = {"u8", "u16", "f32", "u32"};  // u32: an unknown type
  std::string scene = R"({"geometry": [], "camera": {"position": [0, 1, 5], "target": [0, 0, 0]},
    "light": {"type": "point", "position": [0, 3, 0], "intensity": 1},
    "volumes": [{"raw": ")" + raw + R"(", "type": ")" + types[data[0] % 4] + R"(", "dims": [)" +
                      std::to_string(data[1] % 17) + ", " + std::to_string(data[2] % 17) + ", " +
                      std::to_string(data[3] % 17) + R"(], "header_bytes": )" + std::to_string(data[4] % 8) +
                      R"(, "box_min": [0, 0, 0], "box_max": [1, 1, 1]}]})";
  try {
    vs::Scene s = vs::parseSceneJson(scene, "", "fuzz.json");
    const vs::Volume& v = s.volumes.at(0);
    if (v.density.size() != v.voxelCount()) __builtin_trap();
    for (float d : v.density)
      if (!std::isfinite(d) || d < 0.0f) __builtin_trap();
    if (!std::isfinite(v.densityAt(glm::vec3(0.5f)))) __builtin_trap();
  } catch (const vs::SceneError&) {
  }
  return 0;
}
