// The on-disk cache of computed image pairs (the reference, the ground truth): BASE.ls.exr,
// BASE.final.exr and BASE.json, the JSON written last, so an entry without it is never read.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "harness/io/image.hpp"

namespace vs {

struct CachedImages {
  Image inscatter, final;
  nlohmann::json meta;
};

// The entry at `base` when its JSON's "key_text" is `keyText` and both images are width x height;
// nothing for a missing, unreadable or foreign entry (it is then computed again).
std::optional<CachedImages> readCachedImages(const std::string& base, const std::string& keyText, int width,
                                             int height);
// Writes the entry at `base` (creating its folder); `meta` gains "key_text". A failure only warns on
// stderr: the images are still used, just not cached.
void writeCachedImages(const std::string& base, const std::string& keyText, const Image& inscatter,
                       const Image& final, nlohmann::json meta);

}  // namespace vs
