// minmax: the traversal against a brute-force scan, accuracy against raymarch, hard cases.
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/SVD>
#include <glm/gtc/matrix_transform.hpp>

#include "gl_test.hpp"
#include "harness/evaluation/metrics.hpp"
#include "minmax/epipolar.hpp"
#include "minmax/minmax.hpp"
#include "minmax/traversal.hpp"

namespace vs::testing {
namespace {

using minmax::MinMax;
using Segments = std::vector<std::pair<float, float>>;

void appendMerged(Segments& out, float a, float b) {
  if (!out.empty() && out.back().second == a) out.back().second = b;
  else out.emplace_back(a, b);
}

Segments bruteForce(const std::vector<float>& row, float beta, float g0, float g1) {
  Segments out;
  int d = int(row.size());
  g0 = std::clamp(g0, 0.0f, float(d));
  g1 = std::clamp(g1, 0.0f, float(d));
  if (!(g1 > g0)) return out;
  for (int j = int(std::floor(g0)); j < d && float(j) < g1; ++j)
    if (beta < row[j]) appendMerged(out, std::max(float(j), g0), std::min(float(j + 1), g1));
  return out;
}

TEST(MinmaxTraversal, MatchesBruteForceOnRandomRows) {
  std::mt19937 rng(12345);
  int cases = 0;
  for (int log2d = 0; log2d <= 9; ++log2d) {
    int d = 1 << log2d;
    for (int rowIndex = 0; rowIndex < 60; ++rowIndex) {
      // Few distinct values so that ties between beta and stored values are common.
      int levels = 1 + int(rng() % 6);
      std::vector<float> row(d);
      for (float& v : row) v = float(rng() % levels) * 0.5f;
      if (rowIndex % 7 == 0) std::fill(row.begin(), row.end(), 1.0f);  // constant rows
      auto tree = minmax::buildMinMaxTree(row);
      for (int q = 0; q < 40; ++q) {
        float beta = q % 3 == 0 ? float(rng() % (levels + 1)) * 0.5f : std::uniform_real_distribution<float>(-0.2f, 3.2f)(rng);
        auto pick = [&]() -> float {
          switch (rng() % 4) {
            case 0: return float(rng() % (d + 1));                                         // texel edges, row ends
            case 1: return std::uniform_real_distribution<float>(0.0f, float(d))(rng);     // anywhere
            case 2: return rng() % 2 ? 0.0f : float(d);                                    // ends of the row
            default: return std::uniform_real_distribution<float>(-1.0f, float(d) + 1.0f)(rng);  // outside
          }
        };
        float g0 = pick(), g1 = pick();
        if (g1 < g0) std::swap(g0, g1);
        Segments expected = bruteForce(row, beta, g0, g1);
        for (int mode = 0; mode < 8; ++mode) {
          minmax::TraversalOptions options{(mode & 1) != 0, (mode & 2) != 0, (mode & 4) != 0};
          Segments got;
          minmax::traverseRow(tree.data(), d, beta, g0, g1, options, [&](float a, float b) { appendMerged(got, a, b); });
          ASSERT_EQ(got, expected) << "d " << d << " beta " << beta << " [" << g0 << ", " << g1 << "] mode " << mode;
          ++cases;
        }
      }
    }
  }
  std::printf("%d traversals agree with the brute-force scan\n", cases);
}

TEST(MinmaxTraversal, DelayedRunsNeedFewerEmitsAndOneLevelClimbsTerminate) {
  std::vector<float> row(256);
  for (int j = 0; j < 256; ++j) row[j] = (j / 16) % 2 ? 0.0f : 2.0f;  // 8 lit blocks of 16
  auto tree = minmax::buildMinMaxTree(row);
  int emitsDelayed = 0, emitsEager = 0;
  minmax::traverseRow(tree.data(), 256, 1.0f, 0.0f, 256.0f, {true, true}, [&](float, float) { ++emitsDelayed; });
  minmax::traverseRow(tree.data(), 256, 1.0f, 0.0f, 256.0f, {true, false}, [&](float, float) { ++emitsEager; });
  EXPECT_EQ(emitsDelayed, 8);
  EXPECT_GE(emitsEager, 8);
  int iterations = minmax::traverseRow(tree.data(), 256, 1.0f, 0.0f, 256.0f, {true, true}, [](float, float) {});
  EXPECT_LT(iterations, 200);
}

TEST(MinmaxTraversal, TopStartSkipsTheClimbOverALongLitRun) {
  // A ray from the eye over a row lit but for its last 16 texels: from the root the walk descends
  // the right spine; from the first leaf it climbs the left one a level per step, then descends.
  std::vector<float> row(1024, 2.0f);
  for (int j = 1008; j < 1024; ++j) row[j] = 0.0f;
  auto tree = minmax::buildMinMaxTree(row);
  minmax::TraversalOptions fromLeaf{true, true, false}, fromTop{true, true, true};
  int leafIterations = minmax::traverseRow(tree.data(), 1024, 1.0f, 0.0f, 1024.0f, fromLeaf, [](float, float) {});
  int topIterations = minmax::traverseRow(tree.data(), 1024, 1.0f, 0.0f, 1024.0f, fromTop, [](float, float) {});
  EXPECT_LT(topIterations, leafIterations);
  std::printf("iterations: %d from the first leaf, %d from the top\n", leafIterations, topIterations);
}

// With the epipole on screen the low-rank grid's beta range starts at the ray-marched disk's edge,
// not at 0, and no pixel that the Integration pass takes (outside the disk) lies below it; with
// radius 0 it starts at 0 as before.
TEST(MinmaxEpipolarFrame, BetaRangeStartsAtTheRayMarchedDisk) {
  minmax::ViewInput in;
  in.width = 96;
  in.height = 72;
  in.eye = glm::dvec3(0.0, 1.0, 5.0);
  glm::dvec3 target(0.0, 1.0, 0.0);
  in.forward = glm::normalize(target - in.eye);
  glm::dmat4 viewProj = glm::perspective(glm::radians(60.0), 96.0 / 72.0, 0.1, 100.0) *
                        glm::lookAt(in.eye, target, glm::dvec3(0.0, 1.0, 0.0));
  in.viewProj = viewProj;
  in.invViewProj = glm::inverse(viewProj);
  in.lightPos = glm::dvec3(0.7, 1.4, -3.0);  // in front of the camera: the epipole is on screen
  in.boundsLo = glm::dvec3(-5.0);
  in.boundsHi = glm::dvec3(5.0);
  minmax::EpipolarFrame open = minmax::computeEpipolarFrame(in);
  ASSERT_TRUE(open.fullCircle);
  EXPECT_EQ(open.betaLo, 0.0);
  for (double radius : {2.0, 8.0, 20.0}) {
    in.epipoleRadius = radius;
    minmax::EpipolarFrame f = minmax::computeEpipolarFrame(in);
    EXPECT_GT(f.betaLo, 0.0) << radius;
    double smallest = 10.0;
    for (int y = 0; y < in.height; ++y) {
      for (int x = 0; x < in.width; ++x) {
        glm::dvec2 pixel(x + 0.5, y + 0.5);
        if (glm::length(pixel - f.epipolePixel) < radius) continue;  // the Near Epipole pass's
        glm::dvec3 v = minmax::pixelRay(in, pixel.x, pixel.y);
        smallest = std::min(smallest, std::acos(std::clamp(glm::dot(v, f.axis), -1.0, 1.0)));
      }
    }
    EXPECT_LE(f.betaLo, smallest) << radius;
    EXPECT_GT(f.betaLo, 0.9 * smallest) << radius;  // and not much below it
  }
}


// The low-rank factors (from the eigenproblem of S S^T) against a full SVD of the same 64x64
// samples truncated to the same rank: the same approximation, for point and directional lights
// and ranks 1..16 (the product sum_i B_i(beta) Gamma_i(gamma) at the grid nodes).
TEST(MinmaxLowRank, MatchesTheTruncatedSvd) {
  for (bool directional : {false, true}) {
    minmax::EpipolarFrame f;
    f.directional = directional;
    f.eyeLightDistance = directional ? 1.0 : 6.0;
    f.betaLo = 0.05;
    f.betaHi = 2.9;
    f.gammaAll = directional ? 20.0 : 2.5;
    minmax::MediumParams m{directional, 0.1, 0.12, true, 0.4};
    Eigen::MatrixXd samples(minmax::kGrid, minmax::kGrid);
    for (int r = 0; r < minmax::kGrid; ++r)
      for (int c = 0; c < minmax::kGrid; ++c)
        samples(r, c) = minmax::smoothIntegrand(m, f.eyeLightDistance, minmax::betaAtGrid(f, r / (minmax::kGrid - 1.0)),
                                                minmax::gammaAtGrid(f, c / (minmax::kGrid - 1.0)));
    Eigen::BDCSVD<Eigen::MatrixXd> svd(samples, Eigen::ComputeThinU | Eigen::ComputeThinV);
    for (int rank : {1, 2, 4, 8, 16}) {
      minmax::LowRank lr = minmax::lowRankApproximation(f, m, rank, 64);
      ASSERT_EQ(lr.rank, rank);
      Eigen::MatrixXd expected = svd.matrixU().leftCols(rank) * svd.singularValues().head(rank).asDiagonal() *
                                 svd.matrixV().leftCols(rank).transpose();
      double worst = 0.0;
      for (int r = 0; r < minmax::kGrid; ++r)
        for (int c = 0; c < minmax::kGrid; ++c) {
          double product = 0.0;
          for (int i = 0; i < rank; ++i)
            product += double(lr.basisBeta[size_t(i) * minmax::kGrid + r]) * lr.basisGamma[size_t(i) * minmax::kGrid + c];
          worst = std::max(worst, std::fabs(product - expected(r, c)));
        }
      EXPECT_LT(worst, 1e-5 * samples.cwiseAbs().maxCoeff()) << "rank " << rank << (directional ? " directional" : " point");
      double kept = svd.singularValues().head(rank).squaredNorm() / svd.singularValues().squaredNorm();
      EXPECT_NEAR(lr.energy, kept, 1e-9);
    }
  }
}

class MinmaxTest : public GlTest {};

constexpr int kW = 96, kH = 72;

double meanValue(const Image& img) {
  double sum = 0.0;
  for (float v : img.rgb) sum += v;
  return img.rgb.empty() ? 0.0 : sum / double(img.rgb.size());
}

struct Accuracy {
  double nrmse = 0;  // RMSE of L_s over the mean of the reference's L_s
  ErrorMetrics metrics;
};

// minmax against raymarch at the same shadow-map resolution and many steps. Rays that pass close
// to a point light in view see a 1/r^2 peak that uniform steps resolve slowly (raymarch with 1024
// steps is itself ~0.2 nRMSE off on spheres), hence 8192 steps: cheap at 96x72.
Accuracy accuracy(const Scene& scene, const std::string& spec, const MethodRun& ref) {
  MethodRun run = renderScene(scene, spec, kW, kH);
  EXPECT_EQ(run.status, RunStatus::Success) << spec << ": " << run.reason;
  EXPECT_EQ(run.nonFinitePixels, 0u) << spec;
  Accuracy a;
  a.metrics = compareImages(run.inscatter, ref.inscatter);
  a.nrmse = a.metrics.rmse / std::max(meanValue(ref.inscatter), 1e-30);
  return a;
}

MethodRun reference(const Scene& scene, int sm = 512) {
  MethodRun ref = renderScene(scene, "raymarch:steps=8192:sm=" + std::to_string(sm), kW, kH);
  EXPECT_EQ(ref.status, RunStatus::Success) << ref.reason;
  return ref;
}

// README bound for the built-in scenes at 96x72, sm=512, defaults: L_s RMSE / mean(L_s) < 0.12.
TEST_F(MinmaxTest, MatchesRaymarchOnBuiltinScenes) {
  for (const char* name : {"spheres", "room", "trees", "terrain"}) {
    Scene scene = loadScene(name);
    MethodRun ref = reference(scene);
    Accuracy a = accuracy(scene, "minmax:sm=512", ref);
    std::printf("%-8s L_s nRMSE %.4f  RMSE %.3e  relMSE %.3e\n", name, a.nrmse, a.metrics.rmse, a.metrics.relmse);
    EXPECT_LT(a.nrmse, 0.12) << name;
  }
}

TEST_F(MinmaxTest, ErrorFallsAsSlicesAndRankRise) {
  Scene scene = loadScene("trees");
  MethodRun ref = reference(scene);
  std::vector<double> bySlices, byRank;
  for (int slices : {8, 32, 0}) {
    Accuracy a = accuracy(scene, "minmax:sm=512:rank=8:slices=" + std::to_string(slices), ref);
    std::printf("slices %4d (0 = auto): nRMSE %.4f\n", slices, a.nrmse);
    bySlices.push_back(a.nrmse);
  }
  for (int rank : {1, 2, 4}) {
    Accuracy a = accuracy(scene, "minmax:sm=512:rank=" + std::to_string(rank), ref);
    std::printf("rank %d: nRMSE %.4f\n", rank, a.nrmse);
    byRank.push_back(a.nrmse);
  }
  for (size_t i = 1; i < bySlices.size(); ++i) EXPECT_LT(bySlices[i], bySlices[i - 1]);
  for (size_t i = 1; i < byRank.size(); ++i) EXPECT_LT(byRank[i], byRank[i - 1]);
}

TEST_F(MinmaxTest, OptimisationsDoNotChangeTheImage) {
  Scene scene = loadScene("spheres");
  MethodRun base = renderScene(scene, "minmax:sm=512", kW, kH);
  for (const char* spec : {"minmax:sm=512:up_one_level=0", "minmax:sm=512:delay_gamma=0", "minmax:sm=512:top_start=0"}) {
    MethodRun run = renderScene(scene, spec, kW, kH);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    EXPECT_LT(compareImages(run.inscatter, base.inscatter).rmse, 1e-4 * std::max(meanValue(base.inscatter), 1e-30))
        << spec;
  }
}

// A colour checker gobo, 16x16 texels.
void setCheckerTexture(Light& light) {
  light.textureWidth = light.textureHeight = 16;
  light.textureRGB.resize(16 * 16 * 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      bool on = ((x / 4) + (y / 4)) % 2 == 0;
      float* p = &light.textureRGB[(y * 16 + x) * 3];
      p[0] = on ? 1.0f : 0.2f;
      p[1] = on ? 0.8f : 0.1f;
      p[2] = on ? 0.3f : 0.9f;
    }
}

const char* kTexturedBase = R"({
  "geometry": [
    {"generator": "plane", "params": {"center": [0, 0, 0], "size": [20, 20]}},
    {"generator": "sphere", "params": {"center": [-1.0, 1.0, 0.0], "radius": 0.8, "segments": 24}},
    {"generator": "box", "params": {"center": [1.2, 0.7, -1.0], "size": [1.0, 1.4, 1.0]}}
  ],
  "camera": {"position": [0, 2, 8], "target": [0, 1.5, 0], "up": [0, 1, 0], "fov_y_deg": 60, "near": 0.1, "far": 40},
  "light": LIGHT,
  "medium": {"sigma_s": 0.08, "sigma_a": 0.02, "phase": "hg", "g": 0.3}
})";

