// Timer, result files, effects and method-spec parsing.
#include <chrono>
#include <sstream>
#include <cmath>
#include <filesystem>
#include <thread>

#include "gl_test.hpp"
#include "harness/pipeline/effects.hpp"
#include "harness/cli/progress.hpp"
#include "harness/io/results.hpp"
#include "harness/gl/thread_pinning.hpp"
#include "harness/gl/timer.hpp"

#ifdef __linux__
#include <sched.h>
#endif

namespace vs::testing {
namespace {

namespace fs = std::filesystem;

class TimerTest : public GlTest {};

TEST(TimingStatsTest, MedianMinMaxAndMdape) {
  TimingStats s = summarise({10, 12, 8, 10, 30});
  EXPECT_DOUBLE_EQ(s.medianMs, 10);
  EXPECT_DOUBLE_EQ(s.minMs, 8);
  EXPECT_DOUBLE_EQ(s.maxMs, 30);
  // |x - 10| / 10: 0, 20, 20, 0, 200 -> median 20 %.
  EXPECT_DOUBLE_EQ(s.mdapePct, 20);
  EXPECT_EQ(s.samples, 5u);
  // Nearest rank: the 95th and 99th percentiles of five frames are the slowest one.
  EXPECT_DOUBLE_EQ(s.p95Ms, 30);
  EXPECT_DOUBLE_EQ(s.p99Ms, 30);
  std::vector<double> hundred;
  for (int i = 1; i <= 100; ++i) hundred.push_back(i);
  EXPECT_DOUBLE_EQ(percentileOf(hundred, 95), 95);
  EXPECT_DOUBLE_EQ(percentileOf(hundred, 99), 99);
  EXPECT_DOUBLE_EQ(percentileOf(hundred, 0), 1);
  EXPECT_DOUBLE_EQ(percentileOf({}, 50), 0);
}

TEST_F(TimerTest, WallClockAgreesWithCpuTimedWork) {
  PassTimer timer(TimerStrategy::WallClock);
  for (int frame = 0; frame < 3; ++frame) {
    timer.beginFrame(frame > 0);
    {
      auto scope = timer.scope("Sleep");
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
    }
    {
      auto scope = timer.scope("Nothing");
    }
    timer.endFrame();
  }
  timer.finish();
  ASSERT_EQ(timer.samples().at("Sleep").size(), 2u);
  for (double ms : timer.samples().at("Sleep")) {
    EXPECT_GE(ms, 30.0);
    EXPECT_LT(ms, 45.0);
  }
  for (double ms : timer.samples().at("Nothing")) EXPECT_LT(ms, 5.0);
  for (double ms : timer.samples().at(PassTimer::kFrame)) EXPECT_GE(ms, 30.0);
}

TEST_F(TimerTest, APassRunTwiceInAFrameCountsOnceWithItsSum) {
  for (TimerStrategy strategy : {TimerStrategy::WallClock, TimerStrategy::GpuTimestamp}) {
    PassTimer timer(strategy);
    for (int frame = 0; frame < 5; ++frame) {
      timer.beginFrame(true);
      for (int light = 0; light < 2; ++light) {
        auto scope = timer.scope("Per Light");
        if (strategy == TimerStrategy::WallClock) std::this_thread::sleep_for(std::chrono::milliseconds(15));
      }
      timer.endFrame();
    }
    timer.finish();
    ASSERT_EQ(timer.samples().at("Per Light").size(), 5u) << timerStrategyName(strategy);
    if (strategy == TimerStrategy::WallClock) {
      for (double ms : timer.samples().at("Per Light")) EXPECT_GE(ms, 30.0);
    }
  }
}

TEST_F(TimerTest, GpuTimestampStrategyRecordsEveryPass) {
  gl::Texture target = gl::createTexture2D(GL_RGBA8, 64, 64);
  gl::Framebuffer fbo = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, target.id()}});
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  PassTimer timer(TimerStrategy::GpuTimestamp);
  for (int frame = 0; frame < 6; ++frame) {
    timer.beginFrame(true);
    {
      auto scope = timer.scope("Clear");
      glClear(GL_COLOR_BUFFER_BIT);
    }
    timer.endFrame();
  }
  timer.finish();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  EXPECT_EQ(timer.samples().at("Clear").size(), 6u);
  EXPECT_EQ(timer.samples().at(PassTimer::kFrame).size(), 6u);
}

