// Scene description shared by the harness and every method: geometry, camera, one light, medium.
#pragma once
#include <glm/glm.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenes/animation.hpp"

namespace vs {

// Any problem with scene input (missing file, malformed JSON/glTF, out-of-range value).
// what() is one line that names the file and the problem.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The alpha channel of a texture (glTF baseColorTexture): row 0 = top, sampled bilinearly between
// texel centres with repeat wrapping at (u, v), v = 0 at the top (glTF convention).
struct AlphaTexture {
  int width = 0, height = 0;
  std::vector<float> alpha;  // width * height, in [0, 1]
  float sample(glm::vec2 uv) const;
};

struct Mesh {
  std::vector<glm::vec3> positions;  // world space
  std::vector<glm::vec3> normals;    // same size as positions, unit length
  std::vector<uint32_t> indices;     // triangle list
  glm::vec3 albedo{0.8f};            // Lambert albedo (glTF baseColorFactor rgb)
  std::string name;
  // Light transmission through the surface: one crossing passes 1 - opacity * (1 - transmittanceColor)
  // per channel; opacity 1 is an opaque occluder, 0 casts no shadow. transmittanceColor 0 (the
  // default) gives grey shadows of transmittance 1 - opacity.
  float opacity = 1.0f;
  glm::vec3 transmittanceColor{0.0f};
  // Per-texel alpha (glTF alphaMode BLEND or MASK with a baseColorTexture): index into
  // Scene::alphaTextures, sampled at `uvs`. BLEND: opacity x texel alpha; MASK (alphaCutoff >= 0):
  // cut out where opacity x texel alpha < alphaCutoff, opaque elsewhere.
  std::vector<glm::vec2> uvs;
  int alphaTexture = -1;
  float alphaCutoff = -1.0f;
  bool isOpaque() const { return opacity >= 1.0f && alphaTexture < 0; }
  // Opacity at a texel alpha (1 without a texture), as every renderer and the ground truth apply it.
  float opacityAt(float texelAlpha) const {
    float a = opacity * texelAlpha;
    return alphaCutoff >= 0.0f ? (a < alphaCutoff ? 0.0f : 1.0f) : a;
  }
  bool hasTransmittanceColor() const { return transmittanceColor != glm::vec3(0.0f); }
  glm::vec3 crossingTransmittance() const { return glm::vec3(1.0f) - opacity * (glm::vec3(1.0f) - transmittanceColor); }
  size_t triangleCount() const { return indices.size() / 3; }
};

// A density grid placed in world space by an axis-aligned box: sigma(x) = density(x) * densityScale
// * (sigmaS, sigmaA) per scene unit, trilinear inside the box (voxel centres), zero outside. The
// coefficients are per colour channel: unequal channels tint the light passing through.
struct Volume {
  std::string name;
  int dims[3] = {0, 0, 0};           // x, y, z voxels
  std::vector<float> density;        // x fastest, then y, then z; finite and >= 0
  glm::vec3 boxLo{-1.0f}, boxHi{1.0f};
  float densityScale = 1.0f;
  glm::vec3 sigmaS{1.0f}, sigmaA{0.0f};  // per unit density and colour channel, 1/scene unit
  glm::vec3 sigmaT() const { return sigmaS + sigmaA; }
  float meanSigmaT() const { return (sigmaT().x + sigmaT().y + sigmaT().z) / 3.0f; }
  bool chromatic() const { return sigmaT().x != sigmaT().y || sigmaT().y != sigmaT().z || sigmaS.x != sigmaS.y || sigmaS.y != sigmaS.z; }
  size_t voxelCount() const { return size_t(dims[0]) * size_t(dims[1]) * size_t(dims[2]); }
  float voxel(int x, int y, int z) const { return density[(size_t(z) * dims[1] + y) * dims[0] + x]; }
  // Trilinear density at a world point (0 outside the box), before densityScale.
  float densityAt(const glm::vec3& p) const;
  float maxDensity() const;
};

struct Camera {
  glm::vec3 position{0, 1, 5};
  glm::vec3 target{0, 1, 0};
  glm::vec3 up{0, 1, 0};
  float fovYDeg = 60.0f;  // vertical field of view
  float nearZ = 0.1f;
  float farZ = 100.0f;
};

enum class LightType { Point, Spot, Directional, Rect, Disk };
// "point", "spot", "directional", "rect", "disk" (the scene-file names).
const char* lightTypeName(LightType type);
// The light-type code shaders see (common.glsl LIGHT_*): 0 point, 1 spot, 2 directional, 3 rect, 4 disk.
int lightTypeCode(LightType type);
inline bool isAreaLight(LightType type) { return type == LightType::Rect || type == LightType::Disk; }

struct Light {
  LightType type = LightType::Point;
  glm::vec3 position{0, 5, 0};       // point and spot
  glm::vec3 direction{0, -1, 0};     // spot and directional: direction the light travels (unit)
  glm::vec3 color{1.0f};
  float intensity = 100.0f;          // point/spot: radiant intensity I (W/sr); directional: irradiance E;
                                     // rect/disk: radiance L (W/(m^2 sr))
  float spotInnerDeg = 20.0f;        // spot: full intensity inside this half-angle
  float spotOuterDeg = 30.0f;        // spot: zero outside this half-angle (also the shadow-map fov)
  // Area lights (rect, disk): a Lambertian emitter of radiance `color * intensity` centred at
  // `position`, facing `direction` (its normal); rect: width along `tangent`, height along
  // normal x tangent; disk: radius. One-sided (cosine emission into the half-space the normal
  // faces) unless twoSided. A small light of area A is a point light of intensity
  // I(w) = radiance * A * |cos| towards w.
  float width = 1.0f, height = 1.0f, radius = 0.5f;
  glm::vec3 tangent{1, 0, 0};
  bool twoSided = false;
  // Point lights only: emission I * cos towards `direction` (|cos| when twoSided) instead of
  // uniform I. A virtual point light of an area light (harness/pipeline/vpl.hpp) is such a light.
  bool cosineLobe = false;
  float area() const;
  // Point on the light for (u, v) in [0, 1)^2 (rect: uniform over the rectangle; disk: concentric map).
  glm::vec3 samplePoint(float u, float v) const;
  // Optional light texture (gobo), linear RGB, row 0 = top. Projection: spot = through the cone,
  // directional = orthographic over the shadow-map extent, point = latitude-longitude around the light.
  std::string texturePath;
  int textureWidth = 0, textureHeight = 0;
  std::vector<float> textureRGB;     // width*height*3
  bool hasTexture() const { return !textureRGB.empty(); }
};

enum class Phase { Isotropic, HenyeyGreenstein };

struct Medium {
  float sigmaS = 0.0f;  // scattering coefficient, 1/scene unit
  float sigmaA = 0.0f;  // absorption coefficient, 1/scene unit
  Phase phase = Phase::Isotropic;
  float g = 0.0f;       // Henyey-Greenstein asymmetry in (-1, 1)
  float sigmaT() const { return sigmaS + sigmaA; }
};

struct Scene {
  std::string name;        // stable name (built-in) or file stem
  std::string source;      // file path or "builtin:NAME"
  std::string description; // one line for `vshadow list`
  std::vector<Mesh> meshes;
  Camera camera;
  Light light;
  Medium medium;
  std::vector<Volume> volumes;  // heterogeneous media, added to the homogeneous `medium`
  std::vector<AlphaTexture> alphaTextures;  // referenced by Mesh::alphaTexture
  std::string contentHash; // hash of the scene's defining text and referenced files (cache keys)
  size_t droppedTriangles = 0;  // degenerate triangles (NaN/Inf vertex, zero area) removed at load
  Animation animation;          // keyframed camera, light and geometry; still unless animation.moves()
  // Geometry that moves: the bounds over the whole sequence (sequenceBounds), kept by sceneAt's
  // still frames, so that bounds() and every fit to it are the same at every frame.
  bool hasMotionBounds = false;
  glm::vec3 motionLo{0.0f}, motionHi{0.0f};
  // What loading assumed where the input was incomplete (an OBJ's missing material library, say),
  // one line each naming the file and line: printed by the commands, recorded in meta.json.
  std::vector<std::string> warnings;

