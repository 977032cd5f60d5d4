// Area lights end to end: a disk light on its axis against a 2D quadrature oracle, a tiny light
// against the exact ground truth, the reference against the ground truth on `arealight`, and the
// per-VPL wrapper (shared parameter vpls) around the point-light methods.
#include <cmath>
#include <cstdio>

#include "gl_test.hpp"
#include "harness/evaluation/ground_truth.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/vpl.hpp"

namespace vs::testing {
namespace {

class AreaLightTest : public GlTest {};

// In-scattered radiance along the axis of a downward disk light of radiance L and radius R at
// height H, seen from the origin looking up, far plane at F: sigma_s int_0^F e^{-sigma s} / (4 pi)
// int_disk L cos e^{-sigma r} / r^2 dA ds, with cos = h / r and h = H - s (sigma_a = 0).
double diskAxisInscatter(double L, double R, double H, double F, double sigma) {
  const int ns = 4000, nr = 2000;
  double total = 0.0;
  for (int i = 0; i < ns; ++i) {
    double s = (i + 0.5) / ns * F, h = H - s, irradiance = 0.0;
    for (int j = 0; j < nr; ++j) {
      double rho = (j + 0.5) / nr * R, r = std::sqrt(h * h + rho * rho);
      irradiance += 2.0 * M_PI * rho * (R / nr) * L * (h / r) * std::exp(-sigma * r) / (r * r);
    }
    total += sigma * std::exp(-sigma * s) * irradiance / (4.0 * M_PI) * (F / ns);
  }
  return total;
}

TEST_F(AreaLightTest, DiskOnAxisMatchesQuadrature) {
  Scene scene = sceneFromJson(R"({"geometry": [],
    "camera": {"position": [0, 0, 0], "target": [0, 5, 0], "up": [0, 0, 1], "fov_y_deg": 10, "near": 0.1, "far": 4.5},
    "light": {"type": "disk", "position": [0, 5, 0], "direction": [0, -1, 0], "radius": 0.5, "intensity": 8},
    "medium": {"sigma_s": 0.1, "sigma_a": 0}})");
  const int W = 9, H = 9;  // the middle pixel's ray is the disk's axis
  double expected = diskAxisInscatter(8.0, 0.5, 5.0, 4.5, 0.1);
  GroundTruthOptions options;
  options.width = W;
  options.height = H;
  options.steps = 1024;
  options.lightSamples = 256;
  GroundTruth gt = renderGroundTruth(scene, options);
  MethodRun ref = renderScene(scene, "raymarch:steps=1024:light_samples=64:light_sm=64", W, H);
  ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
  std::printf("disk on axis: oracle %.6g, ground truth %.6g, raymarch (64 light samples) %.6g\n", expected,
              gt.inscatter.at(4, 4)[0], ref.inscatter.at(4, 4)[0]);
  EXPECT_NEAR(gt.inscatter.at(4, 4)[0], expected, 2e-3 * expected);
  EXPECT_NEAR(ref.inscatter.at(4, 4)[0], expected, 1e-2 * expected);
}

TEST_F(AreaLightTest, TinyDiskOnItsAxisIsThePointLight) {
  // Along the axis the emission cosine is 1, so a disk of radius 1e-4 and radiance L is the point
  // light of intensity L pi r^2 there.
  const char* common = R"("camera": {"position": [0, 0, 0], "target": [0, 5, 0], "up": [0, 0, 1], "fov_y_deg": 10, "near": 0.1, "far": 4.5},
    "medium": {"sigma_s": 0.1, "sigma_a": 0.02}, "geometry": [])";
  double radius = 1e-4, L = 8.0 / (M_PI * radius * radius);
  Scene disk = sceneFromJson(std::string("{") + common + R"(, "light": {"type": "disk", "position": [0, 5, 0], "direction": [0, -1, 0], "radius": 1e-4, "intensity": )" +
                             std::to_string(L) + "}}");
  Scene point = sceneFromJson(std::string("{") + common + R"(, "light": {"type": "point", "position": [0, 5, 0], "intensity": 8}})");
  const int W = 9, H = 9;
  GroundTruthOptions options;
  options.width = W;
  options.height = H;
  options.steps = 1024;
  options.lightSamples = 16;
  GroundTruth gtDisk = renderGroundTruth(disk, options), gtPoint = renderGroundTruth(point, options);
  MethodRun gpuDisk = renderScene(disk, "raymarch:steps=1024:light_samples=4:light_sm=64", W, H);
  MethodRun gpuPoint = renderScene(point, "raymarch:steps=1024", W, H);
  ASSERT_EQ(gpuDisk.status, RunStatus::Success) << gpuDisk.reason;
  double expected = gtPoint.inscatter.at(4, 4)[0];
  EXPECT_NEAR(gtDisk.inscatter.at(4, 4)[0], expected, 1e-5 * expected);
  EXPECT_NEAR(gpuDisk.inscatter.at(4, 4)[0], gpuPoint.inscatter.at(4, 4)[0], 1e-4 * expected);
}