TEST_F(TimerTest, CalibrationPicksWallClockWhereQueriesDisagree) {
  TimerCalibration c = calibrateTimer();
  std::printf("calibration: %s\n", c.reason.c_str());
  EXPECT_GT(c.drawWallMs, 1.0);
  EXPECT_GT(c.computeWallMs, 0.0);
  bool agree = std::fabs(c.drawTimestampMs - c.drawWallMs) < 0.25 * c.drawWallMs &&
               std::fabs(c.computeTimestampMs - c.computeWallMs) < 0.25 * c.computeWallMs;
  EXPECT_EQ(c.chosen, agree ? TimerStrategy::GpuTimestamp : TimerStrategy::WallClock);
  // llvmpipe's queries are known to under-report draws and read zero for compute.
  if (isLlvmpipe()) {
    EXPECT_EQ(c.chosen, TimerStrategy::WallClock);
  }
}

#ifdef __linux__
// The CPUs a thread may run on.
std::vector<int> affinityOf(int tid) {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (sched_getaffinity(pid_t(tid), sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

TEST_F(TimerTest, DriverThreadsArePinnedOnePerCpuAndThreadsStartedLaterStayFree) {
  calibrateTimer();  // a draw and a dispatch: the driver's workers exist
  const std::vector<int> mine = affinityOf(0);
  if (mine.size() < 2) GTEST_SKIP() << "one CPU: nothing to spread";
  EXPECT_FALSE(pinDriverThreads("off", true).applied);
  EXPECT_FALSE(pinDriverThreads("auto", false).applied);  // timestamps are used: no glFinish brackets
  const size_t threadsBefore = otherThreads().size();
  ThreadPinning p = pinDriverThreads("on", true);
  std::printf("%s\n", describe(p).c_str());
  if (threadsBefore == 0) {  // a driver without threads of its own in this process
    EXPECT_FALSE(p.applied);
    return;
  }
  ASSERT_TRUE(p.applied);
  ASSERT_EQ(p.threads.size(), threadsBefore);
  std::vector<int> used;
  for (size_t k = 0; k < p.threads.size(); ++k) {
    EXPECT_EQ(affinityOf(p.threads[k].tid), std::vector<int>{p.threads[k].cpu}) << p.threads[k].name;
    EXPECT_EQ(p.threads[k].cpu, mine[k % mine.size()]);  // consecutive threads on distinct CPUs
  }
  EXPECT_EQ(affinityOf(0), mine);  // the caller keeps its CPUs...
  std::vector<int> later;
  std::thread([&] { later = affinityOf(0); }).join();
  EXPECT_EQ(later, mine);  // ...and so do the threads it starts (the ground truth's)
  nlohmann::json j = toJson(p);
  EXPECT_EQ(j["applied"], true);
  EXPECT_EQ(j["threads"].size(), p.threads.size());
}
#endif

TEST(ShaderSourceTest, IncludesAreExpandedAndEveryLineKnowsItsFile) {
  gl::Preprocessed pre = gl::preprocess("harness/shaders/direct.frag", "#define X 1\n");
  ASSERT_EQ(pre.files.size(), 2u);
  EXPECT_EQ(pre.files[1], "harness/shaders/common.glsl");
  std::istringstream in(pre.source);
  std::string line;
  int n = 0;
  bool sawMain = false, sawCommon = false, sawDefine = false;
  while (std::getline(in, line)) {
    ++n;
    if (line.find("outRadiance = vec4(surfaceRadiance") != std::string::npos) {
      EXPECT_EQ(pre.locate(n), "harness/shaders/direct.frag:13");
      sawMain = true;
    }
    if (line.find("float phase(float cosTheta)") != std::string::npos) {
      EXPECT_EQ(pre.locate(n).rfind("harness/shaders/common.glsl:", 0), 0u) << pre.locate(n);
      sawCommon = true;
    }
    sawDefine = sawDefine || line == "#define X 1";
  }
  EXPECT_TRUE(sawMain && sawCommon && sawDefine);
  EXPECT_EQ(pre.source.rfind("#version 450 core\n", 0), 0u);
}

TEST(ProgressTest, LogsOfLongItemsShowProgressAtMostOncePerInterval) {
  // Not a terminal (a batch job's log): one line per finished item, and inside a long item one
  // line per interval; a short item stays one line.
  ::testing::internal::CaptureStderr();
  {
    Progress every(1, std::chrono::seconds(0));
    every.item(0, "stress");
    for (int i = 1; i <= 3; ++i) every.frames(i, 3);
    every.finished("done");
    Progress quiet(1);
    quiet.item(0, "short");
    for (int i = 1; i <= 3; ++i) quiet.frames(i, 3);
    quiet.finished("done");
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(),
            "[1/1] stress: 1/3\n[1/1] stress: 2/3\n[1/1] stress: done\n[1/1] short: done\n");
}

TEST(ResultsTest, CsvRoundTripsQuotesAndCommas) {
  std::vector<std::string> row = {"a", "b,c", "say \"hi\"", "", "multi\nline"};
  auto parsed = CsvTable::parse(CsvTable::format(row) + CsvTable::format({"1", "2", "3", "4", "5"}));
  ASSERT_EQ(parsed.size(), 2u);
  EXPECT_EQ(parsed[0], row);
}

TEST(ResultsTest, RunsAndPassesHaveTheDocumentedColumns) {
  auto has = [](const std::vector<std::string>& h, const std::string& c) {
    return std::find(h.begin(), h.end(), c) != h.end();
  };
  for (const char* c : {"scene", "method", "params", "status", "frame_median_ms", "rmse", "psnr", "ssim", "relmse",
                        "max_abs", "ls_rmse", "passes", "renderer", "timer", "unstable", "frame_mdape_pct"})
    EXPECT_TRUE(has(runsColumns(), c)) << c;
  for (const char* c : {"scene", "method", "params", "pass", "median_ms", "min_ms", "max_ms", "mdape_pct"})
    EXPECT_TRUE(has(passesColumns(), c)) << c;
}

TEST(ResultsTest, UpsertReplacesByKeyAndSaveIsAtomic) {
  std::string dir = makeTempDir("csv");
  std::string path = dir + "/t.csv";
  static const std::vector<std::string> columns = {"k1", "k2", "v"};
  CsvTable t(columns, 2);
  auto row = [&](const char* k1, const char* k2, const char* v) { return ResultRow(columns).set("k1", k1).set("k2", k2).set("v", v); };
  t.upsert(row("a", "x", "1"));
  t.upsert(row("a", "y", "2"));
  t.upsert(row("a", "x", "3"));
  t.save(path);
  CsvTable again({"k1", "k2", "v"}, 2);
  again.loadExisting(path);
  ASSERT_EQ(again.rows().size(), 2u);
  EXPECT_EQ(again.rows()[0][2], "3");
  for (const auto& entry : fs::directory_iterator(dir)) EXPECT_EQ(entry.path().filename(), "t.csv");
  CsvTable other({"different"}, 1);
  EXPECT_THROW(other.loadExisting(path), std::runtime_error);
  EXPECT_THROW(writeFileAtomic(dir + "/missing/sub/file", "x"), std::runtime_error);
  EXPECT_THROW(ResultRow(columns).set("no-such-column", "x"), std::logic_error);
}

TEST(ResultsTest, OlderTablesGainNewColumnsByName) {
  std::string dir = makeTempDir("csv-migrate");
  writeFile(dir + "/t.csv", "v,k1,k2\n7,a,x\n");
  static const std::vector<std::string> columns = {"k1", "k2", "new", "v"};
  CsvTable t(columns, 2);
  t.loadExisting(dir + "/t.csv");
  ASSERT_EQ(t.rows().size(), 1u);
  EXPECT_EQ(t.rows()[0], (std::vector<std::string>{"a", "x", "", "7"}));
}

TEST(ParamsTest, SpecsAreValidated) {
  EXPECT_THROW(parseMethodSpec(""), UsageError);
  EXPECT_THROW(parseMethodSpec("raymarch:steps"), UsageError);
  EXPECT_THROW(parseMethodSpec("raymarch:steps=1:steps=2"), UsageError);
  std::vector<ParamSpec> specs = {ParamSpec::integer("n", 4, 1, 8, "n"), ParamSpec::integer("sm", 64, 64, 128, "").pow2(),
                                  ParamSpec::choice("mode", "a", {"a", "b"}, ""), ParamSpec::real("x", 0.5, 0, 1, "")};
  EXPECT_EQ(ParamValues::parse("m", specs, {}).canonical(), "n=4:sm=64:mode=a:x=0.5");
  EXPECT_THROW(ParamValues::parse("m", specs, {{"n", "9"}}), UsageError);
  EXPECT_THROW(ParamValues::parse("m", specs, {{"n", "2.5"}}), UsageError);
  EXPECT_THROW(ParamValues::parse("m", specs, {{"sm", "96"}}), UsageError);
  EXPECT_THROW(ParamValues::parse("m", specs, {{"mode", "c"}}), UsageError);
  EXPECT_THROW(ParamValues::parse("m", specs, {{"x", "nan"}}), UsageError);
  EXPECT_THROW(ParamValues::parse("m", specs, {{"bogus", "1"}}), UsageError);
  EXPECT_THROW(createMethod("no-such-method"), UsageError);
}

TEST(ReferenceTest, TheFirstMethodDeclaringReferenceParametersServesEveryCaller) {
  Effects effects;
  effects.scattering = effects.extinction = true;
  ReferenceMethod reference = referenceMethodFor(effects, registeredMethods());
  ASSERT_FALSE(reference.params.empty());
  EXPECT_EQ(referenceSpecFor(effects, 512, registeredMethods()), reference.name + ":" + reference.params + ":sm=512");
  EXPECT_NO_THROW(parseMethodSpec(referenceSpecFor(effects, 512, registeredMethods())));
  EXPECT_THROW(referenceMethodFor(effects, MethodRegistry{}), std::runtime_error);
}

// The reference method itself writes its capped parameters and its brute-force baselines (the
// equal-quality columns); no caller builds its spec text.
class ReferenceBaselineTest : public GlTest {};

TEST_F(ReferenceBaselineTest, TheReferenceWritesItsBudgetAndItsBaselines) {
  for (bool area : {false, true}) {
    Effects effects;
    effects.scattering = effects.extinction = true;
    effects.areaLight = area;
    effects.light = area ? LightType::Rect : LightType::Point;
    ReferenceBudget budget;
    budget.maxSteps = 100;
    budget.maxShadowMapSize = 128;
    ReferenceMethod capped = referenceMethodFor(effects, registeredMethods(), budget);
    ResolvedSpec full = resolveSpec(referenceSpecFor(effects, 512, registeredMethods()), glLimits());
    ResolvedSpec cut = resolveSpec(capped.name + ":" + capped.params + ":sm=512", glLimits());
    auto method = createMethod(capped.name);
    int stepsParams = 0;
    for (const ParamSpec& p : method->params()) {
      if (p.kind != ParamSpec::Kind::Int || !full.params.has(p.name)) continue;
      // Every integer the budget reaches is at most the budget; the others stay as they were.
      int before = full.params.getInt(p.name), after = cut.params.getInt(p.name);
      EXPECT_LE(after, before) << p.name;
      if (after < before) {
        ++stepsParams;
        EXPECT_TRUE(after == budget.maxSteps || after == budget.maxShadowMapSize) << p.name << "=" << after;
      }
    }
    EXPECT_GE(stepsParams, area ? 2 : 1) << "the budget capped nothing";
    // Its baselines: one per series it offers, each a spec that resolves and differs by steps.
    int baselines = 0;
    for (const auto& series : method->qualitySeries(effects)) {
      std::string at8 = method->baselineParams({series.name, 8}), at16 = method->baselineParams({series.name, 16});
      if (at8.empty()) continue;
      ++baselines;
      EXPECT_NE(at8, at16);
      EXPECT_NO_THROW(resolveSpec(capped.name + ":" + at8, glLimits())) << at8;
    }
    EXPECT_GE(baselines, area ? 1 : 2) << "point lights have the uniform and the equiangular baseline";
    EXPECT_TRUE(method->baselineParams({"no-such-series", 8}).empty());
    if (!area) {  // light-ray steps per voxel reach the spec
      std::string half = method->baselineParams({"uniform", 8, 0, 0.5});
      EXPECT_DOUBLE_EQ(resolveSpec(capped.name + ":" + half, glLimits()).params.getFloat("vsteps"), 0.5) << half;
    }
    if (area) {  // light samples reach the spec
      std::string at4 = method->baselineParams({method->qualitySeries(effects)[0].name, 8, 4});
      ResolvedSpec r = resolveSpec(capped.name + ":" + at4, glLimits());
      EXPECT_EQ(r.params.getInt("light_samples"), 4) << at4;
    }
  }
}

class MinTimeTest : public GlTest {};

// --min-time: a slow run measures fewer frames, a fast one all of them, and the images read back
// are those of a full run (the measured frames are the run's last, so an image that depended on
// the frame index would not change either).
TEST_F(MinTimeTest, SlowRunsMeasureFewerFramesWithTheSameImages) {
  Scene scene = loadScene("spheres");
  RunOptions full;
  full.width = 48;
  full.height = 36;
  full.frames = 5;
  full.warmup = 1;
  const std::string spec = "raymarch:steps=64:jitter=1:sm=256";
  MethodRun all = renderScene(scene, spec, full);
  ASSERT_EQ(all.status, RunStatus::Success) << all.reason;
  EXPECT_EQ(all.frame.samples, 5u);

  RunOptions budget = full;
  budget.minTimeMs = 1e-6;  // any frame fills it: one measured frame
  MethodRun one = renderScene(scene, spec, budget);
  ASSERT_EQ(one.status, RunStatus::Success) << one.reason;
  EXPECT_EQ(one.frame.samples, 1u);
  EXPECT_EQ(one.passStats.at("Ray Marching").samples, 1u);
  EXPECT_EQ(one.inscatter.rgb, all.inscatter.rgb);

  budget.minTimeMs = 1e7;  // no frame fills it: every frame
  MethodRun capped = renderScene(scene, spec, budget);
  ASSERT_EQ(capped.status, RunStatus::Success) << capped.reason;
  EXPECT_EQ(capped.frame.samples, 5u);
  EXPECT_EQ(capped.inscatter.rgb, all.inscatter.rgb);
}

class EffectsTest : public GlTest {};

TEST_F(EffectsTest, SceneWithoutMediumRunsNoScatteringPass) {
  Scene scene = loadScene("spheres");
  scene.medium = Medium{};
  ASSERT_FALSE(deriveEffects(scene).scattering);
  MethodRun run = renderScene(scene, "raymarch:steps=16:sm=256", 32, 32);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  EXPECT_EQ(run.passes, (std::vector<std::string>{"Shadow Map", "G Buffer", "Direct Lighting", "Composite"}));
  for (float v : run.inscatter.rgb) ASSERT_EQ(v, 0.0f);
}

TEST_F(EffectsTest, SceneWithMediumRunsTheMethodPasses) {
  Scene scene = loadScene("spheres");
  ASSERT_TRUE(deriveEffects(scene).scattering);
  MethodRun run = renderScene(scene, "raymarch:steps=16:sm=256", 32, 32);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  EXPECT_NE(std::find(run.passes.begin(), run.passes.end(), "Ray Marching"), run.passes.end());
}

TEST_F(EffectsTest, EveryLightTypeRendersFiniteImages) {
  for (const char* type : {"point", "spot", "directional"}) {
    std::string json = std::string(R"({"geometry": [{"generator": "plane", "params": {"center": [0,0,0], "size": [10, 10]}},
        {"generator": "sphere", "params": {"center": [0,1,0], "radius": 1}}],
      "camera": {"position": [0,2,8], "target": [0,1,0], "up": [0,1,0], "fov_y_deg": 50, "near": 0.1, "far": 50},
      "light": {"type": ")") + type + R"(", )" +
                       (std::string(type) == "directional" ? "" : R"("position": [0,6,0], )") +
                       (std::string(type) == "point" ? "" : R"("direction": [0.2,-1,0.1], )") +
                       (std::string(type) == "spot" ? R"("spot_inner_deg": 20, "spot_outer_deg": 35, )" : "") +
                       R"("intensity": 20},
      "medium": {"sigma_s": 0.05, "sigma_a": 0.01, "phase": "hg", "g": 0.3}})";
    Scene scene = sceneFromJson(json);
    MethodRun run = renderScene(scene, "raymarch:steps=32:sm=256", 32, 32);
    ASSERT_EQ(run.status, RunStatus::Success) << type << ": " << run.reason;
    double sum = 0;
    for (float v : run.inscatter.rgb) sum += v;
    EXPECT_GT(sum, 0.0) << type;
  }
}

