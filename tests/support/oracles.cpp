#include "oracles.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "harness/pipeline/frame.hpp"

namespace vs::testing {

const char* const kOpenMediumScene = R"({
  "description": "point light in an open homogeneous medium",
  "geometry": [],
  "camera": {"position": [0, 0, 0], "target": [0, 0, -1], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.1, "far": 20},
  "light": {"type": "point", "position": [3, 0.5, -5], "color": [1, 0.8, 0.6], "intensity": 40},
  "medium": {"sigma_s": 0.1, "sigma_a": 0.05, "phase": "isotropic"}
})";

void pixelRay(const Scene& scene, int width, int height, int x, int y, glm::dvec3& dir, double& farDistance) {
  glm::dmat4 view = glm::dmat4(cameraView(scene.camera));
  glm::dmat4 proj = glm::dmat4(cameraProjection(scene.camera, float(width) / float(height)));
  glm::dmat4 inverse = glm::inverse(proj * view);
  glm::dvec3 eye(scene.camera.position);
  glm::dvec3 forward = glm::normalize(glm::dvec3(scene.camera.target) - eye);
  glm::dvec4 ndc((x + 0.5) / width * 2.0 - 1.0, (height - 1 - y + 0.5) / height * 2.0 - 1.0, 1.0, 1.0);
  glm::dvec4 p = inverse * ndc;
  dir = glm::normalize(glm::dvec3(p) / p.w - eye);
  farDistance = scene.camera.farZ / glm::dot(dir, forward);
}

glm::dvec3 quadratureInscatter(const Scene& s, glm::dvec3 dir, double dist, int panels) {
  const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                        0.2369268850561891};
  const double sigmaS = s.medium.sigmaS, sigmaT = s.medium.sigmaT();
  const glm::dvec3 eye(s.camera.position), light(s.light.position);
  const glm::dvec3 I = glm::dvec3(s.light.color) * double(s.light.intensity);
  glm::dvec3 sum(0.0);
  double h = dist / panels;
  for (int p = 0; p < panels; ++p) {
    double a = p * h;
    for (int k = 0; k < 5; ++k) {
      double t = a + 0.5 * h * (x5[k] + 1.0);
      glm::dvec3 x = eye + dir * t;
      double r2 = glm::dot(x - light, x - light);
      double r = std::sqrt(r2);
      glm::dvec3 Lin = I * std::exp(-sigmaT * r) / r2;
      sum += 0.5 * h * w5[k] * sigmaS * std::exp(-sigmaT * t) / (4.0 * M_PI) * Lin;
    }
  }
  return sum;
}

}  // namespace vs::testing