TEST_F(AreaLightTest, TinyLightMatchesItsCosineLobedPoint) {
  // A rect light of side 1e-4 is a point light of on-axis intensity L A with a cosine lobe: the
  // ray-marched image (4 light samples) matches the exact ground truth, shadows included.
  Scene scene = sceneFromJson(R"({"geometry": [
      {"generator": "plane", "params": {"center": [0, 0, 0], "size": [12, 12]}},
      {"generator": "box", "params": {"center": [-1, 0.75, 0], "size": [1, 1.5, 1]}},
      {"generator": "sphere", "params": {"center": [1.2, 0.8, -0.5], "radius": 0.7, "segments": 32}}],
    "camera": {"position": [0, 1.5, 6], "target": [0, 1, 0], "fov_y_deg": 55, "near": 0.05, "far": 30},
    "light": {"type": "rect", "position": [0.3, 3.5, -1.5], "target": [0, 0, 0], "width": 1e-4, "height": 1e-4, "intensity": 4e9},
    "medium": {"sigma_s": 0.08, "sigma_a": 0.02}})");
  const int W = 32, H = 24;
  GroundTruthOptions options;
  options.width = W;
  options.height = H;
  options.steps = 1024;
  options.lightSamples = 4;
  GroundTruth gt = renderGroundTruth(scene, options);
  MethodRun ref = renderScene(scene, "raymarch:steps=2048:sampling=equiangular:light_samples=4:light_sm=1024", W, H);
  ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
  ErrorMetrics ls = compareImages(ref.inscatter, gt.inscatter);
  std::printf("rect 1e-4: raymarch vs ground truth L_s relMSE %.2e ssim %.4f\n", ls.relmse, ls.ssim);
  EXPECT_LT(ls.relmse, 2e-3);
  EXPECT_GT(ls.ssim, 0.99);
}

TEST_F(AreaLightTest, ReferenceMatchesGroundTruthOnArealight) {
  const int W = 32, H = 24;
  Scene scene = loadScene("arealight");
  GroundTruthOptions options;
  options.width = W;
  options.height = H;
  options.steps = 256;
  options.lightSamples = 64;
  GroundTruth gt = renderGroundTruth(scene, options);
  MethodRun ref = renderScene(scene, referenceSpecFor(deriveEffects(scene), 1024, registeredMethods()), W, H);
  ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
  ErrorMetrics ls = compareImages(ref.inscatter, gt.inscatter), final = compareImages(ref.final, gt.final);
  std::printf("arealight: reference vs ground truth: L_s relMSE %.2e ssim %.4f; L relMSE %.2e (%.1f s)\n", ls.relmse,
              ls.ssim, final.relmse, gt.computeMs / 1000);
  EXPECT_LT(ls.relmse, 5e-3);
  EXPECT_GT(ls.ssim, 0.99);
  // The surface term takes the light's centre for every method (README): the final image differs
  // from exact visibility at the pillars' hard shadow edges, as on the other scenes.
  EXPECT_LT(final.relmse, 3e-2);
}

TEST_F(AreaLightTest, MethodsWithoutAreaLightsAreUnsupported) {
  Scene scene = loadScene("arealight");
  for (const auto& info : registeredMethods()) {
    auto method = info.create();
    std::string reason = method->unsupportedReason(scene, resolveSpec(info.name, glLimits()).params);
    if (method->capabilities().areaLight) {
      EXPECT_EQ(reason, "") << info.name;
    } else {
      EXPECT_NE(reason.find("area lights"), std::string::npos) << info.name << ": " << reason;
    }
  }
}

// ---- the per-VPL wrapper

bool mentionsVpls(const MethodRun& run) {
  for (const auto& a : run.approximations)
    if (a.find("virtual point lights (per-VPL wrapper)") != std::string::npos) return true;
  return false;
}