// Methods that fail in the ways a sweep must survive.
class FaultyMethod : public Method {
 public:
  enum class Fault { ThrowInSetup, ThrowInRender, NaNPixels, GlError, UndeclaredPass };
  explicit FaultyMethod(Fault fault) : fault_(fault) {}
  std::string name() const override { return "faulty"; }
  std::string description() const override { return "test method"; }
  Capabilities capabilities() const override {
    Capabilities c;
    c.pointLight = c.spotLight = c.directionalLight = true;
    return c;
  }
  std::vector<ParamSpec> params() const override { return {}; }
  std::vector<std::string> passes() const override { return {"Faulty Pass"}; }
  void setup(const SetupContext&, const ParamValues&) override {
    if (fault_ == Fault::ThrowInSetup) throw std::runtime_error("setup exploded");
  }
  void render(const Frame& frame, PassTimer& timer) override {
    auto scope = timer.scope("Faulty Pass");
    if (fault_ == Fault::ThrowInRender) throw std::runtime_error("render exploded");
    if (fault_ == Fault::NaNPixels) {
      const float nan[4] = {std::nanf(""), 0, 0, 1};
      glClearNamedFramebufferfv(frame.inscatterFbo, GL_COLOR, 0, nan);
    }
    if (fault_ == Fault::GlError) glBindTextureUnit(0, 987654);  // not a texture name
    if (fault_ == Fault::UndeclaredPass) {
      auto stray = timer.scope("Stray Pass");
    }
  }