  size_t triangleCount() const;
  size_t vertexCount() const;
  // The bytes the scene's own data takes in memory: mesh vertices (positions, normals, texture
  // coordinates) and indices, alpha and light textures, volume densities.
  size_t dataBytes() const;
  // Axis-aligned bounds of all geometry (over the whole sequence when it moves) and volume boxes;
  // a unit box around the origin when empty.
  void bounds(glm::vec3& lo, glm::vec3& hi) const;
};

// How a long load is going, for a progress bar: `stage` says what is being read ("model.obj:
// parsing", "cleaning meshes"), `fraction` how far that stage is, in [0, 1]. Called at the start of
// each stage and every few tens of thousands of lines or faces within it, on the loading thread.
using LoadProgress = std::function<void(const std::string& stage, double fraction)>;

// Loads a scene by built-in name (see builtinSceneNames) or by path to a .json file.
// Throws SceneError with a one-line message on any problem.
Scene loadScene(const std::string& nameOrPath, const LoadProgress& progress = {});
// Parses scene JSON text; baseDir resolves relative glTF/texture paths; origin names it in errors.
Scene parseSceneJson(const std::string& text, const std::string& baseDir, const std::string& origin,
                     const LoadProgress& progress = {});

struct BuiltinSceneInfo {
  std::string name, description;
};
std::vector<BuiltinSceneInfo> builtinScenes();

}  // namespace vs
