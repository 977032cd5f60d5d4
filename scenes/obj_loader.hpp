// Wavefront OBJ + MTL geometry (the classic research scenes ship as OBJ), through tinyobjloader.
#pragma once
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "scenes/content_hash.hpp"
#include "scenes/scene.hpp"

namespace vs {

// Loads every face of `path` (polygons triangulated), one mesh per (object, material), in world
// space after `transform`. Materials: Kd is the albedo (clamped to [0, 1]); `d`, or 1 - `Tr`, the
// opacity. Malformed v/vn/vt/f lines, out-of-range indices and missing MTL files are SceneErrors
// "<path>:<line>: <problem>"; other statements (l, p, s, curves, ...) are ignored. When `hasher` is
// given, the OBJ and its MTL files are added to it.
std::vector<Mesh> loadObj(const std::string& path, const glm::mat4& transform, ContentHasher* hasher = nullptr);

}  // namespace vs