 private:
  Fault fault_;
};

class FailureRowTest : public GlTest {};

TEST_F(FailureRowTest, FaultsBecomeFailureRowsWithReasons) {
  Scene scene = loadScene("spheres");
  RunOptions options = RunOptions::singleFrame(32, 24);
  Runner runner(scene, limits(), options);
  std::vector<ParamSpec> specs = allParams(FaultyMethod(FaultyMethod::Fault::NaNPixels), 1024);
  ParamValues params = ParamValues::parse("faulty", specs, {{"sm", "256"}});
  struct Expect {
    FaultyMethod::Fault fault;
    const char* reason;
  };
  for (Expect e : {Expect{FaultyMethod::Fault::ThrowInSetup, "setup exploded"},
                   Expect{FaultyMethod::Fault::ThrowInRender, "render exploded"},
                   Expect{FaultyMethod::Fault::NaNPixels, "non-finite"}, Expect{FaultyMethod::Fault::GlError, "GL error"},
                   Expect{FaultyMethod::Fault::UndeclaredPass, "pass 'Stray Pass' is not among the passes faulty declares"}}) {
    FaultyMethod method(e.fault);
    MethodRun run = runner.run(method, params);
    EXPECT_EQ(run.status, RunStatus::Failure) << e.reason;
    EXPECT_NE(run.reason.find(e.reason), std::string::npos) << run.reason;
  }
  // The GL error above was expected; the runner recovers and the next run is clean.
  gl::resetDebugErrorCount();
  auto good = createMethod("raymarch");
  MethodRun ok = runner.run(*good, resolveSpec("raymarch:steps=4:sm=256", limits()).params);
  EXPECT_EQ(ok.status, RunStatus::Success) << ok.reason;
}

}  // namespace
}  // namespace vs::testing

