// slicemap: bit counting and colour classes on the CPU; layered transmittance oracles through
// the slicemap (surfaces and L_s); accuracy against the exact ground truth on the foliage scenes
// as slices, slicing and resolution change; opaque scenes against the reference; the paper's
// voxelization limits (steep and light-parallel primitives, more layers than slices).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fixtures.hpp"
#include "gl_test.hpp"
#include "harness/evaluation/ground_truth.hpp"
#include "harness/evaluation/metrics.hpp"
#include "oracles.hpp"
#include "slicemap/slicemap.hpp"

namespace vs::testing {
namespace {

class SlicemapTest : public GlTest {};

// ---- CPU

TEST(SlicemapCounting, BitsInFrontOfASlice) {
  std::vector<uint32_t> words = {0x80000001u, 0u, 0xFFu, 0u};  // cells 0, 31, 64..71
  EXPECT_EQ(slicemap::bitsInFront(words, 0), 0);
  EXPECT_EQ(slicemap::bitsInFront(words, 1), 1);
  EXPECT_EQ(slicemap::bitsInFront(words, 31), 1);
  EXPECT_EQ(slicemap::bitsInFront(words, 32), 2);
  EXPECT_EQ(slicemap::bitsInFront(words, 68), 6);
  EXPECT_EQ(slicemap::bitsInFront(words, 128), 10);
}

TEST(SlicemapClasses, OneClassPerTransmittance) {
  std::string problem;
  auto foliage = slicemap::colorClasses(loadScene("foliage"), false, problem);
  ASSERT_EQ(foliage.size(), 1u) << problem;
  EXPECT_NEAR(foliage[0].transmittance.x, 0.45f, 1e-6f);
  auto tinted = slicemap::colorClasses(loadScene("foliage_tinted"), true, problem);
  ASSERT_EQ(tinted.size(), 2u) << problem;  // the opaque trunk and ground, the leaves
  EXPECT_TRUE(tinted[0].opaqueMeshes);
  EXPECT_NEAR(tinted[1].transmittance.y, 1.0f - 0.55f * 0.3f, 1e-6f);
  auto spheres = slicemap::colorClasses(loadScene("spheres"), true, problem);
  ASSERT_EQ(spheres.size(), 1u);
  EXPECT_EQ(spheres[0].transmittance, glm::vec3(0.0f));
  EXPECT_TRUE(slicemap::colorClasses(loadScene("spheres"), false, problem).empty());

  Scene many = loadScene("foliage");
  Mesh leaves = many.meshes.back();
  for (float o : {0.1f, 0.2f, 0.3f, 0.4f}) {
    leaves.opacity = o;
    many.meshes.push_back(leaves);
  }
  EXPECT_TRUE(slicemap::colorClasses(many, false, problem).empty());
  EXPECT_NE(problem.find("at most 4 colour classes"), std::string::npos) << problem;
}

// ---- GPU

// K horizontal quads of opacity `o` stacked between heights 1 and 2 over a ground plane, lit by a
// directional light straight down; the camera, under the stack, looks down at the ground, which
// receives E (1 - o)^K. A thin medium (sigma_s 1e-4) makes the method run and adds < 1e-4.
std::string stackScene(int layers, double opacity, double thickness = 1.0) {
  std::string geometry = R"({"generator": "plane", "params": {"center": [0, 0, 0], "size": [40, 40]}, "albedo": [0.6, 0.6, 0.6]})";
  for (int k = 0; k < layers; ++k) {
    double h = 1.0 + thickness * (layers > 1 ? double(k) / double(layers - 1) : 0.5);
    geometry += R"(, {"generator": "plane", "params": {"center": [0, )" + std::to_string(h) +
                R"(, 0], "size": [30, 30]}, "albedo": [0.5, 0.5, 0.5], "opacity": )" + std::to_string(opacity) + "}";
  }
  return R"({"geometry": [)" + geometry + R"(],
    "camera": {"position": [0, 0.6, 0.001], "target": [0, 0, 0], "fov_y_deg": 30, "near": 0.05, "far": 20},
    "light": {"type": "directional", "direction": [0, -1, 0], "intensity": 2},
    "medium": {"sigma_s": 1e-4, "sigma_a": 0.0}})";
}

