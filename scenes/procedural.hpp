// Procedural geometry: simple shapes and the generators behind the built-in scenes.
// The make* functions expect parameters inside the ranges listed in scenes/README.md;
// generateMeshes() reads and validates them from JSON. All output is deterministic (seeded).
// Winding is counter-clockwise seen from the side the normals point to; normals point outwards,
// except for `room`, whose faces point into the room.
#pragma once
#include <nlohmann/json.hpp>
#include <glm/glm.hpp>
#include <cstdint>
#include <string>
#include <vector>
#include "scenes/scene.hpp"

namespace vs {

// Bumped whenever a generator's output changes for the same parameters (part of the content hash).
constexpr const char* kProceduralVersion = "procedural-v1";
// Integer mixing (xorshift-multiply) for seeds and lattice values; shared by the generators.
uint64_t mix64(uint64_t x);

// Upper limit on the triangles one generator call may produce (guards against typos like 1e6 segments).
constexpr uint64_t kMaxGeneratedTriangles = 20'000'000;
// The limit in force (kMaxGeneratedTriangles unless lowered, e.g. by a fuzzer that must stay fast).
uint64_t generatedTriangleLimit();
void setGeneratedTriangleLimit(uint64_t limit);

struct PlaneParams {        // horizontal, facing +Y
  glm::vec3 center{0.0f};
  glm::vec2 size{10.0f};    // extent along X and Z
  int subdivisions = 1;     // quads per side
};

struct BoxParams {
  glm::vec3 center{0.0f};
  glm::vec3 size{1.0f};
  glm::vec3 rotateDeg{0.0f};  // Euler angles, applied X then Y then Z
};

struct SphereParams {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  int segments = 32;  // around the Y axis
  int rings = 16;     // pole to pole
};

struct TorusParams {  // ring in the XZ plane before rotation
  glm::vec3 center{0.0f};
  float majorRadius = 1.0f, minorRadius = 0.25f;
  int majorSegments = 48, minorSegments = 16;
  glm::vec3 rotateDeg{0.0f};
};

struct TorusKnotParams {  // (p, q) torus knot lying around the Y axis before rotation
  glm::vec3 center{0.0f};
  float radius = 1.0f;      // outer radius of the knot's centre line
  float tubeRadius = 0.1f;
  int p = 2, q = 3;         // windings around the axis of symmetry / through the hole
  int segments = 256, tubeSegments = 16;
  glm::vec3 rotateDeg{0.0f};
};

enum class Wall { PosX, NegX, PosZ, NegZ };

struct RoomParams {  // closed box seen from inside; optional rectangular window in one wall
  glm::vec3 center{0.0f};  // centre of the floor
  glm::vec3 size{10.0f, 5.0f, 10.0f};
  bool hasWindow = false;
  Wall windowWall = Wall::NegZ;
  glm::vec2 windowCenter{0.0f, 2.5f};  // offset along the wall from its middle, height above the floor
  glm::vec2 windowSize{2.0f, 1.5f};    // width, height
};

struct FenceParams {  // diamond mesh in the local XY plane (facing Z), then rotated about Y
  glm::vec3 center{0.0f};  // bottom centre
  float width = 10.0f, height = 3.0f;
  float mesh = 0.3f;        // diamond diagonal (spacing of parallel wires along X)
  float wireRadius = 0.015f;
  bool frame = true;        // end posts and a top rail
  float frameRadius = 0.045f;
  float rotateYDeg = 0.0f;
};

struct TreeParams {  // recursive branches made of tapered prisms
  glm::vec3 base{0.0f};
  float height = 3.0f;       // trunk length
  float trunkRadius = 0.15f;
  int depth = 6;             // branch generations including the trunk
  int branches = 3;          // children per branch
  float branchAngleDeg = 35.0f;
  float lengthRatio = 0.7f, radiusRatio = 0.65f;
  float jitter = 0.3f;       // 0 = perfectly regular
  int sides = 5;
  uint32_t seed = 1;
};

struct ForestParams {
  glm::vec3 center{0.0f};
  glm::vec2 size{20.0f};     // extent along X and Z
  int count = 10;
  uint32_t seed = 1;
  float minSpacing = 0.0f;
  float scaleJitter = 0.3f;  // each tree is scaled by a factor in [1 - j, 1 + j]
  TreeParams tree;           // base and seed are set per tree
};

struct TerrainParams {  // fractal value noise heightfield: y = center.y + height * noise in [0, 1]
  glm::vec3 center{0.0f};
  glm::vec2 size{50.0f};
  int resolution = 128;     // cells per side
  float height = 5.0f;
  float featureSize = 20.0f;  // wavelength of the first octave
  int octaves = 5;
  float persistence = 0.5f, lacunarity = 2.0f;
  uint32_t seed = 1;
};

struct TriangleParams {  // one triangle, passed through unchecked (may be degenerate or non-finite)
  glm::vec3 vertices[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bool hasNormals = false;
  glm::vec3 normals[3];
};

Mesh makePlane(const PlaneParams& p);
Mesh makeBox(const BoxParams& p);
Mesh makeSphere(const SphereParams& p);
Mesh makeTorus(const TorusParams& p);
Mesh makeTorusKnot(const TorusKnotParams& p);
Mesh makeRoom(const RoomParams& p);
Mesh makeChainlinkFence(const FenceParams& p);
Mesh makeTree(const TreeParams& p);
Mesh makeForest(const ForestParams& p);
Mesh makeTerrain(const TerrainParams& p);
Mesh makeTriangle(const TriangleParams& p);

struct LeafCardsParams {     // square cards scattered in an ellipsoidal crown, random orientations
  glm::vec3 center{0.0f, 3.0f, 0.0f};
  glm::vec3 radius{1.5f};    // crown half-extents
  int count = 400;
  float size = 0.3f;         // card side
  uint32_t seed = 1;
};
Mesh makeLeafCards(const LeafCardsParams& p);  // texture coordinates 0..1 across each card

// Alpha channel of a leaf seen flat on its card (size x size texels): a pointed elliptic blade
// of opacity 0.6 with thinner veins (0.3) and a soft rim falling to 0 over two texels, nothing
// outside it. For leaf cards ("alpha_texture": {"pattern": "leaf"} in a scene's geometry entry).
AlphaTexture makeLeafAlphaTexture(int size);

struct LayersParams {        // `count` horizontal squares stacked `spacing` apart, lowest at center
  glm::vec3 center{0.0f};
  float size = 2.0f;
  int count = 10;
  float spacing = 0.01f;
};
Mesh makeLayers(const LayersParams& p);

// Names accepted by generateMeshes, in documentation order.
const std::vector<std::string>& generatorNames();

// Validates `params` (a JSON object) for generator `name` and builds its meshes, named after the
// generator. Throws SceneError "<origin>: <paramsPath>.<key>: <problem>" on an unknown generator
// (reported at generatorPath), unknown parameter or out-of-range value.
std::vector<Mesh> generateMeshes(const std::string& name, const nlohmann::json& params,
                                 const std::string& origin, const std::string& generatorPath,
                                 const std::string& paramsPath);

}  // namespace vs
