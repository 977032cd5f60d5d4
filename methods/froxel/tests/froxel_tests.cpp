// froxel: against closed forms where its grid is exact (a constant source), Beer-Lambert through a
// slab of volume data, and convergence to the quadrature oracle as the grid refines.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gl_test.hpp"
#include "harness/evaluation/metrics.hpp"
#include "oracles.hpp"

namespace vs::testing {
namespace {

class FroxelTest : public GlTest {};

constexpr int W = 32, H = 24;

// No occluders and a directional light: the in-scattered radiance per unit length is the same
// everywhere, so each slice's integral is exact and L_s = sigma_s E / (4 pi) (1 - e^{-sigma_t d}) / sigma_t
// at the far distance d of each (sky) pixel; only the interpolation between slice boundaries errs.
TEST_F(FroxelTest, UnshadowedFogMatchesTheClosedForm) {
  Scene scene = sceneFromJson(R"({"geometry": [],
    "camera": {"position": [0, 0, 0], "target": [0, 0, -1], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.1, "far": 20},
    "light": {"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 2},
    "medium": {"sigma_s": 0.1, "sigma_a": 0.05, "phase": "isotropic"}})");
  const double sigmaS = 0.1, sigmaT = 0.15, E = 2.0;
  for (const char* spec : {"froxel:tile=8:slices=32:dist=exp", "froxel:tile=8:slices=32:dist=linear",
                           "froxel:tile=1:slices=512:dist=linear"}) {
    MethodRun r = renderScene(scene, spec, W, H);
    ASSERT_EQ(r.status, RunStatus::Success) << spec << ": " << r.reason;
    double worst = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        glm::dvec3 dir;
        double d;
        pixelRay(scene, W, H, x, y, dir, d);
        double expected = sigmaS * E / (4.0 * M_PI) * (1.0 - std::exp(-sigmaT * d)) / sigmaT;
        worst = std::max(worst, std::fabs(r.inscatter.at(x, y)[0] - expected) / expected);
      }
    std::printf("%s: worst relative error %.2e against the closed form\n", spec, worst);
    EXPECT_LT(worst, 2e-3) << spec;
  }
}

// A point light in an open medium: the source varies along each ray (1/r^2, extinction), and the
// grid converges to the quadrature oracle as it refines.
TEST_F(FroxelTest, OpenMediumConvergesToTheQuadrature) {
  Scene scene = sceneFromJson(kOpenMediumScene);
  Image oracle(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      glm::dvec3 dir;
      double d;
      pixelRay(scene, W, H, x, y, dir, d);
      glm::dvec3 v = quadratureInscatter(scene, dir, d);
      for (int c = 0; c < 3; ++c) oracle.at(x, y)[c] = float(v[c]);
    }
  double previous = 1e30;
  for (const char* spec : {"froxel:tile=16:slices=32", "froxel:tile=4:slices=128", "froxel:tile=1:slices=512:samples=2"}) {
    MethodRun r = renderScene(scene, spec, W, H);
    ASSERT_EQ(r.status, RunStatus::Success) << spec << ": " << r.reason;
    double err = compareImages(r.inscatter, oracle).relmse;
    std::printf("%s: L_s relMSE %.3e against the quadrature\n", spec, err);
    EXPECT_LT(err, previous) << spec;
    previous = err;
  }
  EXPECT_LT(previous, 1e-4);
}

// On the built-in spheres (point light in view, occluders) and cloud (volume data under the sun)
// the grid converges to the ray-marched reference as it refines.
TEST_F(FroxelTest, RefiningTheGridConvergesToTheReferenceOnSpheresAndCloud) {
  for (const char* name : {"spheres", "cloud"}) {
    Scene scene = loadScene(name);
    MethodRun ref = renderScene(scene, referenceSpecFor(deriveEffects(scene), 1024, registeredMethods()), W, H);
    ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
    double previous = 1e30;
    for (const char* spec : {"froxel:tile=16:slices=32", "froxel:tile=4:slices=128", "froxel:tile=1:slices=512:samples=4"}) {
      MethodRun r = renderScene(scene, spec, W, H);
      ASSERT_EQ(r.status, RunStatus::Success) << name << " " << spec << ": " << r.reason;
      const double err = compareImages(r.inscatter, ref.inscatter).relmse;
      std::printf("%s %s: L_s relMSE %.3e against the reference\n", name, spec, err);
      EXPECT_LT(err, previous) << name << " " << spec;
      previous = err;
    }
    EXPECT_LT(previous, 2e-3) << name;
  }
}

// A slab of volume data between y = 1 and 2, seen and lit from above: the surface behind it is
// attenuated as Beer-Lambert along both rays (sigma_a = k, no scattering), and a scattering slab
// (sigma_s = sigma_t = k) scatters E / (4 pi (1 + c)) (1 - e^{-k (1 + c) / c}) at view cosine c.
std::string slabScene(double sigmaS, double sigmaA) {
  return R"({"geometry": [{"generator": "plane", "params": {"center": [0, 0, 0], "size": [40, 40]}, "albedo": [0.5, 0.5, 0.5]}],
    "volumes": [{"dims": [1, 1, 1], "density": [1], "box_min": [-20, 1, -20], "box_max": [20, 2, 20], "sigma_s": )" +
         std::to_string(sigmaS) + R"(, "sigma_a": )" + std::to_string(sigmaA) + R"(}],
    "camera": {"position": [0, 5, 0.001], "target": [0, 0, 0], "fov_y_deg": 20, "near": 0.1, "far": 20},
    "light": {"type": "directional", "direction": [0, -1, 0], "intensity": 2}})";
}