// Largest relative deviation of the ground's radiance from 0.6 / pi * 2 * t.
double worstGroundError(const MethodRun& run, double t) {
  double expected = 0.6 / M_PI * 2.0 * t, worst = 0.0;
  for (int y = 0; y < run.final.height; ++y)
    for (int x = 0; x < run.final.width; ++x)
      worst = std::max(worst, std::fabs(run.final.at(x, y)[0] - expected) / expected);
  return worst;
}

TEST_F(SlicemapTest, StackedLayersShadowTheGroundExactly) {
  // Every layer in a slice of its own (64 slices per class over one unit when the opaque ground and
  // the layers share the words, 128 unpacked; layers 1/39 apart): Shading gives the ground
  // E (1 - o)^K, with every slicing and lookup.
  for (int layers : {1, 5, 40}) {
    Scene scene = sceneFromJson(stackScene(layers, 0.5));
    for (const char* spec : {"slicemap:res=64:sm=64", "slicemap:res=64:sm=64:slicing=local", "slicemap:res=64:sm=64:lookup=prefix:pack=0:targets=3"}) {
      MethodRun run = renderScene(scene, spec, 8, 6);
      ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
      EXPECT_LT(worstGroundError(run, std::pow(0.5, layers)), 2e-3) << layers << " layers, " << spec;
    }
  }
}

TEST_F(SlicemapTest, MoreLayersThanSlicesCountOnce) {
  // 200 layers 1/199 apart: 128 uniform slices hold two layers in some slices, which count once
  // (the paper's limit); 256 slices separate them again. (A small shared shadow map: the shared
  // transmittance map holds 200 crossings per texel.)
  Scene scene = sceneFromJson(stackScene(200, 0.01));
  MethodRun one = renderScene(scene, "slicemap:res=32:targets=1:sm=64:pack=0", 8, 6);
  MethodRun two = renderScene(scene, "slicemap:res=32:targets=2:sm=64:pack=0", 8, 6);
  ASSERT_EQ(one.status, RunStatus::Success) << one.reason;
  ASSERT_EQ(two.status, RunStatus::Success) << two.reason;
  EXPECT_LT(worstGroundError(one, std::pow(0.99, 128)), 2e-3);
  EXPECT_LT(worstGroundError(two, std::pow(0.99, 200)), 2e-3);
}

TEST_F(SlicemapTest, LayersAtOneDepthShareOneSlice) {
  // Ten coincident layers: one slice holds them all, so they count once (the exact answer is
  // (1 - o)^10; the ground truth and the transmittance map count every crossing).
  Scene scene = sceneFromJson(stackScene(10, 0.5, 0.0));
  for (const char* spec : {"slicemap:res=32:sm=64", "slicemap:res=32:sm=64:slicing=local"}) {
    MethodRun run = renderScene(scene, spec, 8, 6);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    EXPECT_LT(worstGroundError(run, 0.5), 2e-3) << spec;
  }
}

TEST_F(SlicemapTest, OpacityOneLeavesShadowLikeOpaqueOccluders) {
  // Leaves of opacity 1 are opaque occluders: voxelized with the opaque class, or in the shared
  // shadow map; either way the surfaces match the exact ground truth as closely as the shared
  // Direct Lighting does.
  Scene scene = loadScene("foliage");
  scene.meshes.back().opacity = 1.0f;
  const int W = 48, H = 36;
  GroundTruthOptions options;
  options.width = W;
  options.height = H;
  options.steps = 128;
  GroundTruth gt = renderGroundTruth(scene, options);
  MethodRun shared = renderScene(scene, "raymarch:steps=128", W, H);
  double bound = 2.0 * compareImages(shared.final, gt.final).relmse + 1e-3;
  for (const char* spec : {"slicemap:steps=128", "slicemap:steps=128:opaque=shadowmap"}) {
    MethodRun run = renderScene(scene, spec, W, H);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    double err = compareImages(run.final, gt.final).relmse;
    std::printf("opacity-1 leaves, %s: L relMSE %.2e (raymarch with the shared shadow map %.2e)\n", spec, err,
                compareImages(shared.final, gt.final).relmse);
    EXPECT_LT(err, bound) << spec;
  }
}