Scene sceneWithLight(const std::string& lightJson) {
  std::string text = kTexturedBase;
  text.replace(text.find("LIGHT"), 5, lightJson);
  return sceneFromJson(text);
}

// With the light at the eye L_s diverges (Int ds / s^2), so there is no reference to meet: every
// pixel is near the epipole, and the image must stay finite.
TEST_F(MinmaxTest, LightAtTheEyeStaysFinite) {
  std::string text = kTexturedBase;
  text.replace(text.find("LIGHT"), 5, R"({"type": "point", "position": [0, 2, 8], "intensity": 300})");
  MethodRun run = renderScene(sceneFromJson(text), "minmax:sm=256", kW, kH);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  EXPECT_EQ(run.nonFinitePixels, 0u);
  EXPECT_NE(std::find(run.passes.begin(), run.passes.end(), "Near Epipole"), run.passes.end());
}

// README bound: textured lights, L_s RMSE / mean(L_s) < 0.12.
TEST_F(MinmaxTest, TexturedLightsMatchRaymarch) {
  const char* lights[] = {
      R"({"type": "spot", "position": [0, 5, 2], "target": [0, 0, -1], "intensity": 300, "spot_inner_deg": 25, "spot_outer_deg": 40})",
      R"({"type": "point", "position": [0.5, 4, -1], "intensity": 150})",
      R"({"type": "directional", "direction": [0.3, -1, -0.4], "intensity": 4})"};
  for (const char* light : lights) {
    Scene scene = sceneWithLight(light);
    setCheckerTexture(scene.light);
    MethodRun ref = reference(scene);
    Accuracy a = accuracy(scene, "minmax:sm=512", ref);
    std::printf("textured %-70s nRMSE %.4f\n", light, a.nrmse);
    EXPECT_LT(a.nrmse, 0.12) << light;
  }
}

