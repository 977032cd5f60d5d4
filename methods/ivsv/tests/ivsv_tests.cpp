// ivsv: the point cloud and paraboloid map on the CPU, then the method end to end on `arealight`
// against raymarch on the same virtual point lights and against the reference.
#include <cmath>
#include <cstdio>

#include "gl_test.hpp"
#include "harness/evaluation/metrics.hpp"
#include "ivsv/ivsv.hpp"

namespace vs::testing {
namespace {

class IvsvTest : public GlTest {};

TEST(IvsvCpu, PointCloudLiesOnTheOpaqueTrianglesAndFollowsArea) {
  Scene scene = sceneFromJson(R"({"geometry": [
      {"generator": "plane", "params": {"center": [0, 0, 0], "size": [4, 4]}},
      {"generator": "plane", "params": {"center": [0, 2, 0], "size": [2, 2]}}],
    "camera": {"position": [0, 1, 6], "target": [0, 1, 0]},
    "light": {"type": "rect", "position": [0, 5, 0], "direction": [0, -1, 0], "width": 1, "height": 1, "intensity": 1},
    "medium": {"sigma_s": 0.1, "sigma_a": 0}})");
  std::vector<glm::vec4> points = ivsv::samplePointCloud(scene, 20000, 7);
  ASSERT_EQ(points.size(), 20000u);
  size_t upper = 0;
  for (const auto& p : points) {
    EXPECT_TRUE(std::fabs(p.y) < 1e-5f || std::fabs(p.y - 2.0f) < 1e-5f) << p.y;
    upper += p.y > 1.0f;
  }
  EXPECT_NEAR(double(upper) / points.size(), 4.0 / 20.0, 0.015);  // areas 4 and 16
}

// Alpha-tested runs (SetupContext::alphaTest) put ISM points on semi-transparent occluders only
// where they block: a constant opacity against the threshold, a textured one texel by texel.
TEST(IvsvCpu, PointCloudFollowsTheAlphaTest) {
  Scene scene = sceneFromJson(R"({"geometry": [
      {"generator": "plane", "params": {"center": [0, 0, 0], "size": [4, 4]}},
      {"generator": "plane", "params": {"center": [0, 2, 0], "size": [2, 2]}, "opacity": 0.4}],
    "camera": {"position": [0, 1, 6], "target": [0, 1, 0]},
    "light": {"type": "rect", "position": [0, 5, 0], "direction": [0, -1, 0], "width": 1, "height": 1, "intensity": 1},
    "medium": {"sigma_s": 0.1, "sigma_a": 0}})");
  auto upperShare = [&](float alphaTest) {
    std::vector<glm::vec4> points = ivsv::samplePointCloud(scene, 4000, 7, alphaTest);
    size_t upper = 0;
    for (const auto& p : points) upper += p.y > 1.0f;
    return double(upper) / double(std::max<size_t>(points.size(), 1));
  };
  EXPECT_EQ(upperShare(-1.0f), 0.0);  // not alpha-tested: opaque meshes only
  EXPECT_EQ(upperShare(0.5f), 0.0);   // opacity 0.4 lets the light through at 0.5
  EXPECT_NEAR(upperShare(0.3f), 4.0 / 20.0, 0.03);  // ... and blocks it at 0.3
  // The upper plane textured: alpha 0 where x < 0, 1 where x > 0 (u = (x + 1) / 2).
  Mesh& card = scene.meshes[1];
  card.opacity = 1.0f;
  card.alphaTexture = 0;
  card.uvs.clear();
  for (const glm::vec3& p : card.positions) card.uvs.push_back({(p.x + 1.0f) * 0.5f, (p.z + 1.0f) * 0.5f});
  AlphaTexture halves;
  halves.width = 64;
  halves.height = 1;
  for (int i = 0; i < 64; ++i) halves.alpha.push_back(i < 32 ? 0.0f : 1.0f);
  scene.alphaTextures = {halves};
  std::vector<glm::vec4> points = ivsv::samplePointCloud(scene, 4000, 7, 0.5f);
  ASSERT_EQ(points.size(), 4000u);
  size_t right = 0, left = 0;
  for (const auto& p : points) {
    if (p.y < 1.0f) continue;
    // Bilinear filtering blends the halves within half a texel of u = 0 (wrapping) and u = 0.5.
    right += p.x > 0.0f;
    left += p.x < -0.04f && p.x > -0.96f;
  }
  EXPECT_EQ(left, 0u);
  EXPECT_GT(right, 360u);  // the right half: area 2 of 16 + 2, about 444 points
}

