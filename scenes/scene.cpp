// Scene model helpers: light types, area-light sampling, volume lookups.
#include <algorithm>
#include <cmath>

#include "scenes/scene.hpp"

namespace vs {

const char* lightTypeName(LightType type) {
  switch (type) {
    case LightType::Point:
      return "point";
    case LightType::Spot:
      return "spot";
    case LightType::Directional:
      return "directional";
    case LightType::Rect:
      return "rect";
    case LightType::Disk:
      return "disk";
  }
  return "?";
}

int lightTypeCode(LightType type) { return int(type); }

float Light::area() const {
  if (type == LightType::Rect) return width * height;
  if (type == LightType::Disk) return 3.14159265358979323846f * radius * radius;
  return 0.0f;
}

glm::vec3 Light::samplePoint(float u, float v) const {
  glm::vec3 n = direction, t = tangent;
  glm::vec3 b = glm::cross(n, t);
  if (type == LightType::Rect) return position + (u - 0.5f) * width * t + (v - 0.5f) * height * b;
  if (type == LightType::Disk) {
    // Shirley-Chiu concentric map: stratified squares stay stratified on the disk.
    float a = 2.0f * u - 1.0f, c = 2.0f * v - 1.0f;
    if (a == 0.0f && c == 0.0f) return position;
    float r, phi;
    const float quarterPi = 0.78539816339744830962f;
    if (std::fabs(a) > std::fabs(c)) {
      r = a;
      phi = quarterPi * (c / a);
    } else {
      r = c;
      phi = 2.0f * quarterPi - quarterPi * (a / c);
    }
    return position + radius * r * (std::cos(phi) * t + std::sin(phi) * b);
  }
  return position;
}

float AlphaTexture::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0) return 1.0f;
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return alpha[0];
  float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  auto wrap = [](long i, int n) { return int(((i % n) + n) % n); };
  int x0 = wrap(long(fx), width), x1 = wrap(long(fx) + 1, width);
  int y0 = wrap(long(fy), height), y1 = wrap(long(fy) + 1, height);
  float tx = x - fx, ty = y - fy;
  auto at = [&](int i, int j) { return alpha[size_t(j) * size_t(width) + size_t(i)]; };
  return (at(x0, y0) * (1 - tx) + at(x1, y0) * tx) * (1 - ty) + (at(x0, y1) * (1 - tx) + at(x1, y1) * tx) * ty;
}

float Volume::densityAt(const glm::vec3& p) const {
  if (voxelCount() == 0) return 0.0f;
  glm::vec3 extent = boxHi - boxLo;
  glm::vec3 f = (p - boxLo) / glm::max(extent, glm::vec3(1e-30f));
  if (!(f.x >= 0.0f && f.y >= 0.0f && f.z >= 0.0f && f.x <= 1.0f && f.y <= 1.0f && f.z <= 1.0f)) return 0.0f;
  // Voxel centres at (i + 0.5) / n; clamp to the edge voxels inside the box (as GL_CLAMP_TO_EDGE).
  float g[3];
  int i0[3], i1[3];
  for (int k = 0; k < 3; ++k) {
    float c = std::clamp(f[k] * float(dims[k]) - 0.5f, 0.0f, float(dims[k] - 1));
    i0[k] = int(std::floor(c));
    i1[k] = std::min(i0[k] + 1, dims[k] - 1);
    g[k] = c - float(i0[k]);
  }
  float result = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    int x = (corner & 1) ? i1[0] : i0[0], y = (corner & 2) ? i1[1] : i0[1], z = (corner & 4) ? i1[2] : i0[2];
    float w = ((corner & 1) ? g[0] : 1.0f - g[0]) * ((corner & 2) ? g[1] : 1.0f - g[1]) * ((corner & 4) ? g[2] : 1.0f - g[2]);
    result += w * voxel(x, y, z);
  }
  return result;
}

float Volume::maxDensity() const {
  float m = 0.0f;
  for (float d : density) m = std::max(m, d);
  return m;
}

}  // namespace vs