// Per-texel opacity (alpha-textured BLEND leaf cards): each fragment's opacity falls into one of
// alpha_classes bins, a class of the bin's mean opacity; below alpha_min it sets no bit. More
// classes come closer to the exact ground truth, which applies every texel's own opacity.
TEST_F(SlicemapTest, PerTexelOpacityConvergesAsClassesRise) {
  std::string dir = makeTempDir("slicemap-alpha");
  std::vector<float> ramp(16 * 16);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) ramp[size_t(j) * 16 + i] = (float(i) + 0.5f) / 16.0f;
  std::string quad = writeAlphaQuadGltf(dir, "ramp", "BLEND", 0.0, 16, 16, ramp, 6.0, 3.0);
  Scene scene = sceneFromJson(R"({"geometry": [{"gltf": ")" + quad + R"("},
      {"generator": "plane", "params": {"center": [0, 0, 0], "size": [20, 20]}}],
    "camera": {"position": [0, 1, 5], "target": [0, 0, 0], "fov_y_deg": 40, "near": 0.1, "far": 20},
    "light": {"type": "point", "position": [0.3, 6, 0.2], "intensity": 60},
    "medium": {"sigma_s": 0.1, "sigma_a": 0.02}})");  // the camera sees the ground, not the card
  std::string problem;
  auto classes = slicemap::colorClasses(scene, true, problem, {3, 0.1f});
  ASSERT_EQ(classes.size(), 4u) << problem;  // the opaque ground and three opacity bins
  EXPECT_EQ(classes[1].alphaBin, 0);
  // Bin 0 spans opacities 0.1 to 0.4: texels 0.15625, 0.21875, 0.28125, 0.34375 (8-bit in the PNG).
  EXPECT_NEAR(1.0f - classes[1].transmittance.r, 0.25f, 2e-3f);
  const int W = 48, H = 36;
  GroundTruthOptions options;
  options.width = W;
  options.height = H;
  options.steps = 256;
  GroundTruth gt = renderGroundTruth(scene, options);
  double previous = 1e30, first = 0.0;
  MethodRun march = renderScene(scene, "raymarch:steps=256", W, H);
  std::printf("alpha ramp: raymarch L_s relMSE %.3e against the exact ground truth\n",
              compareImages(march.inscatter, gt.inscatter).relmse);
  for (int bins : {1, 2, 3, 4}) {
    MethodRun run = renderScene(
        scene, "slicemap:res=512:steps=256:opaque=shadowmap:alpha_min=0.02:alpha_classes=" + std::to_string(bins), W, H);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    bool named = false;
    for (const std::string& a : run.approximations) named = named || a.find("per-texel opacity quantised") != std::string::npos;
    EXPECT_TRUE(named);
    double err = compareImages(run.inscatter, gt.inscatter).relmse;
    std::printf("alpha ramp, %d opacity classes: L_s relMSE %.3e against the exact ground truth\n", bins, err);
    EXPECT_LT(err, previous * 1.05) << bins << " classes";
    if (bins == 1) first = err;
    previous = err;
  }
  // The part of the error the quantization adds: above slicemap's own on the card at one
  // constant opacity (depth slices, columns), which no number of classes removes.
  Scene constant = scene;
  constant.meshes[0].alphaTexture = -1;
  constant.meshes[0].opacity = 0.5f;
  MethodRun flat = renderScene(constant, "slicemap:res=512:steps=256:opaque=shadowmap", W, H);
  ASSERT_EQ(flat.status, RunStatus::Success) << flat.reason;
  double floor = compareImages(flat.inscatter, renderGroundTruth(constant, options).inscatter).relmse;
  std::printf("alpha ramp: slicemap's own error on a card of constant opacity %.3e\n", floor);
  EXPECT_LT(previous - floor, 0.5 * (first - floor));
  // Below alpha_min nothing is voxelized: at alpha_min = 1 no fragment sets a bit, so L_s is that
  // of no leaf card at all.
  Scene open = scene;
  open.meshes[0].opacity = 0.0f;
  MethodRun none = renderScene(scene, "slicemap:res=512:steps=256:opaque=shadowmap:alpha_min=1", W, H);
  MethodRun without = renderScene(open, "slicemap:res=512:steps=256:opaque=shadowmap", W, H);
  ASSERT_EQ(none.status, RunStatus::Success) << none.reason;
  EXPECT_LT(compareImages(none.inscatter, without.inscatter).relmse, 1e-6);
}

