#include "scenes/animation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <glm/gtc/matrix_transform.hpp>

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

glm::mat4 GeometryMotion::transformAt(double t) const {
  const glm::vec3 move = translate.empty() ? glm::vec3(0.0f) : translate.at(t);
  const float angle = angleDeg.empty() ? 0.0f : angleDeg.at(t);
  const float factor = scale.empty() ? 1.0f : scale.at(t);
  glm::mat4 m = glm::translate(glm::mat4(1.0f), pivot + move);
  m = glm::rotate(m, glm::radians(angle), axis);
  m = glm::scale(m, glm::vec3(factor));
  return glm::translate(m, -pivot);
}

glm::vec4 KeyedChannel::at(double t) const {
  const size_t n = times.size();
  if (n == 0) return glm::vec4(0.0f);
  if (n == 1 || t <= double(times.front())) return values.front();
  if (t >= double(times.back())) return values.back();
  size_t k = size_t(std::upper_bound(times.begin(), times.end(), float(t)) - times.begin()) - 1;
  k = std::min(k, n - 2);
  if (mode == Mode::Step) return values[k];
  const double h = double(times[k + 1]) - double(times[k]);
  const float u = h > 0.0 ? float(std::clamp((t - double(times[k])) / h, 0.0, 1.0)) : 0.0f;
  glm::vec4 v;
  if (mode == Mode::CubicSpline) {
    const float u2 = u * u, u3 = u2 * u, span = float(h);
    v = values[k] * (2 * u3 - 3 * u2 + 1) + outTangents[k] * (span * (u3 - 2 * u2 + u)) +
        values[k + 1] * (-2 * u3 + 3 * u2) + inTangents[k + 1] * (span * (u3 - u2));
  } else if (rotation) {
    const glm::quat a(values[k].w, values[k].x, values[k].y, values[k].z);
    const glm::quat b(values[k + 1].w, values[k + 1].x, values[k + 1].y, values[k + 1].z);
    const glm::quat q = glm::slerp(a, glm::dot(a, b) < 0.0f ? -b : b, u);  // the short way round
    return glm::vec4(q.x, q.y, q.z, q.w);
  } else {
    v = values[k] + (values[k + 1] - values[k]) * u;
  }
  if (rotation) {
    const float len = glm::length(v);
    return len > 1e-12f && std::isfinite(len) ? v / len : values[k];
  }
  return v;
}

glm::mat4 GltfRig::worldAt(int node, int clip, double t) const {
  glm::mat4 world(1.0f);
  const Clip* animated = clip >= 0 && size_t(clip) < clips.size() ? &clips[size_t(clip)] : nullptr;
  // Child to root: world = placement * local(root) * ... * local(node).
  for (int guard = 0; node >= 0 && size_t(node) < nodes.size() && guard <= int(nodes.size()); ++guard) {
    const Node& n = nodes[size_t(node)];
    glm::mat4 local = n.matrix;
    if (!n.hasMatrix) {
      glm::vec3 translation = n.translation, scale = n.scale;
      glm::quat rotation = n.rotation;
      if (animated) {
        auto it = animated->nodes.find(node);
        if (it != animated->nodes.end()) {
          if (!it->second.translation.empty()) translation = glm::vec3(it->second.translation.at(t));
          if (!it->second.scale.empty()) scale = glm::vec3(it->second.scale.at(t));
          if (!it->second.rotation.empty()) {
            const glm::vec4 q = it->second.rotation.at(t);
            rotation = glm::quat(q.w, q.x, q.y, q.z);
          }
        }
      }
      local = glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) * glm::scale(glm::mat4(1.0f), scale);
    }
    world = local * world;
    node = n.parent;
  }
  return placement * world;
}

