// raymarch against an independent CPU oracle, and its convergence towards the reference.
#include <cmath>
#include <cstdio>

#include "gl_test.hpp"
#include "oracles.hpp"
#include "harness/evaluation/metrics.hpp"

namespace vs::testing {
namespace {

class RaymarchTest : public GlTest {};

class QuadratureTest : public GlTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(QuadratureTest, MatchesDoublePrecisionQuadratureWithoutOccluders) {
  Scene scene = sceneFromJson(kOpenMediumScene);
  const int W = 32, H = 24;
  MethodRun run = renderScene(scene, GetParam(), W, H);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  double worst = 0.0;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      glm::dvec3 dir;
      double dist;
      pixelRay(scene, W, H, x, y, dir, dist);
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
  std::printf("%s: worst relative error against quadrature: %.2e\n", GetParam().c_str(), worst);
}

INSTANTIATE_TEST_SUITE_P(Sampling, QuadratureTest,
                         ::testing::Values("raymarch:steps=4096:jitter=0:sm=64",
                                           "raymarch:steps=256:jitter=1:sampling=equiangular:sm=64"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param.find("equiangular") != std::string::npos ? std::string("Equiangular")
                                                                                       : std::string("Uniform");
                         });

TEST_F(RaymarchTest, EquiangularSamplingResolvesTheLightInView) {
  // On spheres the light is on screen: at equal steps, equiangular sampling is far closer to a
  // converged reference than uniform steps (whose error concentrates around the light).
  Scene scene = loadScene("spheres");
  const int W = 96, H = 72;
  MethodRun ref = renderScene(scene, "raymarch:steps=8192:sampling=equiangular:sm=512", W, H);
  MethodRun uniform = renderScene(scene, "raymarch:steps=64:sm=512", W, H);
  MethodRun angular = renderScene(scene, "raymarch:steps=64:sampling=equiangular:sm=512", W, H);
  ASSERT_EQ(uniform.status, RunStatus::Success) << uniform.reason;
  ASSERT_EQ(angular.status, RunStatus::Success) << angular.reason;
  double rmseUniform = compareImages(uniform.inscatter, ref.inscatter).rmse;
  double rmseAngular = compareImages(angular.inscatter, ref.inscatter).rmse;
  std::printf("64 steps against 8192 equiangular: uniform rmse %.3e, equiangular rmse %.3e\n", rmseUniform, rmseAngular);
  EXPECT_LT(rmseAngular * 5, rmseUniform);
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