TEST_F(SlicemapTest, ScanAndPrefixLookupsAgree) {
  Scene scene = loadScene("foliage");
  for (const char* targets : {"1", "3"}) {
    MethodRun scan = renderScene(scene, std::string("slicemap:res=128:steps=32:pack=0:targets=") + targets, 48, 36);
    MethodRun prefix = renderScene(scene, std::string("slicemap:res=128:steps=32:pack=0:lookup=prefix:targets=") + targets, 48, 36);
    ASSERT_EQ(scan.status, RunStatus::Success) << scan.reason;
    ASSERT_EQ(prefix.status, RunStatus::Success) << prefix.reason;
    EXPECT_EQ(compareImages(prefix.inscatter, scan.inscatter).maxAbs, 0.0) << targets;
    EXPECT_EQ(compareImages(prefix.final, scan.final).maxAbs, 0.0) << targets;
  }
}

TEST_F(SlicemapTest, SharedColumnFetches) {
  // Under a directional light every column of a stack of horizontal layers holds the same bits,
  // so samples that share a column fetch see exactly their own visibility, also when the step
  // count is not a multiple of the group (steps=7, share=4: a group of 3 at the end).
  Scene stack = sceneFromJson(stackScene(5, 0.5));
  for (const char* steps : {"8", "7"}) {
    MethodRun one = renderScene(stack, std::string("slicemap:res=64:sm=64:steps=") + steps, 16, 12);
    MethodRun four = renderScene(stack, std::string("slicemap:res=64:sm=64:share=4:steps=") + steps, 16, 12);
    ASSERT_EQ(one.status, RunStatus::Success) << one.reason;
    ASSERT_EQ(four.status, RunStatus::Success) << four.reason;
    EXPECT_LT(compareImages(four.inscatter, one.inscatter).relmse, 1e-12) << steps;
  }
  // On foliage a shared column is a neighbour's: the shadows shift by up to half a group of steps.
  Scene foliage = loadScene("foliage");
  MethodRun one = renderScene(foliage, "slicemap:res=128:steps=64", 48, 36);
  MethodRun two = renderScene(foliage, "slicemap:res=128:steps=64:share=2", 48, 36);
  ASSERT_EQ(two.status, RunStatus::Success) << two.reason;
  double relmse = compareImages(two.inscatter, one.inscatter).relmse;
  EXPECT_GT(relmse, 0.0);
  EXPECT_LT(relmse, 1e-3);
}