glm::mat4 GeometryMotion::meshTransformAt(size_t k, double t) const {
  if (!rig) return transformAt(t);
  if (k >= meshNodes.size() || k >= restInverse.size()) return glm::mat4(1.0f);
  return rig->worldAt(meshNodes[k], clip, t) * restInverse[k];
}

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
  for (const GeometryMotion& g : geometry) {
    std::string text = "geometry " + g.entry;
    if (g.rig && g.clip >= 0 && size_t(g.clip) < g.rig->clips.size()) {
      const std::string& name = g.rig->clips[size_t(g.clip)].name;
      text += " (glTF animation " + (name.empty() ? std::to_string(g.clip) : "'" + name + "'") + ")";
    }
    tracks.push_back(text);
  }
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

void Animation::moveGeometry(double t, const std::vector<Mesh>& rest, std::vector<Mesh>& meshes) const {
  for (const GeometryMotion& g : geometry) {
    for (size_t k = 0; k < g.meshes.size(); ++k) {
      const size_t index = g.meshes[k];
      if (index >= rest.size() || index >= meshes.size()) continue;
      const glm::mat4 m = g.meshTransformAt(k, t);
      // Normals by the inverse transpose (a glTF scale may be non-uniform), then renormalised.
      const glm::mat3 linear(m);
      const float det = glm::determinant(linear);
      const glm::mat3 rotation = std::fabs(det) > 1e-30f ? glm::transpose(glm::inverse(linear)) : linear;
      const Mesh& from = rest[index];
      Mesh& to = meshes[index];
      for (size_t i = 0; i < from.positions.size() && i < to.positions.size(); ++i)
        to.positions[i] = glm::vec3(m * glm::vec4(from.positions[i], 1.0f));
      for (size_t i = 0; i < from.normals.size() && i < to.normals.size(); ++i) {
        glm::vec3 n = rotation * from.normals[i];
        float len = glm::length(n);
        to.normals[i] = len > 1e-20f ? n / len : from.normals[i];
      }
    }
  }
}

void sequenceBounds(const Scene& scene, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = glm::vec3(std::numeric_limits<float>::lowest());
  const Animation& a = scene.animation;
  std::vector<bool> moving(scene.meshes.size(), false);
  for (const GeometryMotion& g : a.geometry)
    for (size_t index : g.meshes)
      if (index < moving.size()) moving[index] = true;
  for (size_t i = 0; i < scene.meshes.size(); ++i)
    if (!moving[i])
      for (const glm::vec3& p : scene.meshes[i].positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
  // A moving mesh: the corners of its rest box, transformed at every frame (a box that holds the
  // mesh at each frame).
  for (const GeometryMotion& g : a.geometry) {
    for (size_t k = 0; k < g.meshes.size(); ++k) {
      if (g.meshes[k] >= scene.meshes.size()) continue;
      glm::vec3 restLo(std::numeric_limits<float>::max()), restHi(std::numeric_limits<float>::lowest());
      for (const glm::vec3& p : scene.meshes[g.meshes[k]].positions) {
        restLo = glm::min(restLo, p);
        restHi = glm::max(restHi, p);
      }
      if (restLo.x > restHi.x) continue;
      for (int frame = 0; frame < a.frameCount(); ++frame) {
        const glm::mat4 m = g.meshTransformAt(k, a.timeOf(uint32_t(frame)));
        for (int corner = 0; corner < 8; ++corner) {
          glm::vec3 c((corner & 1) ? restHi.x : restLo.x, (corner & 2) ? restHi.y : restLo.y,
                      (corner & 4) ? restHi.z : restLo.z);
          glm::vec3 p = glm::vec3(m * glm::vec4(c, 1.0f));
          lo = glm::min(lo, p);
          hi = glm::max(hi, p);
        }
      }
    }
  }
}

Scene sceneAt(const Scene& scene, double t) {
  Scene still = scene;
  if (!scene.animation.moves()) return still;
  scene.animation.apply(t, still.camera, still.light);
  scene.animation.moveGeometry(t, scene.meshes, still.meshes);
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
