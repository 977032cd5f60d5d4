// libFuzzer target: OBJ loading on arbitrary bytes, through files as the loader reads them. The bytes
// before the first line "#fuzz.mtl" are the OBJ; the bytes after that line are written beside it as
// `fuzz.mtl` (an OBJ names it with `mtllib fuzz.mtl`), so that material libraries are fuzzed too;
// without the line there is no MTL file. Any outcome but meshes with valid indices or a SceneError
// is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "scenes/obj_loader.hpp"

namespace {

void writeOrRemove(const std::filesystem::path& path, const uint8_t* data, size_t size, bool write) {
  std::error_code ignored;
  if (!write) {
    std::filesystem::remove(path, ignored);
    return;
  }
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("vshadow-obj-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  static const std::string marker = "#fuzz.mtl\n";
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const size_t split = bytes.find(marker);
  const bool hasMtl = split != std::string::npos;
  const size_t objSize = hasMtl ? split : size;
  writeOrRemove(dir / "model.obj", data, objSize, true);
  writeOrRemove(dir / "fuzz.mtl", hasMtl ? data + split + marker.size() : nullptr,
                hasMtl ? size - split - marker.size() : 0, hasMtl);
  std::vector<std::string> warnings;
  try {
    for (const auto& mesh : vs::loadObj((dir / "model.obj").string(), glm::mat4(1.0f), nullptr, &warnings))
      for (uint32_t index : mesh.indices)
        if (index >= mesh.positions.size()) __builtin_trap();
  } catch (const vs::SceneError&) {
  }
  for (const std::string& warning : warnings)
    if (warning.find('\n') != std::string::npos) __builtin_trap();  // warnings are one line each
  return 0;
}