TEST_F(SlicemapTest, MatchesTheExactGroundTruthOnFoliage) {
  // Against the CPU ground truth (Embree any-hit transmittance, double precision) at 48x36. L_s is
  // as close as the brute-force march with the transmittance map at the same steps; the surfaces
  // (Shading) get closer with resolution and local slicing.
  const int W = 48, H = 36;
  for (const char* name : {"foliage", "foliage_tinted"}) {
    Scene scene = loadScene(name);
    GroundTruthOptions options;
    options.width = W;
    options.height = H;
    options.steps = 512;
    GroundTruth gt = renderGroundTruth(scene, options);
    MethodRun ray = renderScene(scene, "raymarch:steps=256", W, H);
    ASSERT_EQ(ray.status, RunStatus::Success) << ray.reason;
    double rayLs = compareImages(ray.inscatter, gt.inscatter).relmse;
    std::printf("%s raymarch:steps=256: L_s relMSE %.2e\n", name, rayLs);
    std::vector<double> finals;
    for (const char* spec : {"slicemap:res=256:steps=256", "slicemap:res=512:steps=256:slicing=local:targets=2"}) {
      MethodRun run = renderScene(scene, spec, W, H);
      ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
      double ls = compareImages(run.inscatter, gt.inscatter).relmse;
      finals.push_back(compareImages(run.final, gt.final).relmse);
      std::printf("%s %s: L_s relMSE %.2e, L relMSE %.2e\n", name, spec, ls, finals.back());
      EXPECT_LT(ls, 1.2 * rayLs) << name << " " << spec;
    }
    EXPECT_LT(finals[0], 1e-2) << name;
    EXPECT_LT(finals[1], 5e-3) << name;
    EXPECT_LT(finals[1], finals[0]) << name;
  }
}

TEST_F(SlicemapTest, OpaqueScenesAgainstTheReference) {
  // Opaque occluders voxelized (the default without semi-transparent ones) or in the shared
  // shadow map: L_s within the declared bound on every built-in opaque scene.
  const int W = 64, H = 48;
  for (const char* name : {"spheres", "fence", "room", "trees", "terrain"}) {
    Scene scene = loadScene(name);
    MethodRun ref = renderScene(scene, "raymarch:steps=1024:sm=2048", W, H);
    ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
    for (const char* spec : {"slicemap", "slicemap:opaque=shadowmap"}) {
      MethodRun run = renderScene(scene, spec, W, H);
      ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
      double ls = compareImages(run.inscatter, ref.inscatter).relmse;
      std::printf("%s %s: L_s relMSE %.2e, L relMSE %.2e\n", name, spec, ls, compareImages(run.final, ref.final).relmse);
      EXPECT_LT(ls, SlicemapMethod().declaredRelMseBound()) << name << " " << spec;
    }
  }
}

// A quad of opacity 0.5 and side 2 over a ground plane, tilted by `tiltDeg` from the horizontal
// about the x axis, under a directional light straight down.
std::string tiltedQuadScene(double tiltDeg) {
  double t = glm::radians(tiltDeg);
  auto corner = [&](double x, double v) {
    return "[" + std::to_string(x) + ", " + std::to_string(2.0 + v * std::sin(t)) + ", " + std::to_string(v * std::cos(t)) + "]";
  };
  auto triangle = [&](const std::string& a, const std::string& b, const std::string& c) {
    return R"(, {"generator": "triangle", "params": {"vertices": [)" + a + ", " + b + ", " + c + R"(]}, "opacity": 0.5})";
  };
  return R"({"geometry": [{"generator": "plane", "params": {"center": [0, 0, 0], "size": [8, 8]}, "albedo": [0.6, 0.6, 0.6]})" +
         triangle(corner(-1, -1), corner(1, -1), corner(1, 1)) + triangle(corner(-1, -1), corner(1, 1), corner(-1, 1)) + R"(],
    "camera": {"position": [3, 4, 5], "target": [0, 0, 0], "fov_y_deg": 50, "near": 0.1, "far": 20},
    "light": {"type": "directional", "direction": [0, -1, 0], "intensity": 2},
    "medium": {"sigma_s": 1e-4, "sigma_a": 0.0}})";
}