TEST(IvsvCpu, ParaboloidMapsTheHemisphereIntoTheUnitDisk) {
  glm::vec3 t(1, 0, 0), b(0, 0, 1), n(0, -1, 0);
  EXPECT_NEAR(glm::length(ivsv::paraboloid(n, t, b, n)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(ivsv::paraboloid(t, t, b, n)), 1.0f, 1e-6f);  // the horizon
  glm::vec3 d = glm::normalize(glm::vec3(0.3f, -0.8f, 0.2f));
  EXPECT_LT(glm::length(ivsv::paraboloid(d, t, b, n)), 1.0f);
}

TEST_F(IvsvTest, MatchesRaymarchOnTheSameVirtualPointLights) {
  // Same 64 Hammersley VPLs: what is left is the ISM's and the coarse grid's visibility.
  const int W = 96, H = 72;
  Scene scene = loadScene("arealight");
  MethodRun marched = renderScene(scene, "raymarch:steps=256:sampling=equiangular:vpls=64:sm=512", W, H);
  ASSERT_EQ(marched.status, RunStatus::Success) << marched.reason;
  MethodRun run = renderScene(scene, "ivsv:lights=64:steps=64", W, H);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  ErrorMetrics ls = compareImages(run.inscatter, marched.inscatter);
  std::printf("ivsv vs raymarch on the same 64 VPLs: L_s relMSE %.2e ssim %.4f\n", ls.relmse, ls.ssim);
  EXPECT_LT(ls.relmse, 5e-4);  // 6.2e-5 measured
  EXPECT_GT(ls.ssim, 0.99);
  for (const char* pass : {"VPL Sampling", "Imperfect Shadow Maps", "Voxelize", "Scan", "Final Gather"})
    EXPECT_TRUE(run.passStats.count(pass)) << pass;
}

TEST_F(IvsvTest, UnshadowedEqualsRaymarchWithoutOccluders) {
  // Without casters the grids are empty: the gather is the plain VPL integral.
  const int W = 64, H = 48;
  Scene scene = loadScene("arealight");
  RunOptions options = RunOptions::singleFrame(W, H);
  options.shadowCasters = false;
  MethodRun marched = renderScene(scene, "raymarch:steps=256:sampling=equiangular:vpls=16:sm=256", options);
  MethodRun run = renderScene(scene, "ivsv:lights=16:steps=256", options);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  ErrorMetrics ls = compareImages(run.inscatter, marched.inscatter);
  std::printf("ivsv unshadowed vs raymarch: L_s relMSE %.2e\n", ls.relmse);
  EXPECT_LT(ls.relmse, 1e-3);
}

TEST_F(IvsvTest, AThousandVplsFitTheDispatchLimits) {
  // 4M points need more than 65,535 splat workgroups along x; 1,024 grids fill the array's layers.
  MethodRun run = renderScene(loadScene("arealight"), "ivsv:lights=1024:steps=2", 24, 18);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
}

TEST_F(IvsvTest, OneVplAndALightTouchingAnOccluderStayCloseToRaymarch) {
  // One VPL (at the light's centre, a cosine-lobed point light), and a one-sided disk resting on a
  // sphere's top: ISM points at distance ~0 from the VPLs must not blow up or black out the fog.
  Scene touching = sceneFromJson(R"({"geometry": [
      {"generator": "plane", "params": {"center": [0, 0, 0], "size": [10, 10]}},
      {"generator": "sphere", "params": {"center": [0, 1.0, 0], "radius": 0.6, "segments": 32}}],
    "camera": {"position": [0, 1.5, 6], "target": [0, 1, 0], "fov_y_deg": 55, "near": 0.05, "far": 30},
    "light": {"type": "disk", "position": [0, 1.61, 0], "direction": [0, -1, 0.3], "radius": 0.3, "intensity": 80},
    "medium": {"sigma_s": 0.08, "sigma_a": 0.02}})");
  for (const auto& [scene, lights] : {std::pair<Scene, int>{loadScene("arealight"), 1}, {touching, 16}}) {
    std::string n = std::to_string(lights);
    MethodRun marched = renderScene(scene, "raymarch:steps=256:sampling=equiangular:sm=512:vpls=" + n, 64, 48);
    MethodRun run = renderScene(scene, "ivsv:steps=64:lights=" + n, 64, 48);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    ErrorMetrics ls = compareImages(run.inscatter, marched.inscatter);
    std::printf("%d VPL(s): ivsv vs raymarch on the same VPLs: L_s relMSE %.2e\n", lights, ls.relmse);
    // Measured: 2.6e-4 with one VPL; 1.4e-2 touching, where the sphere fills most of each VPL's
    // hemisphere from a few centimetres and its points leave holes (README, known limits).
    EXPECT_LT(ls.relmse, lights == 1 ? 2e-3 : 5e-2) << lights;
    EXPECT_EQ(run.nonFinitePixels, 0u);
  }
}

TEST_F(IvsvTest, RefusesTwoSidedLightsAndPointLights) {
  Scene scene = loadScene("arealight");
  scene.light.twoSided = true;
  auto m = createMethod("ivsv");
  EXPECT_NE(m->unsupportedReason(scene, resolveSpec("ivsv", glLimits()).params).find("two-sided"), std::string::npos);
  Scene spheres = loadScene("spheres");
  EXPECT_NE(m->unsupportedReason(spheres, resolveSpec("ivsv", glLimits()).params), "");
}

}  // namespace
}  // namespace vs::testing
