#include "scenes/animation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scenes/content_hash.hpp"
#include "scenes/scene.hpp"

namespace vs {

const char* interpolationName(Interpolation mode) {
  switch (mode) {
    case Interpolation::Linear:
      return "linear";
    case Interpolation::Step:
      return "step";
    case Interpolation::CatmullRom:
      return "catmull-rom";
  }
  return "?";
}

template <typename T>
T Track<T>::at(double t) const {
  const size_t n = times.size();
  if (n == 0) return T{};
  if (n == 1 || t <= double(times.front())) return values.front();
  if (t >= double(times.back())) return values.back();
  // The key span [k, k+1] that holds t.
  size_t k = size_t(std::upper_bound(times.begin(), times.end(), float(t)) - times.begin()) - 1;
  k = std::min(k, n - 2);
  if (mode == Interpolation::Step) return values[k];
  const double t0 = times[k], t1 = times[k + 1];
  const double h = t1 - t0;  // > 0: times strictly increase (checked at load)
  const float u = h > 0.0 ? float(std::clamp((t - t0) / h, 0.0, 1.0)) : 0.0f;
  if (mode == Interpolation::Linear) return values[k] + (values[k + 1] - values[k]) * u;
  // Hermite basis with tangents (per unit time) from the neighbouring keys, scaled to the span.
  auto tangent = [&](size_t i) {
    size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, n - 1);
    double span = double(times[b]) - double(times[a]);
    return span > 0.0 ? (values[b] - values[a]) * float(h / span) : T{};
  };
  const float u2 = u * u, u3 = u2 * u;
  return values[k] * (2 * u3 - 3 * u2 + 1) + tangent(k) * (u3 - 2 * u2 + u) + values[k + 1] * (-2 * u3 + 3 * u2) +
         tangent(k + 1) * (u3 - u2);
}

template struct Track<float>;
template struct Track<glm::vec3>;

bool Animation::movesLight() const {
  return !lightPosition.empty() || !lightDirection.empty() || !lightTarget.empty() || !lightTangent.empty() ||
         !lightIntensity.empty() || !lightWidth.empty() || !lightHeight.empty() || !lightRadius.empty();
}

int Animation::frameCount() const {
  if (!moves()) return 1;
  return int(std::floor(duration * fps + 1e-9)) + 1;
}

double Animation::timeOf(uint32_t frameIndex) const {
  if (!moves()) return 0.0;
  return double(frameIndex % uint32_t(frameCount())) / fps;
}

std::string Animation::describe() const {
  if (!moves()) return "";
  std::vector<std::string> tracks;
  auto add = [&](bool present, const char* name) {
    if (present) tracks.push_back(name);
  };
  add(!cameraPosition.empty(), "camera position");
  add(!cameraTarget.empty(), "camera target");
  add(!cameraFov.empty(), "camera fov");
  add(!lightPosition.empty(), "light position");
  add(!lightDirection.empty(), "light direction");
  add(!lightTarget.empty(), "light target");
  add(!lightTangent.empty(), "light tangent");
  add(!lightIntensity.empty(), "light intensity");
  add(!lightWidth.empty() || !lightHeight.empty() || !lightRadius.empty(), "light size");
  char head[96];
  std::snprintf(head, sizeof head, "%g s at %g fps (%d frames)", duration, fps, frameCount());
  std::string text = head;
  for (size_t i = 0; i < tracks.size(); ++i) text += (i == 0 ? ": " : ", ") + tracks[i];
  return text;
}

void Animation::apply(double t, Camera& camera, Light& light) const {
  if (!moves()) return;
  if (!cameraPosition.empty()) camera.position = cameraPosition.at(t);
  if (!cameraTarget.empty()) camera.target = cameraTarget.at(t);
  if (!cameraFov.empty()) camera.fovYDeg = cameraFov.at(t);
  if (!lightPosition.empty()) light.position = lightPosition.at(t);
  if (!lightIntensity.empty()) light.intensity = std::max(lightIntensity.at(t), 0.0f);
  if (!lightWidth.empty()) light.width = lightWidth.at(t);
  if (!lightHeight.empty()) light.height = lightHeight.at(t);
  if (!lightRadius.empty()) light.radius = lightRadius.at(t);
  // Directions are unit vectors: interpolated, then normalised (a zero is refused at load, where
  // every frame of the sequence is checked).
  auto unit = [](glm::vec3 v, glm::vec3 fallback) {
    float len = glm::length(v);
    return len > 1e-12f && std::isfinite(len) ? v / len : fallback;
  };
  if (!lightDirection.empty()) light.direction = unit(lightDirection.at(t), light.direction);
  if (!lightTarget.empty()) light.direction = unit(lightTarget.at(t) - light.position, light.direction);
  if (!lightTangent.empty() || !lightDirection.empty() || !lightTarget.empty()) {
    glm::vec3 tangent = lightTangent.empty() ? light.tangent : lightTangent.at(t);
    tangent -= light.direction * glm::dot(tangent, light.direction);
    glm::vec3 fallback = std::fabs(light.direction.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    light.tangent = unit(tangent, glm::normalize(glm::cross(light.direction, fallback)));
  }
}

Scene sceneAt(const Scene& scene, double t) {
  Scene still = scene;
  if (!scene.animation.moves()) return still;
  scene.animation.apply(t, still.camera, still.light);
  still.animation = Animation{};
  ContentHasher hasher;
  hasher.addBlock(scene.contentHash);
  char time[64];
  std::snprintf(time, sizeof time, "t=%.9g", t);
  hasher.addBlock(std::string(time));
  still.contentHash = hasher.hex();
  return still;
}

}  // namespace vs