TEST_F(SlicemapTest, SteepAndLightParallelPrimitives) {
  // One fragment per column and primitive: a steep quad sets one bit per column although it
  // crosses many slices there (holes in the voxelization), yet every light ray still crosses it
  // once, so its shadow is right. A quad exactly parallel to the light rasterizes to nothing:
  // no bits, no shadow, as for a shadow map and for the exact ground truth.
  RunOptions options = RunOptions::singleFrame(16, 12);
  for (double tilt : {0.0, 60.0, 85.0, 90.0}) {
    Scene scene = sceneFromJson(tiltedQuadScene(tilt));
    Runner runner(scene, glLimits(), options);
    SlicemapMethod method;
    MethodRun run = runner.run(method, resolveSpec("slicemap:res=128:sm=128:opaque=shadowmap", glLimits()).params);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    std::vector<uint32_t> words = method.readSlicemap(0, 0);
    int columns = 0, bits = 0;
    for (size_t c = 0; c < words.size() / 4; ++c) {
      int n = slicemap::bitsInFront({words.begin() + long(4 * c), words.begin() + long(4 * c + 4)}, 128);
      columns += n > 0;
      bits += n;
    }
    // Cells a surface voxelization would fill: in each column the quad spans texel * tan(tilt) in
    // depth, over slices of 2 sin(tilt) / 128 (uniform slicing over the quad's own depth range).
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const Mesh& m : scene.meshes)
      for (const glm::vec3& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
    double texel = glm::length(hi - lo) / 128.0;  // the shared ortho view spans the bounding sphere
    double t = glm::radians(tilt);
    double perColumn = tilt > 0.0 && tilt < 90.0 ? 1.0 + texel * std::tan(t) / (2.0 * std::sin(t) / 128.0) : 1.0;
    double crossed = double(columns) * perColumn;
    std::printf("tilt %.0f deg: %d columns, %d bits set, %.0f cells crossed (%.1f%% voxelized)\n", tilt, columns, bits,
                crossed, crossed > 0.0 ? 100.0 * bits / crossed : 0.0);
    EXPECT_EQ(bits, columns) << "one bit per covered column";
    if (tilt >= 90.0) EXPECT_EQ(bits, 0);
    else EXPECT_GT(columns, 0);
    GroundTruthOptions gtOptions;
    gtOptions.width = options.width;
    gtOptions.height = options.height;
    gtOptions.steps = 64;
    GroundTruth gt = renderGroundTruth(scene, gtOptions);
    double err = compareImages(run.final, gt.final).relmse;
    std::printf("  L relMSE against the ground truth %.2e\n", err);
    EXPECT_LT(err, tilt >= 85.0 ? 2e-2 : 5e-3) << "tilt " << tilt;
    // The shadow is there (and absent for the light-parallel quad).
    RunOptions open = options;
    open.shadowCasters = false;
    MethodRun unshadowed = renderScene(scene, "slicemap:res=128:sm=128:opaque=shadowmap", open);
    double darkening = compareImages(run.final, unshadowed.final).relmse;
    std::printf("  L relMSE against the unshadowed image %.2e\n", darkening);
    if (tilt < 90.0) EXPECT_GT(darkening, 1e-3) << "tilt " << tilt;
    else EXPECT_LT(darkening, 1e-6);
  }
}

TEST_F(SlicemapTest, ShadingAgainstTheSharedShadowMap) {
  // The paper's use: surfaces shadowed by the slicemaps. On foliage the surfaces' error against the
  // ground truth is printed beside the shared Direct Lighting's (exact transmittance map at sm).
  const int W = 48, H = 36;
  Scene scene = loadScene("foliage");
  GroundTruthOptions options;
  options.width = W;
  options.height = H;
  options.steps = 256;
  GroundTruth gt = renderGroundTruth(scene, options);
  MethodRun own = renderScene(scene, "slicemap:res=512:steps=64", W, H);
  MethodRun shared = renderScene(scene, "slicemap:res=512:steps=64:surface=0", W, H);
  ASSERT_EQ(own.status, RunStatus::Success) << own.reason;
  ASSERT_EQ(shared.status, RunStatus::Success) << shared.reason;
  EXPECT_EQ(std::count(own.passes.begin(), own.passes.end(), "Shading"), 1);
  EXPECT_EQ(std::count(shared.passes.begin(), shared.passes.end(), "Shading"), 0);
  double eOwn = compareImages(own.final, gt.final).relmse, eShared = compareImages(shared.final, gt.final).relmse;
  std::printf("foliage surfaces: slicemap Shading L relMSE %.2e, shared shadow + transmittance map %.2e\n", eOwn, eShared);
  EXPECT_LT(eOwn, 5e-3);
  EXPECT_NE(own.final.rgb, shared.final.rgb);
}

