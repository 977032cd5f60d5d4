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
// opacity. Malformed v/vn/vt/f lines and out-of-range indices are SceneErrors "<path>:<line>:
// <problem>"; other statements (l, p, s, curves, ...) are ignored. A material library that cannot
// be read, or a `usemtl` the libraries lack, is not an error (downloaded OBJs often come without
// their MTL, and in-scattering does not depend on albedo): one warning "<path>:<line>: ..." is
// added to `warnings` and its faces are opaque with the default albedo. When `hasher` is given,
// the OBJ and its MTL files are added to it. In the MTL files, a `Kd`, `d` or `Tr` whose values are
// not numbers is a SceneError "<mtl path>:<line>: <problem>" (tinyobjloader would read them as 0).
// `progress` hears of the stages ("model.obj: checking", "parsing", "building meshes").
std::vector<Mesh> loadObj(const std::string& path, const glm::mat4& transform, ContentHasher* hasher = nullptr,
                          std::vector<std::string>* warnings = nullptr, const LoadProgress& progress = {});

}  // namespace vs
