// libFuzzer target: OBJ loading on arbitrary bytes, through a file as the loader reads files. Any
// outcome but meshes with valid indices or a SceneError is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <glm/glm.hpp>
#include <string>

#include "scenes/obj_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("vshadow-obj-fuzz-" + std::to_string(::getpid()) + ".obj")).string();
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    for (const auto& mesh : vs::loadObj(path, glm::mat4(1.0f)))
      for (uint32_t index : mesh.indices)
        if (index >= mesh.positions.size()) __builtin_trap();
  } catch (const vs::SceneError&) {
  }
  return 0;
}