// README bound: every hard case renders finite pixels with L_s RMSE / mean(L_s) < 0.08.
TEST_F(MinmaxTest, HardCasesStayFiniteAndClose) {
  struct Case {
    const char* name;
    const char* light;
    const char* camera;
  };
  const Case cases[] = {
      {"epipole on screen", R"({"type": "point", "position": [0.5, 4, -1], "intensity": 150})", nullptr},
      {"epipole off screen", R"({"type": "point", "position": [12, 3, 8], "intensity": 800})", nullptr},
      {"epipole behind the camera", R"({"type": "point", "position": [0.5, 4, 12], "intensity": 400})", nullptr},
      {"looking straight at the light", R"({"type": "point", "position": [0, 3, -3], "intensity": 150})",
       R"({"position": [0, 2, 8], "target": [0, 3, -3], "up": [0, 1, 0], "fov_y_deg": 60, "near": 0.1, "far": 40})"},
      {"directional along the view", R"({"type": "directional", "direction": [0, -0.0625, -1], "intensity": 4})", nullptr},
      {"directional against the view", R"({"type": "directional", "direction": [0, -0.0625, 1], "intensity": 4})", nullptr},
      {"directional across the view", R"({"type": "directional", "direction": [1, -0.3, 0], "intensity": 4})", nullptr},
      {"spot facing the eye", R"({"type": "spot", "position": [0, 2, -4], "target": [0, 2, 8], "intensity": 300, "spot_outer_deg": 30})", nullptr},
  };
  for (const Case& c : cases) {
    std::string text = kTexturedBase;
    text.replace(text.find("LIGHT"), 5, c.light);
    if (c.camera) {
      size_t at = text.find("\"camera\": ") + 10;
      text.replace(at, text.find('}', at) + 1 - at, c.camera);
    }
    Scene scene = sceneFromJson(text);
    MethodRun ref = reference(scene);
    Accuracy a = accuracy(scene, "minmax:sm=512", ref);
    std::printf("%-32s nRMSE %.4f  max abs %.3g\n", c.name, a.nrmse, a.metrics.maxAbs);
    EXPECT_EQ(a.metrics.nonFinite, 0u) << c.name;
    EXPECT_LT(a.nrmse, 0.08) << c.name;
  }
}

