// glTF 2.0 (.gltf with embedded or external buffers, and .glb) geometry and KHR_lights_punctual lights.
#pragma once
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>
#include "scenes/animation.hpp"
#include "scenes/content_hash.hpp"
#include "scenes/scene.hpp"

namespace vs {

struct GltfContent {
  // One mesh per triangle primitive instance, in world space. Not yet sanitised: degenerate
  // triangles are still present (the scene loader removes and counts them).
  std::vector<Mesh> meshes;
  // Alpha channels of the textures that BLEND/MASK materials use; Mesh::alphaTexture indexes this.
  std::vector<AlphaTexture> alphaTextures;
  bool hasLight = false;  // the first KHR_lights_punctual light met in the node hierarchy
  Light light;
  // The file's node animations (glTF "animations"), for a scene's animation block to play: the
  // node hierarchy with its rest transforms and every clip's channels (placement: `transform`).
  // Null when the file has none. meshNode[k] is the node whose instance meshes[k] is.
  std::shared_ptr<GltfRig> rig;
  std::vector<int> meshNode;
  // What loading left out (morph-target "weights" channels), one line each.
  std::vector<std::string> warnings;
};

// Loads the default scene (or the first scene, or all root nodes when there is none), applying node
// transforms and then `transform`. The format (.gltf JSON or .glb binary) is recognised by content.
// When `hasher` is given, the file and its external buffers are added to it.
// Throws SceneError "<path>: <problem>" on a missing file, malformed content, an out-of-range index
// or an accessor that does not fit its buffer. `progress` hears of the stages ("model.glb: parsing",
// "reading meshes").
GltfContent loadGltf(const std::string& path, const glm::mat4& transform, ContentHasher* hasher = nullptr,
                     const LoadProgress& progress = {});

}  // namespace vs
