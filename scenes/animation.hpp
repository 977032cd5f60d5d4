// Scenes that move: keyframed tracks for the camera and the light, played at a fixed frame rate.
// Frame i shows the scene at t_i = (i mod frameCount) / fps, a pure function of the frame index
// (never of the wall clock), so every run renders the same sequence.
#pragma once
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace vs {

struct Camera;
struct Light;
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

struct Animation {
  double duration = 0.0;  // seconds; 0: the scene does not move
  double fps = 24.0;
  Track<glm::vec3> cameraPosition, cameraTarget;
  Track<float> cameraFov;
  Track<glm::vec3> lightPosition, lightDirection, lightTarget, lightTangent;
  Track<float> lightIntensity, lightWidth, lightHeight, lightRadius;

  bool moves() const { return duration > 0.0; }
  bool movesCamera() const { return !cameraPosition.empty() || !cameraTarget.empty() || !cameraFov.empty(); }
  bool movesLight() const;
  // Frames in one pass of the sequence: t = 0, 1/fps, ..., up to the duration.
  int frameCount() const;
  double timeOf(uint32_t frameIndex) const;
  // "2 s at 24 fps (49 frames): camera position, light direction", or "" for a still scene.
  std::string describe() const;
  // Sets the animated members of `camera` and `light` to their values at time t (the others stay).
  void apply(double t, Camera& camera, Light& light) const;
};

// The scene as it is at time t: camera and light from the tracks, no animation left; its content
// hash names the time, so that cached references of different frames never mix.
Scene sceneAt(const Scene& scene, double t);

}  // namespace vs