// Mipmap Construction: every node of each row's tree is (min, max) of its children and the leaves
// are the rectified row, for rows of 16 to 2048 texels (every remainder of the four-level passes).
TEST_F(MinmaxTest, MipmapNodesAreMinAndMaxOfTheirChildren) {
  Scene scene = loadScene("room");
  RunOptions options = RunOptions::singleFrame(32, 24);
  for (int res : {16, 32, 64, 256, 512, 2048}) {
    Runner runner(scene, glLimits(), options);
    MinmaxMethod method;
    MethodRun run = runner.run(method, resolveSpec("minmax:slices=16:res=" + std::to_string(res), glLimits()).params);
    ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
    std::vector<DebugView> views = method.debugViews();
    ASSERT_EQ(views.size(), 1u);
    GLint width = 0, slices = 0;
    glGetTextureLevelParameteriv(views[0].texture, 0, GL_TEXTURE_WIDTH, &width);
    glGetTextureLevelParameteriv(views[0].texture, 0, GL_TEXTURE_HEIGHT, &slices);
    int d = res;
    ASSERT_EQ(width, 3 * d / 4);
    std::vector<float> tree(size_t(4 * width) * size_t(slices));
    glGetTextureImage(views[0].texture, 0, GL_RGBA, GL_FLOAT, GLsizei(tree.size() * 4), tree.data());
    int wrong = 0, occluded = 0;
    for (int k = 0; k < slices; ++k) {
      const float* row = &tree[size_t(k) * size_t(4 * width)];
      auto lo = [&](int i) { return row[minmax::gpuTreeFloat(unsigned(i), d)]; };
      auto hi = [&](int i) { return i >= d ? lo(i) : row[minmax::gpuTreeFloat(unsigned(i), d) + 1]; };
      // Leaves: the beta where a light ray is blocked (in [0, pi]) or 4 (never blocked).
      for (int i = d; i < 2 * d; ++i) {
        wrong += !(lo(i) == 4.0f || (lo(i) >= 0.0f && lo(i) <= 3.1416f));
        occluded += lo(i) < 4.0f;
      }
      for (int i = 1; i < d; ++i)
        wrong += lo(i) != std::min(lo(2 * i), lo(2 * i + 1)) || hi(i) != std::max(hi(2 * i), hi(2 * i + 1));
    }
    EXPECT_GT(occluded, d * slices / 2) << "res=" << res;  // the room's walls block most light rays
    EXPECT_EQ(wrong, 0) << "res=" << res;
  }
}

