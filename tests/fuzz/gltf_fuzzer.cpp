// libFuzzer target: glTF loading (.gltf JSON and .glb binary, recognised by content) on arbitrary
// bytes, through a file as the loader reads files. Any outcome but content or a SceneError is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <glm/glm.hpp>
#include <string>

#include "scenes/gltf_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("vshadow-gltf-fuzz-" + std::to_string(::getpid()) + ".gltf")).string();
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    vs::GltfContent content = vs::loadGltf(path, glm::mat4(1.0f));
    for (const auto& mesh : content.meshes)
      for (uint32_t index : mesh.indices)
        if (index >= mesh.positions.size()) __builtin_trap();  // the loader must never emit a bad index
  } catch (const vs::SceneError&) {
  }
  return 0;
}