TEST_F(SlicemapTest, WithOpaqueSlicesTheSharedShadowMapIsNotRendered) {
  Scene scene = loadScene("spheres");
  MethodRun own = renderScene(scene, "slicemap", 16, 12);
  ASSERT_EQ(own.status, RunStatus::Success) << own.reason;
  EXPECT_EQ(std::count(own.passes.begin(), own.passes.end(), "Shadow Map"), 0);
  EXPECT_EQ(std::count(own.passes.begin(), own.passes.end(), "Slicemap"), 1);
  MethodRun paper = renderScene(loadScene("foliage"), "slicemap:slicing=local:lookup=prefix:opaque=shadowmap:pack=0", 16, 12);
  ASSERT_EQ(paper.status, RunStatus::Success) << paper.reason;
  for (const char* pass : {"Shadow Map", "Near/Far Maps", "Slicemap", "Prefix Counts", "Scattering", "Shading"})
    EXPECT_EQ(std::count(paper.passes.begin(), paper.passes.end(), pass), 1) << pass;
}

TEST_F(SlicemapTest, PointAndSpotLightsAgainstTheReference) {
  // Six cube faces around a point light, one view for a spot light, with semi-transparent leaves.
  const int W = 48, H = 36;
  for (const char* type : {"point", "spot"}) {
    Scene scene = loadScene("foliage");
    if (std::string(type) == "spot") {
      scene.light.type = LightType::Spot;
      scene.light.direction = glm::normalize(glm::vec3(0.0f, 3.4f, 0.0f) - scene.light.position);
      scene.light.spotInnerDeg = 30.0f;
      scene.light.spotOuterDeg = 40.0f;
    }
    MethodRun ref = renderScene(scene, "raymarch:steps=512", W, H);
    MethodRun run = renderScene(scene, "slicemap:steps=512", W, H);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    double err = compareImages(run.inscatter, ref.inscatter).relmse;
    std::printf("foliage, %s light: L_s relMSE against raymarch at the same steps %.2e\n", type, err);
    EXPECT_LT(err, 1e-3) << type;
  }
}

TEST_F(SlicemapTest, RefusesWhatItCannotVoxelize) {
  auto method = createMethod("slicemap");
  ResolvedSpec spec = resolveSpec("slicemap", glLimits());
  EXPECT_NE(method->unsupportedReason(loadScene("volumes"), spec.params).find("volume"), std::string::npos);
  ResolvedSpec huge = resolveSpec("slicemap:res=8192:targets=8", glLimits());
  EXPECT_NE(method->unsupportedReason(loadScene("foliage"), huge.params).find("MiB of slicemaps"), std::string::npos);
  ResolvedSpec prefixPacked = resolveSpec("slicemap:lookup=prefix", glLimits());
  EXPECT_NE(method->unsupportedReason(loadScene("foliage"), prefixPacked.params).find("pack=0"), std::string::npos);
  EXPECT_EQ(method->unsupportedReason(loadScene("spheres"), prefixPacked.params), "");  // one class: nothing to pack
  ResolvedSpec sharedPrefix = resolveSpec("slicemap:lookup=prefix:pack=0:share=2", glLimits());
  EXPECT_NE(method->unsupportedReason(loadScene("foliage"), sharedPrefix.params).find("lookup=scan"), std::string::npos);
  EXPECT_THROW(resolveSpec("slicemap:targets=9", glLimits()), UsageError);
  EXPECT_THROW(resolveSpec("slicemap:res=100", glLimits()), UsageError);
}

}  // namespace
}  // namespace vs::testing
