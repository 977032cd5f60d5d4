// Volume data end to end: Beer-Lambert oracles for the ground truth and the ray-marched reference,
// the reference against the exact ground truth on the built-in volume scenes, convergence of the
// nested march, and methods without volume support reporting Unsupported.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "gl_test.hpp"
#include "harness/evaluation/ground_truth.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/io/results.hpp"
#include "oracles.hpp"

namespace vs::testing {
namespace {

class VolumeTest : public GlTest {};

// A pure absorber slab of optical thickness k between a downward camera and a lit ground plane,
// light straight down: the ground's radiance is albedo/pi * E * exp(-k) (light path) *
// exp(-k / c) (view path, c = cosine of the pixel's ray with the vertical). `sigmaA` is JSON: a
// number or an [r, g, b] triple.
std::string slabScene(const std::string& sigmaA) {
  return R"({"geometry": [{"generator": "plane", "params": {"center": [0, 0, 0], "size": [40, 40]}, "albedo": [0.5, 0.5, 0.5]}],
    "volumes": [{"dims": [1, 1, 1], "density": [1], "box_min": [-20, 1, -20], "box_max": [20, 2, 20], "sigma_s": 0, "sigma_a": )" +
         sigmaA + R"(}],
    "camera": {"position": [0, 5, 0.001], "target": [0, 0, 0], "fov_y_deg": 20, "near": 0.1, "far": 20},
    "light": {"type": "directional", "direction": [0, -1, 0], "intensity": 2}})";
}

TEST_F(VolumeTest, SlabAttenuatesAsBeerLambert) {
  // Grey slabs, then a tinted one: each colour channel follows its own k.
  struct Case {
    std::string sigmaA;
    glm::dvec3 k;
  };
  for (const Case& slab : {Case{"0.25", glm::dvec3(0.25)}, Case{"1", glm::dvec3(1.0)}, Case{"3", glm::dvec3(3.0)},
                           Case{"[0.25, 1, 3]", glm::dvec3(0.25, 1.0, 3.0)}}) {
    Scene scene = sceneFromJson(slabScene(slab.sigmaA));
    EXPECT_EQ(deriveEffects(scene).coloredShadows, slab.k.x != slab.k.z) << slab.sigmaA;
    GroundTruthOptions options;
    options.width = 8;
    options.height = 6;
    options.steps = 64;
    GroundTruth gt = renderGroundTruth(scene, options);
    MethodRun ref = renderScene(scene, "raymarch:steps=4096", 8, 6);
    ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 8; ++x) {
        glm::dvec3 dir;
        double dist;
        pixelRay(scene, 8, 6, x, y, dir, dist);
        for (int c = 0; c < 3; ++c) {
          double k = slab.k[c], expected = 0.5 / M_PI * 2.0 * std::exp(-k) * std::exp(-k / std::fabs(dir.y));
          EXPECT_NEAR(gt.final.at(x, y)[c], expected, 1e-5 * expected) << "ground truth, k " << k;
          // The camera ray's optical depth is a trapezoid sum over 4096 steps of ~1.2e-3: each of the
          // slab's two faces costs at most sigma_t * step, 2 * 3 * 1.2e-3 = 0.7 % at k = 3.
          EXPECT_NEAR(ref.final.at(x, y)[c], expected, 1e-2 * expected) << "raymarch, k " << k;
        }
        EXPECT_EQ(ref.inscatter.at(x, y)[0], 0.0f);
      }
  }
}

TEST_F(VolumeTest, ScatteringSlabMatchesClosedForm) {
  // A scattering slab (sigma_s = sigma_t = k) lit from straight above and seen from above: along a
  // view ray at cosine c to the vertical, depth z = c s below the slab's top, L_s =
  // int_0^{1/c} k e^{-k s} e^{-k c s} E / (4 pi) ds = E / (4 pi (1 + c)) (1 - e^{-k (1 + c) / c}).
  const double k = 0.8, E = 2.0;
  std::string text = slabScene("0");
  text.replace(text.find("\"sigma_s\": 0"), 12, "\"sigma_s\": " + std::to_string(k));
  Scene scene = sceneFromJson(text);
  GroundTruthOptions options;
  options.width = 8;
  options.height = 6;
  options.steps = 16384;
  GroundTruth gt = renderGroundTruth(scene, options);
  MethodRun ref = renderScene(scene, "raymarch:steps=4096", 8, 6);
  ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      glm::dvec3 dir;
      double dist;
      pixelRay(scene, 8, 6, x, y, dir, dist);
      double c = std::fabs(dir.y);
      double expected = E / (4.0 * M_PI * (1.0 + c)) * (1.0 - std::exp(-k * (1.0 + c) / c));
      // Both sample the camera ray in equal steps (~3e-4 and 1.2e-3 here) across the slab's faces,
      // where the scattering coefficient jumps: an error of the order of one step.
      EXPECT_NEAR(gt.inscatter.at(x, y)[0], expected, 1e-3 * expected);
      EXPECT_NEAR(ref.inscatter.at(x, y)[0], expected, 5e-3 * expected);
    }
}

