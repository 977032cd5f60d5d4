// Virtual point lights (VPLs): an area light as N cosine-lobed point lights at Hammersley points of
// its surface. The per-VPL wrapper (Runner, shared parameter `vpls`) runs any point-light method
// once per VPL and sums L_s; methods that sample area lights themselves use the same points.
#pragma once
#include <glm/glm.hpp>

#include <vector>

#include "scenes/scene.hpp"

namespace vs {

// Point (u, v) of the 2D Hammersley set of `count` points: stratified in u, radical inverse in v.
glm::vec2 hammersley(int k, int count);

// `count` points on the area light's surface (Light::samplePoint at the Hammersley points). With
// `shifted`, the set is moved off those points (u by half a stratum, v by 1 - 1/golden, modulo 1):
// the reference samples the light this way, so that a VPL method's sampling error shows against it.
std::vector<glm::vec3> virtualPointLightPositions(const Light& areaLight, int count, bool shifted = false);

// One of `count` VPLs of `areaLight` at `position`: a point light of intensity
// radiance * area / count with a cosine lobe about the light's normal (one- or two-sided as the
// light). With count = 1 at the centre it is the area light as the shared passes shade surfaces.
Light virtualPointLight(const Light& areaLight, const glm::vec3& position, int count);

}  // namespace vs
