#include "harness/evaluation/image_cache.hpp"

#include <cstdio>
#include <filesystem>

#include "harness/io/results.hpp"
#include "scenes/json_reader.hpp"

namespace vs {

std::optional<CachedImages> readCachedImages(const std::string& base, const std::string& keyText, int width,
                                             int height) {
  namespace fs = std::filesystem;
  const std::string lsPath = base + ".ls.exr", finalPath = base + ".final.exr", jsonPath = base + ".json";
  if (!fs::exists(lsPath) || !fs::exists(finalPath) || !fs::exists(jsonPath)) return std::nullopt;
  try {
    CachedImages entry;
    std::string text, error;
    if (!readFile(jsonPath, text, error)) return std::nullopt;
    entry.meta = nlohmann::json::parse(text);
    if (entry.meta.value("key_text", std::string()) != keyText) return std::nullopt;
    entry.inscatter = readImage(lsPath);
    entry.final = readImage(finalPath);
    for (const Image* img : {&entry.inscatter, &entry.final})
      if (img->width != width || img->height != height) return std::nullopt;
    return entry;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

void writeCachedImages(const std::string& base, const std::string& keyText, const Image& inscatter,
                       const Image& final, nlohmann::json meta) {
  try {
    std::filesystem::create_directories(std::filesystem::path(base).parent_path());
    writeExr(base + ".ls.exr", inscatter);
    writeExr(base + ".final.exr", final);
    meta["key_text"] = keyText;
    writeFileAtomic(base + ".json", meta.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "warning: %s not cached (%s)\n", base.c_str(), e.what());
  }
}

}  // namespace vs