TEST_F(MinmaxTest, WorkCountersCountTheTraversal) {
  // Without shadow casters every row is one lit run; with the spheres' shadows the rows break into
  // several, and the traversal takes more steps. The counters come from an extra, untimed frame.
  Scene scene = loadScene("spheres");
  RunOptions options = RunOptions::singleFrame(kW, kH);
  options.workCounters = true;
  MethodRun shadowed = renderScene(scene, "minmax:sm=512", options);
  options.shadowCasters = false;
  MethodRun open = renderScene(scene, "minmax:sm=512", options);
  ASSERT_EQ(open.status, RunStatus::Success) << open.reason;
  ASSERT_EQ(shadowed.status, RunStatus::Success) << shadowed.reason;
  for (const MethodRun* run : {&open, &shadowed}) {
    ASSERT_TRUE(run->stats.count("minmax_iterations_mean"));
    EXPECT_GT(run->stats.at("minmax_pixels"), 0.5 * kW * kH);
    EXPECT_LE(run->stats.at("minmax_pixels"), double(kW * kH));
    EXPECT_GE(run->stats.at("minmax_iterations_max"), run->stats.at("minmax_iterations_mean"));
  }
  EXPECT_DOUBLE_EQ(open.stats.at("minmax_lit_runs_max"), 1.0);
  EXPECT_GT(open.stats.at("minmax_lit_runs_mean"), 0.9);
  EXPECT_GT(shadowed.stats.at("minmax_lit_runs_max"), 1.0);
  EXPECT_GT(shadowed.stats.at("minmax_iterations_mean"), open.stats.at("minmax_iterations_mean"));
  std::printf("spheres %dx%d: iterations per pixel %.1f (max %.0f), lit runs %.2f (max %.0f); unshadowed %.1f, %.2f\n", kW,
              kH, shadowed.stats.at("minmax_iterations_mean"), shadowed.stats.at("minmax_iterations_max"),
              shadowed.stats.at("minmax_lit_runs_mean"), shadowed.stats.at("minmax_lit_runs_max"),
              open.stats.at("minmax_iterations_mean"), open.stats.at("minmax_lit_runs_mean"));
}

}  // namespace
}  // namespace vs::testing