TEST_F(AreaLightTest, PerVplRaymarchEqualsRaymarchWithTheSameLightSamples) {
  // raymarch samples the light at the same Hammersley points itself, so wrapping it must give the
  // same L_s: what the wrapper adds (lobed point lights, per-VPL shadow maps, the sum) is exact.
  const int W = 64, H = 48;
  Scene scene = loadScene("arealight");
  MethodRun native = renderScene(scene, "raymarch:steps=128:light_samples=8:light_sm=256", W, H);
  MethodRun wrapped = renderScene(scene, "raymarch:steps=128:vpls=8:sm=256", W, H);
  ASSERT_EQ(native.status, RunStatus::Success) << native.reason;
  ASSERT_EQ(wrapped.status, RunStatus::Success) << wrapped.reason;
  ErrorMetrics ls = compareImages(wrapped.inscatter, native.inscatter);
  std::printf("raymarch per VPL vs its own 8 light samples: L_s relMSE %.2e max %.2e\n", ls.relmse, ls.maxAbs);
  EXPECT_LT(ls.relmse, 1e-5);
  EXPECT_TRUE(mentionsVpls(wrapped));
  EXPECT_FALSE(mentionsVpls(native));
  // The wrapper's passes, each one sample per frame (the sum over its VPLs).
  for (const char* pass : {"VPL Shadow Maps", "Ray Marching", "VPL Accumulation"}) {
    ASSERT_TRUE(wrapped.passStats.count(pass)) << pass;
    EXPECT_EQ(wrapped.passStats.at(pass).samples, 1u) << pass;
  }
}

TEST_F(AreaLightTest, PointLightMethodsPerVplMatchRaymarchOnTheSameVpls) {
  const int W = 96, H = 72;
  Scene scene = loadScene("arealight");
  MethodRun marched = renderScene(scene, "raymarch:steps=512:sampling=equiangular:vpls=16:sm=512", W, H);
  ASSERT_EQ(marched.status, RunStatus::Success) << marched.reason;
  for (const char* spec : {"vsv:vpls=16:sm=512", "minmax:vpls=16:sm=512"}) {
    MethodRun run = renderScene(scene, spec, W, H);
    ASSERT_EQ(run.status, RunStatus::Success) << spec << ": " << run.reason;
    ErrorMetrics ls = compareImages(run.inscatter, marched.inscatter);
    std::printf("%s vs raymarch on the same 16 VPLs: L_s relMSE %.2e ssim %.4f\n", spec, ls.relmse, ls.ssim);
    EXPECT_LT(ls.relmse, 2e-3) << spec;
    EXPECT_GT(ls.ssim, 0.98) << spec;
    EXPECT_TRUE(mentionsVpls(run)) << spec;
  }
}

TEST_F(AreaLightTest, TinyAreaLightPerVplIsItsCosineLobedPointLight) {
  // Side 1e-6 and one VPL: vsv behind the wrapper renders what vsv renders for the cosine-lobed
  // point light of intensity L A at the centre, shadows included.
  const char* common = R"("geometry": [
      {"generator": "plane", "params": {"center": [0, 0, 0], "size": [12, 12]}},
      {"generator": "box", "params": {"center": [-1, 0.75, 0], "size": [1, 1.5, 1]}}],
    "camera": {"position": [0, 1.5, 6], "target": [0, 1, 0], "fov_y_deg": 55, "near": 0.05, "far": 30},
    "medium": {"sigma_s": 0.08, "sigma_a": 0.02})";
  Scene rect = sceneFromJson(std::string("{") + common +
                             R"(, "light": {"type": "rect", "position": [0.3, 3.5, -1.5], "target": [0, 0, 0],
                                "width": 1e-6, "height": 1e-6, "intensity": 4e13}})");
  Scene point = rect;
  point.light = virtualPointLight(rect.light, rect.light.position, 1);
  ASSERT_NEAR(point.light.intensity, 40.0f, 1e-3f);
  const int W = 64, H = 48;
  for (int vpls : {1, 4}) {
    MethodRun wrapped = renderScene(rect, "vsv:vpls=" + std::to_string(vpls) + ":sm=512", W, H);
    MethodRun lobed = renderScene(point, "vsv:sm=512", W, H);
    ASSERT_EQ(wrapped.status, RunStatus::Success) << wrapped.reason;
    ASSERT_EQ(lobed.status, RunStatus::Success) << lobed.reason;
    ErrorMetrics ls = compareImages(wrapped.inscatter, lobed.inscatter);
    std::printf("rect 1e-6, %d VPLs vs its lobed point: L_s relMSE %.2e\n", vpls, ls.relmse);
    EXPECT_LT(ls.relmse, 1e-6) << vpls;
  }
  // The lobe is real: the same point light without it is brighter off the light's axis.
  Scene uniform = point;
  uniform.light.cosineLobe = false;
  MethodRun plain = renderScene(uniform, "vsv:sm=512", W, H);
  MethodRun lobed = renderScene(point, "vsv:sm=512", W, H);
  double sumPlain = 0, sumLobed = 0;
  for (size_t i = 0; i < plain.inscatter.rgb.size(); ++i) {
    sumPlain += plain.inscatter.rgb[i];
    sumLobed += lobed.inscatter.rgb[i];
  }
  EXPECT_LT(sumLobed, 0.9 * sumPlain);
}

