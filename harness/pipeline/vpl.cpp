#include "harness/pipeline/vpl.hpp"

#include <algorithm>

namespace vs {

glm::vec2 hammersley(int k, int count) {
  uint32_t bits = uint32_t(k);
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return glm::vec2((float(k) + 0.5f) / float(std::max(count, 1)), float(bits) * 2.3283064365386963e-10f);
}

std::vector<glm::vec3> virtualPointLightPositions(const Light& areaLight, int count, bool shifted) {
  std::vector<glm::vec3> points;
  points.reserve(size_t(std::max(count, 0)));
  glm::vec2 shift = shifted ? glm::vec2(0.5f / float(std::max(count, 1)), 0.381966011f) : glm::vec2(0.0f);
  for (int k = 0; k < count; ++k) {
    glm::vec2 uv = glm::fract(hammersley(k, count) + shift);
    points.push_back(areaLight.samplePoint(uv.x, uv.y));
  }
  return points;
}

Light virtualPointLight(const Light& areaLight, const glm::vec3& position, int count) {
  Light vpl;
  vpl.type = LightType::Point;
  vpl.position = position;
  vpl.direction = areaLight.direction;
  vpl.color = areaLight.color;
  vpl.intensity = areaLight.intensity * areaLight.area() / float(std::max(count, 1));
  vpl.twoSided = areaLight.twoSided;
  vpl.cosineLobe = true;
  return vpl;
}

}  // namespace vs
