// Closed-form and quadrature oracles for tests: with V = 1 (no occluders) and a point light in a
// homogeneous medium, L_s along a camera ray is a smooth 1D integral we can evaluate in double.
#pragma once
#include <glm/glm.hpp>

#include "scenes/scene.hpp"

namespace vs::testing {

// No occluders, point light outside the view frustum, homogeneous medium, 40-degree camera.
extern const char* const kOpenMediumScene;

// The camera ray of pixel (x, y) (row 0 = top) and its length to the far plane, in double.
void pixelRay(const Scene& scene, int width, int height, int x, int y, glm::dvec3& dir, double& farDistance);
// L_s = int_0^dist sigma_s exp(-sigma_t s) / (4 pi) * I exp(-sigma_t r) / r^2 ds, isotropic phase,
// by composite 5-point Gauss-Legendre quadrature over `panels` panels.
glm::dvec3 quadratureInscatter(const Scene& scene, glm::dvec3 dir, double dist, int panels = 4000);

}  // namespace vs::testing