TEST_F(AreaLightTest, AreaLightFacingAwayPerVpl) {
  // One-sided and facing up: only the fog above the light's plane is lit, next to the VPLs, where
  // the point-light singularity is strongest. Every method stays finite and near raymarch on the
  // same VPLs, and nothing below the plane is lit.
  Scene scene = loadScene("arealight");
  scene.light.direction = glm::vec3(0, 1, 0);
  const int W = 64, H = 48;
  MethodRun marched = renderScene(scene, "raymarch:steps=1024:sampling=equiangular:vpls=4:sm=256", W, H);
  ASSERT_EQ(marched.status, RunStatus::Success) << marched.reason;
  for (const char* spec : {"vsv:vpls=4:sm=256", "minmax:vpls=4:sm=256"}) {
    MethodRun run = renderScene(scene, spec, W, H);
    ASSERT_EQ(run.status, RunStatus::Success) << spec << ": " << run.reason;
    ErrorMetrics ls = compareImages(run.inscatter, marched.inscatter);
    std::printf("%s facing away: L_s relMSE %.2e against raymarch on the same VPLs\n", spec, ls.relmse);
    EXPECT_LT(ls.relmse, 5e-3) << spec;
  }
  // The floor lies below the light's plane: no direct light, whatever the method.
  EXPECT_LT(marched.final.at(W / 2, H - 1)[0], 1e-3 + marched.inscatter.at(W / 2, H - 1)[0]);
}

TEST(VirtualPointLights, TheReferenceSamplesTheLightElsewhere) {
  // The reference's light samples (light_shift) share no point with the VPLs of ivsv and the
  // wrapper, and both sets stay on the light.
  Light light;
  light.type = LightType::Rect;
  light.width = 3.0f;
  light.height = 1.5f;
  for (int count : {1, 16, 64}) {
    auto vpls = virtualPointLightPositions(light, count), shifted = virtualPointLightPositions(light, count, true);
    ASSERT_EQ(shifted.size(), size_t(count));
    for (const auto& p : shifted) {
      EXPECT_LE(std::fabs(p.x - light.position.x), 1.5f + 1e-5f);
      EXPECT_LE(std::fabs(p.z - light.position.z), 0.75f + 1e-5f);
      for (const auto& q : vpls) EXPECT_GT(glm::length(p - q), 1e-4f) << count;
    }
  }
}

TEST_F(AreaLightTest, PerVplWrapperRefusesWhatItCannotRun) {
  Scene area = loadScene("arealight"), spheres = loadScene("spheres");
  auto vsv = createMethod("vsv"), slicemap = createMethod("slicemap");
  std::string hint = unsupportedReason(area, *vsv, resolveSpec("vsv", glLimits()).params);
  EXPECT_NE(hint.find("vpls=N"), std::string::npos) << hint;
  EXPECT_EQ(unsupportedReason(area, *vsv, resolveSpec("vsv:vpls=4", glLimits()).params), "");
  std::string point = unsupportedReason(spheres, *vsv, resolveSpec("vsv:vpls=4", glLimits()).params);
  EXPECT_NE(point.find("needs an area light"), std::string::npos) << point;
  std::string fixed = unsupportedReason(area, *slicemap, resolveSpec("slicemap:vpls=4", glLimits()).params);
  EXPECT_NE(fixed.find("one light position"), std::string::npos) << fixed;
  MethodRun row = renderScene(spheres, "vsv:vpls=4", 16, 12);
  EXPECT_EQ(row.status, RunStatus::Unsupported);
  EXPECT_THROW(resolveSpec("vsv:vpls=-1", glLimits()), UsageError);
  EXPECT_THROW(resolveSpec("vsv:vpls=100000", glLimits()), UsageError);
}

}  // namespace
}  // namespace vs::testing