TEST_F(FroxelTest, VolumeSlabMatchesBeerLambert) {
  const double k = 0.8, E = 2.0;
  const std::string spec = "froxel:tile=1:slices=512:dist=linear:samples=4";
  MethodRun absorbing = renderScene(sceneFromJson(slabScene(0.0, k)), spec, 8, 6);
  ASSERT_EQ(absorbing.status, RunStatus::Success) << absorbing.reason;
  Scene scattering = sceneFromJson(slabScene(k, 0.0));
  MethodRun lit = renderScene(scattering, spec, 8, 6);
  ASSERT_EQ(lit.status, RunStatus::Success) << lit.reason;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      glm::dvec3 dir;
      double dist;
      pixelRay(scattering, 8, 6, x, y, dir, dist);
      const double c = std::fabs(dir.y);
      const double surface = 0.5 / M_PI * E * std::exp(-k) * std::exp(-k / c);
      EXPECT_NEAR(absorbing.final.at(x, y)[0], surface, 1e-2 * surface) << x << "," << y;
      const double inscatter = E / (4.0 * M_PI * (1.0 + c)) * (1.0 - std::exp(-k * (1.0 + c) / c));
      EXPECT_NEAR(lit.inscatter.at(x, y)[0], inscatter, 2e-2 * inscatter) << x << "," << y;
    }
}

// Temporal reprojection on a still scene: the jittered samples of successive frames accumulate,
// so after 16 frames of history the grid is closer to 16 stratified samples per froxel than one
// jittered frame is; the row says how much history its last frame had.
void expectHistoryConverges(const std::string& sceneName) {
  Scene scene = loadScene(sceneName);
  MethodRun many = renderScene(scene, "froxel:samples=16", W, H);
  MethodRun single = renderScene(scene, "froxel:jitter=1", W, H, 1, 16);
  MethodRun temporal = renderScene(scene, "froxel:temporal=0.9", W, H, 1, 16);
  for (const MethodRun* r : {&many, &single, &temporal}) ASSERT_EQ(r->status, RunStatus::Success) << r->reason;
  const double singleErr = compareImages(single.inscatter, many.inscatter).relmse;
  const double temporalErr = compareImages(temporal.inscatter, many.inscatter).relmse;
  std::printf("%s against 16 samples per froxel: one jittered frame relMSE %.3e, 16 frames of history %.3e\n",
              sceneName.c_str(), singleErr, temporalErr);
  EXPECT_LT(temporalErr, 0.5 * singleErr) << sceneName;
  EXPECT_EQ(temporal.stats.at("history_frames"), 16.0);
  EXPECT_EQ(single.stats.count("history_frames"), 0u);
}

TEST_F(FroxelTest, TemporalReprojectionAccumulatesHistoryOnAStillScene) { expectHistoryConverges("spheres"); }
// Four volumes: the scattering pass reads each volume's density and then the history (a driver
// once returned wrong history texels after the volumes' sampler array was indexed in a loop).
TEST_F(FroxelTest, TemporalReprojectionAccumulatesHistoryThroughSeveralVolumes) { expectHistoryConverges("volumes"); }

// A grid over the cap is a Failure row with the reason, not an exhausted device.
TEST_F(FroxelTest, AGridOverTheMemoryCapFailsItsRowWithTheReason) {
  Scene scene = sceneFromJson(kOpenMediumScene);
  MethodRun r = renderScene(scene, "froxel:tile=1:slices=512", 1024, 768);
  EXPECT_EQ(r.status, RunStatus::Failure);
  EXPECT_NE(r.reason.find("raise tile or lower slices"), std::string::npos) << r.reason;
}

}  // namespace
}  // namespace vs::testing
