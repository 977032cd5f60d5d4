// Scenes that move: keyframed tracks for the camera, the light and the geometry entries' rigid
// transforms, played at a fixed frame rate.
// Frame i shows the scene at t_i = (i mod frameCount) / fps, a pure function of the frame index
// (never of the wall clock), so every run renders the same sequence.
#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace vs {

struct Camera;
struct Light;
struct Mesh;
struct Scene;

enum class Interpolation { Linear, Step, CatmullRom };
// "linear", "step", "catmull-rom" (the scene-file names).
const char* interpolationName(Interpolation mode);

// Keys at strictly increasing times; before the first key the first value, after the last the last.
// Linear and step as their names say; catmull-rom: a C1 Hermite curve through the keys whose
// tangents are the neighbours' difference over their time span (one-sided at the ends).
template <typename T>
struct Track {
  std::vector<float> times;
  std::vector<T> values;
  Interpolation mode = Interpolation::Linear;
  bool empty() const { return times.empty(); }
  T at(double t) const;
};

// One glTF animation sampler driving a node's translation, rotation or scale: keys of up to four
// components (a rotation is the quaternion x, y, z, w). STEP holds a key, LINEAR interpolates
// (slerp for rotations), CUBICSPLINE is glTF's Hermite spline through the keys with their in- and
// out-tangents. Before the first key the first value, after the last the last.
struct KeyedChannel {
  enum class Mode { Step, Linear, CubicSpline };
  std::vector<float> times;
  std::vector<glm::vec4> values, inTangents, outTangents;  // tangents: CUBICSPLINE only
  Mode mode = Mode::Linear;
  bool rotation = false;
  bool empty() const { return times.empty(); }
  glm::vec4 at(double t) const;
};

// A glTF file's node hierarchy and animation clips, kept to move its meshes (node animations).
struct GltfRig {
  struct Node {
    int parent = -1;
    bool hasMatrix = false;  // given by 'matrix' (glTF forbids animating such a node)
    glm::mat4 matrix{1.0f};
    glm::vec3 translation{0.0f}, scale{1.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  };
  struct NodeChannels {
    KeyedChannel translation, rotation, scale;
  };
  struct Clip {
    std::string name;
    float duration = 0.0f;  // its last key time
    std::map<int, NodeChannels> nodes;
  };
  glm::mat4 placement{1.0f};  // the scene entry's translate, scale and rotate_y_deg
  std::vector<Node> nodes;
  std::vector<Clip> clips;
  // The node's world transform (placement included) at time t of clip `clip` (-1: at rest).
  glm::mat4 worldAt(int node, int clip, double t) const;
};

// One geometry entry's motion: p(t) = pivot + translate(t) + R(axis, angle(t)) scale(t) (p - pivot),
// applied to the entry's meshes as loaded (their rest pose). Absent tracks: no translation, angle 0,
// scale 1. Rigid motion with uniform scale, so normals only rotate.
struct GeometryMotion {
  std::string entry;          // the entry's name, or "#index" without one
  std::vector<size_t> meshes; // indices into Scene::meshes
  glm::vec3 pivot{0.0f};
  glm::vec3 axis{0.0f, 1.0f, 0.0f};  // unit length
  Track<glm::vec3> translate;
  Track<float> angleDeg, scale;
  glm::mat4 transformAt(double t) const;
  // Or a glTF entry's node animation: clip `clip` of `rig` (the tracks above unused). meshes[k]
  // moves with its node, meshNodes[k], from the rest pose it was loaded in.
  std::shared_ptr<const GltfRig> rig;
  int clip = -1;
  std::vector<int> meshNodes;
  std::vector<glm::mat4> restInverse;  // per mesh: the inverse of its node's world transform at rest
  // The transform that takes meshes[k] from its rest pose to its pose at t.
  glm::mat4 meshTransformAt(size_t k, double t) const;
};

struct Animation {
  double duration = 0.0;  // seconds; 0: the scene does not move
  double fps = 24.0;
  Track<glm::vec3> cameraPosition, cameraTarget;
  Track<float> cameraFov;
  Track<glm::vec3> lightPosition, lightDirection, lightTarget, lightTangent;
  Track<float> lightIntensity, lightWidth, lightHeight, lightRadius;
  std::vector<GeometryMotion> geometry;

  bool moves() const { return duration > 0.0; }
  bool movesCamera() const { return !cameraPosition.empty() || !cameraTarget.empty() || !cameraFov.empty(); }
  bool movesLight() const;
  bool movesGeometry() const { return !geometry.empty(); }
  // Frames in one pass of the sequence: t = 0, 1/fps, ..., up to the duration.
  int frameCount() const;
  double timeOf(uint32_t frameIndex) const;
  // "2 s at 24 fps (49 frames): camera position, light direction", or "" for a still scene.
  std::string describe() const;
  // Sets the animated members of `camera` and `light` to their values at time t (the others stay).
  void apply(double t, Camera& camera, Light& light) const;
  // Places the moving meshes of `meshes` at time t, from their rest pose in `rest` (the scene as
  // loaded; same meshes, same sizes). Meshes of no moving entry are left alone.
  void moveGeometry(double t, const std::vector<Mesh>& rest, std::vector<Mesh>& meshes) const;
};

// The scene as it is at time t: camera, light and geometry from the tracks, no animation left; its
// content hash names the time, so that cached references of different frames never mix.
Scene sceneAt(const Scene& scene, double t);
// The bounds of all geometry over the whole sequence (Scene::motionBounds): a moving scene's light
// frusta and ranges are fitted to them, so that every frame, played or still, is fitted alike.
void sequenceBounds(const Scene& scene, glm::vec3& lo, glm::vec3& hi);

}  // namespace vs