TEST_F(VolumeTest, ReferenceMatchesGroundTruthOnBuiltinVolumeScenes) {
  // Bounds stated in the README: the reference against the exact ground truth at 48x36.
  struct Case {
    const char* scene;
    double lsRelmse, finalRelmse;
  };
  const int W = 48, H = 36;
  for (Case c : {Case{"volumes", 2e-4, 2e-4}, Case{"cloud", 2e-4, 2e-4}}) {
    Scene scene = loadScene(c.scene);
    GroundTruthOptions options;
    options.width = W;
    options.height = H;
    options.steps = 512;
    GroundTruth gt = renderGroundTruth(scene, options);
    MethodRun ref = renderScene(scene, referenceSpecFor(deriveEffects(scene), 2048, registeredMethods()), W, H);
    ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
    ErrorMetrics ls = compareImages(ref.inscatter, gt.inscatter);
    ErrorMetrics final = compareImages(ref.final, gt.final);
    std::printf("%s: the reference (4096 steps, split into passes) vs ground truth: L_s relMSE %.2e ssim %.4f; L relMSE %.2e (ground truth %.1f s)\n",
                c.scene, ls.relmse, ls.ssim, final.relmse, gt.computeMs / 1000);
    EXPECT_LT(ls.relmse, c.lsRelmse) << c.scene;
    EXPECT_LT(final.relmse, c.finalRelmse) << c.scene;
  }
}

TEST_F(VolumeTest, NestedMarchConvergesWithLightSteps) {
  Scene scene = loadScene("volumes");
  const int W = 48, H = 36;
  MethodRun ref = renderScene(scene, "raymarch:steps=512:vsteps=4", W, H);
  ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
  double previous = 1e30;
  for (const char* vsteps : {"0.25", "1"}) {
    MethodRun r = renderScene(scene, std::string("raymarch:steps=512:vsteps=") + vsteps, W, H);
    ASSERT_EQ(r.status, RunStatus::Success) << r.reason;
    double err = compareImages(r.inscatter, ref.inscatter).relmse;
    std::printf("vsteps %s: L_s relMSE %.3e against vsteps 4\n", vsteps, err);
    EXPECT_LT(err, previous);
    previous = err;
  }
  EXPECT_LT(previous, 1e-3);
}

TEST_F(VolumeTest, OnlyMethodsWithVolumeDataRunIt) {
  std::string dir = makeTempDir("volume-shootout");
  CommandResult r = runVshadow({"shootout", "--scene", "volumes", "--size", "32x24", "--frames", "1", "--warmup", "0",
                                "--rungs", "first", "--out", dir + "/out", "--cache", dir + "/cache", "--no-images",
                                "--strict-gl"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto rows = CsvTable::parse(readFile(dir + "/out/runs.csv"));
  ASSERT_GT(rows.size(), 1u);
  const auto& header = rows[0];
  auto col = [&](const std::string& name) { return size_t(std::find(header.begin(), header.end(), name) - header.begin()); };
  int supported = 0, unsupported = 0;
  const Effects effects = deriveEffects(loadScene("volumes"));
  for (size_t i = 1; i < rows.size(); ++i) {
    EXPECT_NE(rows[i][col("effects")].find("volume-data"), std::string::npos);
    Capabilities caps = createMethod(rows[i][col("method")])->capabilities();
    if (caps.volumeData) {
      EXPECT_EQ(rows[i][col("status")], "Success") << rows[i][col("reason")];
      ++supported;
    } else {
      EXPECT_EQ(rows[i][col("status")], "Unsupported");
      // The reason names volume data, unless something else (the light type) is missing first.
      caps.volumeData = true;
      if (missingCapability(caps, effects).empty()) {
        EXPECT_NE(rows[i][col("reason")].find("volume data"), std::string::npos) << rows[i][col("reason")];
      }
      ++unsupported;
    }
  }
  EXPECT_GT(supported, 0);
  EXPECT_GT(unsupported, 0);
}

TEST_F(VolumeTest, TooManyVolumesIsBadInputBeforeAnythingIsWritten) {
  std::string dir = makeTempDir("volume-limit");
  std::string volume = R"({"generator": "bucky", "scale": 0.25, "box_min": [0, 0, 0], "box_max": [1, 1, 1]})";
  std::string volumes;
  for (int i = 0; i < 5; ++i) volumes += (i ? "," : "") + volume;
  writeFile(dir + "/five.json", R"({"geometry": [], "volumes": [)" + volumes + R"(],
    "camera": {"position": [0, 1, 5], "target": [0, 0, 0]}, "light": {"type": "point", "position": [0, 3, 0], "intensity": 1}})");
  CommandResult r = runVshadow({"run", "--scene", dir + "/five.json", "--method", "raymarch", "--out", dir + "/out"});
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("at most 4"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

}  // namespace
}  // namespace vs::testing
