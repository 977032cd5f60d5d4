// Moving scenes: every method follows the camera, the light and the geometry, so frame i of a
// sequence equals the scene's state at t_i rendered as a still frame (nothing a method built for
// an earlier frame survives), and the rebuild a move costs is a timed pass of the frame.
#include <algorithm>
#include <cstdio>

#include "gl_test.hpp"
#include "harness/evaluation/metrics.hpp"

namespace vs::testing {
namespace {

class AnimationTest : public GlTest {};

// A scene with camera and light tracks over two seconds at 2 fps (five frames, looping): the
// camera swings sideways and back, the light travels (position, or direction for a sun).
Scene moving(const std::string& name) {
  Scene scene = loadScene(name);
  Animation& a = scene.animation;
  a.duration = 2.0;
  a.fps = 2.0;
  const glm::vec3 eye = scene.camera.position;
  a.cameraPosition = {{0.0f, 1.0f, 2.0f}, {eye, eye + glm::vec3(1.5f, 0.4f, 0.0f), eye}, Interpolation::CatmullRom};
  if (scene.light.type == LightType::Directional) {
    const glm::vec3 d = scene.light.direction;
    a.lightDirection = {{0.0f, 2.0f}, {d, glm::normalize(d + glm::vec3(0.4f, 0.0f, 0.3f))}, Interpolation::Linear};
  } else {
    const glm::vec3 p = scene.light.position;
    a.lightPosition = {{0.0f, 2.0f}, {p, p + glm::vec3(1.2f, -0.3f, 0.8f)}, Interpolation::Linear};
  }
  return scene;
}

// The specs of every registered method that runs `scene` (the per-VPL wrapper for point-light
// methods on an area light), each at its first rung and a small shadow map.
std::vector<std::string> specsFor(const Scene& scene, const gl::Limits& limits) {
  std::vector<std::string> specs;
  for (const MethodInfo& info : registeredMethods()) {
    auto method = info.create();
    std::vector<std::string> ladder = method->qualityLadder();
    std::string spec = info.name + (ladder.front().empty() ? "" : ":" + ladder.front()) + ":sm=256";
    if (!unsupportedReason(scene, *method, resolveSpec(spec, limits).params).empty()) {
      spec += ":vpls=4";
      if (!unsupportedReason(scene, *method, resolveSpec(spec, limits).params).empty()) continue;
    }
    specs.push_back(spec);
  }
  return specs;
}

// Frames 3 and 6 of `scene` against its still states; `refitPass` must run exactly for the methods
// that `refits` names.
void expectFramesEqualStills(const Scene& scene, const std::string& label, const gl::Limits& limits,
                             const char* refitPass, bool (*refits)(const Method&, const Effects&)) {
  for (const std::string& spec : specsFor(scene, limits)) {
    for (int frame : {3, 6}) {  // mid-sequence, and the second pass of the loop (6 mod 5 = 1)
      RunOptions options;
      options.width = 40;
      options.height = 30;
      options.frames = 1;
      options.warmup = frame;  // frames 0..frame-1 move camera, light and geometry first
      MethodRun animated = renderScene(scene, spec, options);
      ASSERT_EQ(animated.status, RunStatus::Success) << label << " " << spec << ": " << animated.reason;
      const Scene still = sceneAt(scene, scene.animation.timeOf(uint32_t(frame)));
      MethodRun expected = renderScene(still, spec, options);  // the same frame index: the same jitter
      ASSERT_EQ(expected.status, RunStatus::Success) << expected.reason;
      ErrorMetrics ls = compareImages(animated.inscatter, expected.inscatter);
      ErrorMetrics final = compareImages(animated.final, expected.final);
      std::printf("%-18s %-50s frame %d: L_s relMSE %.2e, L relMSE %.2e\n", label.c_str(), spec.c_str(), frame,
                  ls.relmse, final.relmse);
      EXPECT_LE(ls.relmse, 1e-6) << label << " " << spec << " frame " << frame;
      EXPECT_LE(final.relmse, 1e-6) << label << " " << spec << " frame " << frame;
      EXPECT_EQ(animated.nonFinitePixels, 0u);
      // A method fitted to what moved pays for the refit in the frame; the others never refit.
      auto method = createMethod(animated.method);
      const bool ranRefit = std::find(animated.passes.begin(), animated.passes.end(), refitPass) != animated.passes.end();
      EXPECT_EQ(ranRefit, refits(*method, deriveEffects(scene))) << spec;
      const bool placedGeometry =
          std::find(animated.passes.begin(), animated.passes.end(), kGeometryUpdatePass) != animated.passes.end();
      EXPECT_EQ(placedGeometry, scene.animation.movesGeometry()) << spec;
    }
  }
}

bool dependsOnLight(const Method& method, const Effects& effects) { return method.setupDependsOnLight(effects); }
bool dependsOnGeometry(const Method& method, const Effects& effects) { return method.setupDependsOnGeometry(effects); }

void expectFramesEqualStills(const std::string& sceneName, const gl::Limits& limits) {
  expectFramesEqualStills(moving(sceneName), sceneName, limits, kLightRefitPass, dependsOnLight);
}

// The scene's objects (every mesh but the first: the ground, the room) turning about a tilted axis
// through their centre and sliding, camera and light still.
Scene movingObjects(const std::string& name) {
  Scene scene = loadScene(name);
  Animation& a = scene.animation;
  a.duration = 2.0;
  a.fps = 2.0;
  GeometryMotion g;
  g.entry = "objects";
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (size_t i = 1; i < scene.meshes.size(); ++i) {
    g.meshes.push_back(i);
    for (const glm::vec3& p : scene.meshes[i].positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  }
  g.pivot = 0.5f * (lo + hi);
  g.axis = glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f));
  g.angleDeg = {{0.0f, 1.0f, 2.0f}, {0.0f, 35.0f, 10.0f}, Interpolation::CatmullRom};
  g.translate = {{0.0f, 2.0f}, {glm::vec3(0.0f), glm::vec3(0.3f, 0.1f, -0.2f)}, Interpolation::Linear};
  a.geometry.push_back(g);
  sequenceBounds(scene, scene.motionLo, scene.motionHi);
  scene.hasMotionBounds = true;
  return scene;
}

void expectGeometryFramesEqualStills(const std::string& sceneName, const gl::Limits& limits) {
  expectFramesEqualStills(movingObjects(sceneName), sceneName + " (objects)", limits, kGeometryRefitPass,
                          dependsOnGeometry);
}

TEST_F(AnimationTest, PointLightFramesEqualTheirStills) { expectFramesEqualStills("spheres", limits()); }
TEST_F(AnimationTest, VolumeFramesEqualTheirStills) { expectFramesEqualStills("volumes", limits()); }
TEST_F(AnimationTest, AreaLightFramesEqualTheirStills) { expectFramesEqualStills("arealight", limits()); }
TEST_F(AnimationTest, SunFramesEqualTheirStills) { expectFramesEqualStills("terrain", limits()); }
TEST_F(AnimationTest, MovingObjectFramesEqualTheirStills) { expectGeometryFramesEqualStills("spheres", limits()); }
TEST_F(AnimationTest, MovingFoliageFramesEqualTheirStills) { expectGeometryFramesEqualStills("foliage", limits()); }
TEST_F(AnimationTest, MovingObjectsUnderAnAreaLightFramesEqualTheirStills) {
  expectGeometryFramesEqualStills("arealight", limits());
}

// A still scene never refits and renders as before.
TEST_F(AnimationTest, StillScenesNeverRefit) {
  const Scene scene = loadScene("spheres");
  MethodRun run = renderScene(scene, "slicemap:sm=256", 32, 24, 2, 2);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  EXPECT_EQ(std::find(run.passes.begin(), run.passes.end(), kLightRefitPass), run.passes.end());
}

}  // namespace
}  // namespace vs::testing
