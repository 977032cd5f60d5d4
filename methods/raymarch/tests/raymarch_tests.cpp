// raymarch against an independent CPU oracle, and its convergence towards the reference.
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>

#include "gl_test.hpp"
#include "harness/metrics.hpp"

namespace vs::testing {
namespace {

// No occluders (V = 1), point light outside the view frustum, homogeneous medium.
const char* kOpenMediumScene = R"({
  "description": "point light in an open homogeneous medium",
  "geometry": [],
  "camera": {"position": [0, 0, 0], "target": [0, 0, -1], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.1, "far": 20},
  "light": {"type": "point", "position": [3, 0.5, -5], "color": [1, 0.8, 0.6], "intensity": 40},
  "medium": {"sigma_s": 0.1, "sigma_a": 0.05, "phase": "isotropic"}
})";

// L_s for one camera ray, by composite Gauss-Legendre quadrature in double precision.
glm::dvec3 quadratureInscatter(const Scene& s, glm::dvec3 dir, double dist) {
  const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                        0.2369268850561891};
  const double sigmaS = s.medium.sigmaS, sigmaT = s.medium.sigmaT();
  const glm::dvec3 eye(s.camera.position), light(s.light.position);
  const glm::dvec3 I = glm::dvec3(s.light.color) * double(s.light.intensity);
  const int panels = 4000;
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

class RaymarchTest : public GlTest {};

TEST_F(RaymarchTest, MatchesDoublePrecisionQuadratureWithoutOccluders) {
  Scene scene = sceneFromJson(kOpenMediumScene);
  const int W = 32, H = 24;
  MethodRun run = renderScene(scene, "raymarch:steps=4096:jitter=0:sm=64", W, H);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  glm::dmat4 view = glm::dmat4(cameraView(scene.camera));
  glm::dmat4 proj = glm::dmat4(cameraProjection(scene.camera, float(W) / H));
  glm::dmat4 inv = glm::inverse(proj * view);
  glm::dvec3 eye(scene.camera.position);
  glm::dvec3 forward = glm::normalize(glm::dvec3(scene.camera.target) - eye);
  double worst = 0.0;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      // Image row 0 is the top; GL's pixel rows start at the bottom.
      glm::dvec4 ndc((x + 0.5) / W * 2.0 - 1.0, (H - 1 - y + 0.5) / H * 2.0 - 1.0, 1.0, 1.0);
      glm::dvec4 p = inv * ndc;
      glm::dvec3 dir = glm::normalize(glm::dvec3(p) / p.w - eye);
      double dist = scene.camera.farZ / glm::dot(dir, forward);
      glm::dvec3 expected = quadratureInscatter(scene, dir, dist);
      const float* got = run.inscatter.at(x, y);
      for (int c = 0; c < 3; ++c) {
        double rel = std::fabs(got[c] - expected[c]) / expected[c];
        worst = std::max(worst, rel);
        ASSERT_LT(rel, 0.005) << "pixel " << x << "," << y << " channel " << c << ": " << got[c] << " vs "
                              << expected[c];
      }
    }
  }
  std::printf("worst relative error against quadrature: %.2e\n", worst);
}

TEST_F(RaymarchTest, ErrorFallsAsStepsRise) {
  Scene scene = loadScene("spheres");
  const int W = 96, H = 72;
  MethodRun ref = renderScene(scene, "raymarch:steps=2048:sm=512", W, H);
  ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
  std::vector<int> steps = {8, 32, 128, 512};
  std::vector<double> rmse;
  for (int n : steps) {
    MethodRun run = renderScene(scene, "raymarch:steps=" + std::to_string(n) + ":sm=512", W, H, 1, 0, 7);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    rmse.push_back(compareImages(run.inscatter, ref.inscatter).rmse);
  }
  for (size_t i = 1; i < rmse.size(); ++i) EXPECT_LT(rmse[i], rmse[i - 1]) << "steps " << steps[i];
  double order = std::log(rmse.front() / rmse[rmse.size() - 2]) / std::log(double(steps[steps.size() - 2]) / steps.front());
  std::printf("L_s RMSE:");
  for (size_t i = 0; i < steps.size(); ++i) std::printf(" %d steps %.3e;", steps[i], rmse[i]);
  std::printf(" measured order %.2f (8..128 steps)\n", order);
  EXPECT_GT(order, 0.4);
}

TEST_F(RaymarchTest, JitterIsDeterministicPerSeed) {
  Scene scene = loadScene("spheres");
  MethodRun a = renderScene(scene, "raymarch:steps=16:sm=256", 48, 32, 1, 0, 3);
  MethodRun b = renderScene(scene, "raymarch:steps=16:sm=256", 48, 32, 1, 0, 3);
  MethodRun c = renderScene(scene, "raymarch:steps=16:sm=256", 48, 32, 1, 0, 4);
  ASSERT_EQ(a.status, RunStatus::Success) << a.reason;
  EXPECT_EQ(a.inscatter.rgb, b.inscatter.rgb);
  EXPECT_NE(a.inscatter.rgb, c.inscatter.rgb);
}

TEST_F(RaymarchTest, ReportsShadowMapSamplesPerSecond) {
  Scene scene = loadScene("spheres");
  MethodRun run = renderScene(scene, "raymarch:steps=32:sm=256", 64, 64, 3, 1);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  ASSERT_TRUE(run.stats.count("shadow_map_samples_per_s"));
  EXPECT_DOUBLE_EQ(run.stats.at("shadow_map_samples"), 64.0 * 64.0 * 32.0);
  EXPECT_GT(run.stats.at("shadow_map_samples_per_s"), 0.0);
}

}  // namespace
}  // namespace vs::testing