namespace vs::testing {
namespace {

// A method with its own light-space structure: declares it needs no shared shadow map.
class OwnShadowsMethod : public Method {
 public:
  std::string name() const override { return "own-shadows"; }
  std::string description() const override { return "test method"; }
  Capabilities capabilities() const override {
    Capabilities c;
    c.pointLight = c.surfaceShadows = true;
    return c;
  }
  std::vector<ParamSpec> params() const override { return {}; }
  std::vector<std::string> passes() const override { return {"Own Pass", "Own Surface Shadows"}; }
  std::vector<std::string> surfacePasses() const override { return {"Own Surface Shadows"}; }
  bool needsSharedShadowMap() const override { return false; }
  std::vector<std::string> approximations() const override { return {"no visibility at all"}; }
  void setup(const SetupContext&, const ParamValues&) override {}
  void render(const Frame& frame, PassTimer& timer) override {
    {
      auto scope = timer.scope("Own Pass");
      const float nothing[4] = {0, 0, 0, 1};
      glClearNamedFramebufferfv(frame.inscatterFbo, GL_COLOR, 0, nothing);
    }
    auto scope = timer.scope("Own Surface Shadows");
  }
};

class ContractTest : public GlTest {};

TEST_F(ContractTest, MethodWithoutSharedShadowMapDoesNotPayForIt) {
  Scene scene = loadScene("spheres");
  RunOptions options = RunOptions::singleFrame(32, 24);
  Runner runner(scene, limits(), options);
  OwnShadowsMethod own;
  ParamValues params = ParamValues::parse("own-shadows", allParams(own, 4096), {});
  MethodRun r = runner.run(own, params);
  ASSERT_EQ(r.status, RunStatus::Success) << r.reason;
  EXPECT_EQ(std::find(r.passes.begin(), r.passes.end(), "Shadow Map"), r.passes.end());
  EXPECT_NE(std::find(r.passes.begin(), r.passes.end(), "Own Pass"), r.passes.end());
  EXPECT_EQ(r.approximations, std::vector<std::string>{"no visibility at all"});
  EXPECT_EQ(r.surfacePasses, std::vector<std::string>{"Own Surface Shadows"}) << "the run knows its surface passes";
  EXPECT_GE(r.setupMs, 0.0);
  // The shared shadow map is empty (V = 1), so Direct Lighting is unshadowed for such a method.
  auto raymarch = createMethod("raymarch");
  MethodRun shadowed = runner.run(*raymarch, resolveSpec("raymarch:steps=4", limits()).params);
  ASSERT_EQ(shadowed.status, RunStatus::Success);
  EXPECT_NE(std::find(shadowed.passes.begin(), shadowed.passes.end(), "Shadow Map"), shadowed.passes.end());
}

// Scattering time has one definition: the method's passes, without the shared ones and without the
// passes it declares as surface shading.
TEST(ContractTest2, ScatteringTimeLeavesOutSharedAndSurfacePasses) {
  MethodRun r;
  r.passStats[kShadowMapPass].medianMs = 1.0;
  r.passStats[kCompositePass].medianMs = 2.0;
  r.passStats["Own Pass"].medianMs = 4.0;
  r.passStats[kVplAccumulationPass].medianMs = 8.0;  // the per-VPL wrapper's work is the method's
  r.passStats["Own Surface Shadows"].medianMs = 16.0;
  EXPECT_DOUBLE_EQ(r.scatterMs(), 28.0);
  r.surfacePasses = {"Own Surface Shadows"};
  EXPECT_DOUBLE_EQ(r.scatterMs(), 12.0);
  EXPECT_FALSE(r.isScatteringPass("Own Surface Shadows"));
  EXPECT_FALSE(r.isScatteringPass(kShadowMapPass));
  EXPECT_TRUE(r.isScatteringPass("Own Pass"));
}

TEST(ContractTest2, MissingCapabilityNamesTheEffect) {
  Capabilities c;
  c.pointLight = true;
  Effects e;
  e.light = LightType::Point;
  EXPECT_EQ(missingCapability(c, e), "");
  e.volumeData = true;
  EXPECT_NE(missingCapability(c, e).find("volume data"), std::string::npos);
  e.volumeData = false;
  e.semiTransparent = true;
  EXPECT_NE(missingCapability(c, e).find("semi-transparent"), std::string::npos);
  c.semiTransparentOccluders = true;
  e.coloredShadows = true;
  EXPECT_NE(missingCapability(c, e).find("colored shadows"), std::string::npos);
  e = Effects{};
  e.light = LightType::Rect;
  e.areaLight = true;
  EXPECT_NE(missingCapability(c, e).find("area lights"), std::string::npos);
}

}  // namespace
}  // namespace vs::testing
