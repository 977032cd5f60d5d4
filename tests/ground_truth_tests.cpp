// The exact-visibility ground truth (CPU, double, Embree) against the quadrature oracle, and the
// ray-marched reference against the ground truth.
#include <cmath>
#include <cstdio>

#include "gl_test.hpp"
#include "harness/evaluation/ground_truth.hpp"
#include "harness/evaluation/metrics.hpp"
#include "oracles.hpp"

namespace vs::testing {
namespace {

class GroundTruthTest : public GlTest {};

TEST_F(GroundTruthTest, MatchesQuadratureWithoutOccluders) {
  Scene scene = sceneFromJson(kOpenMediumScene);
  GroundTruthOptions options;
  options.width = 24;
  options.height = 16;
  options.steps = 4096;
  GroundTruth gt = renderGroundTruth(scene, options);
  for (int y = 0; y < options.height; ++y) {
    for (int x = 0; x < options.width; ++x) {
      glm::dvec3 dir;
      double dist;
      pixelRay(scene, options.width, options.height, x, y, dir, dist);
      glm::dvec3 expected = quadratureInscatter(scene, dir, dist);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(gt.inscatter.at(x, y)[c], expected[c], 1e-3 * expected[c]) << x << "," << y;
    }
  }
}

TEST_F(GroundTruthTest, OccludersCastExactShadows) {
  // A large opaque plane between the light and the whole view: no in-scattering behind it.
  Scene scene = sceneFromJson(R"({
    "geometry": [{"generator": "plane", "params": {"center": [0, 5, 0], "size": [200, 200]}}],
    "camera": {"position": [0, 0, 0], "target": [0, 0, -1], "fov_y_deg": 40, "near": 0.1, "far": 20},
    "light": {"type": "point", "position": [0, 8, -5], "intensity": 40},
    "medium": {"sigma_s": 0.1, "sigma_a": 0.0}})");
  GroundTruthOptions options;
  options.width = 16;
  options.height = 12;
  options.steps = 256;
  GroundTruth gt = renderGroundTruth(scene, options);
  for (int y = 0; y < options.height; ++y)
    for (int x = 0; x < options.width; ++x) ASSERT_EQ(gt.inscatter.at(x, y)[0], 0.0f) << x << "," << y;
}

TEST_F(GroundTruthTest, ReferenceIsCloseToExactVisibility) {
  // Bounds stated in the README. The fence's wires are thinner than a 2048^2 shadow-map texel in
  // places, so its shadow-map visibility departs from exact visibility more (aliasing).
  struct Case {
    const char* scene;
    double lsRelmse, finalRelmse, lsSsim;
  };
  const int W = 64, H = 48;
  for (Case c : {Case{"spheres", 1e-5, 1e-2, 0.995}, Case{"fence", 2e-3, 4e-2, 0.98}}) {
    const char* name = c.scene;
    Scene scene = loadScene(name);
    GroundTruthOptions options;
    options.width = W;
    options.height = H;
    options.steps = 2048;
    GroundTruth gt = renderGroundTruth(scene, options);
    MethodRun ref = renderScene(scene, "raymarch:steps=4096:sampling=equiangular:sm=2048", W, H);
    ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
    ErrorMetrics ls = compareImages(ref.inscatter, gt.inscatter);
    ErrorMetrics final = compareImages(ref.final, gt.final);
    std::printf("%s: reference vs exact visibility: L_s relMSE %.2e rmse %.3e ssim %.4f; L relMSE %.2e ssim %.4f "
                "(ground truth %.1f s)\n",
                name, ls.relmse, ls.rmse, ls.ssim, final.relmse, final.ssim, gt.computeMs / 1000);
    EXPECT_LT(ls.relmse, c.lsRelmse) << name;
    EXPECT_GT(ls.ssim, c.lsSsim) << name;
    EXPECT_LT(final.relmse, c.finalRelmse) << name;
  }
}

TEST_F(GroundTruthTest, LightTexturesAreDeclaredUnsupported) {
  Scene scene = loadScene("spheres");
  scene.light.textureWidth = scene.light.textureHeight = 1;
  scene.light.textureRGB = {1, 1, 1};
  EXPECT_FALSE(groundTruthUnsupported(scene).empty());
  EXPECT_THROW(renderGroundTruth(scene, {}), std::runtime_error);
}

}  // namespace
}  // namespace vs::testing
