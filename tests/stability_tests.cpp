// Every registered method on every hard case (README "Stability"): a method is covered the day it is
// registered; point-light methods run the area-light cases through the per-VPL wrapper (vpls=16). Checks: finite, non-negative pixels; L_s never above the same method's unshadowed
// L_s; relMSE against the reference within the method's declared bound (regular cases);
// identical images from two runs; no GL debug error (the GlTest fixture).
#include <cmath>
#include <cstdlib>

#include "gl_test.hpp"
#include "bad_inputs.hpp"
#include "hard_cases.hpp"
#include "stability_report.hpp"
#include "stress.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/io/results.hpp"

namespace vs::testing {
namespace {


std::vector<std::string> methodNames() {
  std::vector<std::string> names;
  for (const auto& m : registeredMethods()) names.push_back(m.name);
  return names;
}
std::vector<std::string> caseNames() {
  std::vector<std::string> names;
  for (const auto& c : hardCases()) names.push_back(c.name);
  return names;
}

class StabilityTest : public GlTest, public ::testing::WithParamInterface<std::tuple<std::string, std::string>> {};

void expectFiniteNonNegative(const Image& img, const char* what) {
  size_t bad = 0;
  for (float v : img.rgb) bad += !(std::isfinite(v) && v >= 0.0f);
  EXPECT_EQ(bad, 0u) << what << " has non-finite or negative values";
}

TEST_P(StabilityTest, StaysFiniteBoundedAndDeterministic) {
  const auto& [caseName, methodName] = GetParam();
  const HardCase& hard = hardCase(caseName);
  Scene scene = sceneFromJson(hard.json);
  auto method = createMethod(methodName);
  std::string spec = methodName + ":sm=512";
  std::string unsupported = unsupportedReason(scene, *method, resolveSpec(spec, glLimits()).params);
  // A point-light method meets the area-light cases behind the per-VPL wrapper.
  if (!unsupported.empty() && deriveEffects(scene).areaLight) {
    std::string wrapped = spec + ":vpls=" + std::to_string(kHardCaseVpls);
    if (unsupportedReason(scene, *method, resolveSpec(wrapped, glLimits()).params).empty()) {
      spec = wrapped;
      unsupported.clear();
    }
  }
  if (!unsupported.empty()) GTEST_SKIP() << unsupported;

  RunOptions options = RunOptions::singleFrame(hard.width, hard.height);
  MethodRun first = renderScene(scene, spec, options);
  ASSERT_EQ(first.status, RunStatus::Success) << first.reason;
  expectFiniteNonNegative(first.inscatter, "L_s");
  expectFiniteNonNegative(first.final, "L");

  MethodRun second = renderScene(scene, spec, options);
  ASSERT_EQ(second.status, RunStatus::Success) << second.reason;
  EXPECT_EQ(first.inscatter.rgb, second.inscatter.rgb) << "two runs differ";
  EXPECT_EQ(first.final.rgb, second.final.rgb) << "two runs differ";

  options.shadowCasters = false;
  MethodRun unshadowed = renderScene(scene, spec, options);
  ASSERT_EQ(unshadowed.status, RunStatus::Success) << unshadowed.reason;
  size_t above = 0;
  for (size_t i = 0; i < first.inscatter.rgb.size(); ++i) {
    float lit = first.inscatter.rgb[i], open = unshadowed.inscatter.rgb[i];
    above += lit > open * 1.001f + 1e-6f;
  }
  EXPECT_EQ(above, 0u) << "L_s above the unshadowed L_s";

  if (hard.singular) return;  // the integral diverges at the eye: no reference to be close to
  // Alpha-tested occluders are a declared approximation of the scene, not of the method: the
  // bound is for the scenes a method models.
  if (!alphaTestApproximation(scene, alphaTestThreshold(*method, deriveEffects(scene), resolveSpec(spec, glLimits()).params))
           .empty())
    return;
  options.shadowCasters = true;
  const char* cache = std::getenv("VSHADOW_CACHE");
  Reference ref = obtainReference(scene, glLimits(), options, 512, cache ? cache : makeTempDir("ref"));
  ErrorMetrics err = compareImages(first.inscatter, ref.inscatter);
  EXPECT_LE(err.relmse, method->declaredRelMseBound())
      << "L_s relMSE " << err.relmse << ", rmse " << err.rmse << " against " << ref.method << ":" << ref.params;
  RecordProperty("ls_relmse", std::to_string(err.relmse));
}

// Hard cases in time: every frame of the sequence is finite, non-negative, and the same as the
// scene at its time rendered still (so within the still hard case's bounds), for every method.
class TemporalStabilityTest : public GlTest,
                              public ::testing::WithParamInterface<std::tuple<std::string, std::string>> {};

TEST_P(TemporalStabilityTest, EveryFrameIsFiniteAndItsStillFrame) {
  const auto& [caseName, methodName] = GetParam();
  Scene scene = sceneFromJson(temporalHardCase(caseName).json);
  ASSERT_TRUE(scene.animation.moves());
  auto method = createMethod(methodName);
  std::string spec = methodName + ":sm=256";
  std::string unsupported = unsupportedReason(scene, *method, resolveSpec(spec, glLimits()).params);
  if (!unsupported.empty()) GTEST_SKIP() << unsupported;
  RunOptions options;
  options.width = 32;
  options.height = 24;
  options.warmup = 0;
  options.frames = scene.animation.frameCount();
  options.sequence = true;  // every frame's L_s
  MethodRun run = renderScene(scene, spec, options);
  ASSERT_EQ(run.status, RunStatus::Success) << run.reason;
  ASSERT_EQ(run.sequence.size(), size_t(options.frames));
  options.frames = 1;
  options.sequence = false;
  for (const MethodRun::SequenceFrame& f : run.sequence) {
    expectFiniteNonNegative(f.inscatter, "L_s");
    // The still frame at the same frame index (the same jitter).
    options.warmup = int(f.index);
    MethodRun still = renderScene(sceneAt(scene, f.timeS), spec, options);
    ASSERT_EQ(still.status, RunStatus::Success) << still.reason;
    ErrorMetrics e = compareImages(f.inscatter, still.inscatter);
    EXPECT_LE(e.relmse, 1e-6) << "frame " << f.index << " (t = " << f.timeS << " s) differs from its still frame";
  }
}

std::vector<std::string> temporalCaseNames() {
  std::vector<std::string> names;
  for (const auto& c : temporalHardCases()) names.push_back(c.name);
  return names;
}

// A seeded slice of the randomized stress (vshadow_stress runs >= 10,000 per method).
class StressSliceTest : public GlTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(StressSliceTest, RandomConfigurationsStayFinite) {
  StressOptions options;
  options.seed = 20261121;
  options.configs = 24;
  StressSummary s = runStress(GetParam(), options, glLimits());
  std::printf("%s: %d tried, %d unsupported, worst L_s relMSE %.3g (config %u)\n", GetParam().c_str(), s.tried,
              s.unsupported, s.worstRelmse, s.worstIndex);
  EXPECT_EQ(s.failures, 0) << s.firstFailure;
  EXPECT_EQ(s.nonFinite, 0);
  EXPECT_EQ(s.negative, 0);
  EXPECT_GT(s.tried, 0);
}

// On area-light configurations the stress runs point-light methods behind the per-VPL wrapper, as
// the shootout does, instead of counting them unsupported; a method with area lights of its own
// runs them natively.
TEST_F(StressSliceTest, PointLightMethodsMeetAreaLightsThroughTheWrapper) {
  StressOptions options;
  options.seed = 3;
  options.configs = 30;
  options.width = 16;
  options.height = 12;
  int areaLights = 0;
  for (int i = 0; i < options.configs; ++i) areaLights += isAreaLight(randomStressScene(options.seed, uint32_t(i)).light.type);
  ASSERT_GT(areaLights, 0) << "no area light among the configurations: pick another seed";
  std::vector<StressSummary> s = runStress(std::vector<std::string>{"vsv", "ivsv"}, options, glLimits());
  EXPECT_GT(s[0].throughVpls, 0);
  EXPECT_LE(s[0].throughVpls, areaLights);
  EXPECT_EQ(s[0].failures, 0) << s[0].firstFailure;
  EXPECT_EQ(s[1].throughVpls, 0);
  EXPECT_EQ(s[1].failures, 0) << s[1].firstFailure;
}

class StressShardTest : public GlTest {};

TEST_F(StressShardTest, ShardsMergeToTheWholeRun) {
  // A cluster runs the stress in shards (vshadow_stress --shard K/N --partial, then --merge): their
  // merged summaries must be the unsharded run's.
  StressOptions options;
  options.seed = 7;
  options.configs = 9;
  options.width = 16;
  options.height = 12;
  std::vector<std::string> methods = {"raymarch", "vsv", "dsm"};
  double wholeReference = 0, partsReference = 0, partsSeconds = 0;
  std::vector<StressSummary> whole = runStress(methods, options, glLimits(), {}, &wholeReference);
  std::vector<StressSummary> merged;
  options.shards = 3;
  for (options.shard = 0; options.shard < 3; ++options.shard) {
    std::vector<StressSummary> part = runStress(methods, options, glLimits(), {}, &partsReference);
    for (const StressSummary& s : part) partsSeconds += s.seconds;
    if (merged.empty()) merged = part;
    else for (size_t m = 0; m < part.size(); ++m) merged[m].merge(part[m]);
  }
  for (size_t m = 0; m < methods.size(); ++m) {
    EXPECT_EQ(merged[m].tried, whole[m].tried) << methods[m];
    EXPECT_EQ(merged[m].unsupported, whole[m].unsupported) << methods[m];
    EXPECT_EQ(merged[m].throughVpls, whole[m].throughVpls) << methods[m];
    EXPECT_EQ(merged[m].tried + merged[m].unsupported, 9) << methods[m];
    EXPECT_EQ(merged[m].failures, whole[m].failures) << methods[m];
    EXPECT_EQ(merged[m].worstIndex, whole[m].worstIndex) << methods[m];
    EXPECT_DOUBLE_EQ(merged[m].worstRelmse, whole[m].worstRelmse) << methods[m];
    EXPECT_GT(merged[m].seconds, 0.0) << methods[m];  // the report's time column
  }
  // Merging adds the shards' times.
  double mergedSeconds = 0;
  for (const StressSummary& s : merged) mergedSeconds += s.seconds;
  EXPECT_NEAR(mergedSeconds, partsSeconds, 1e-9);
  EXPECT_GT(wholeReference, 0.0);
  EXPECT_GT(partsReference, 0.0);
}

TEST_F(StressShardTest, ReportRowsOfTheShardsMergeToTheWholeRunsRows) {
  // Each shard computes every shards-th hard-case and bad-input row of the report and writes them to
  // its partial file; the rows merged from the files must be those of one unsharded run.
  std::vector<std::string> methods = {"raymarch", "vsv"};
  std::vector<size_t> cases = {1, 2, 5}, inputs = {0, 3, 8};  // 5: singular
  ReportRows whole = computeReportRows(methods, 0, 1, cases, inputs);
  ReportRows merged;
  int calls = 0;
  for (int shard = 0; shard < 2; ++shard) {
    ReportRows part = computeReportRows(methods, shard, 2, cases, inputs, [&](int, int) { ++calls; });
    std::string file = reportRowsJson(part).dump();
    merged.merge(reportRowsFromJson(nlohmann::json::parse(file), methods.size()));
    if (shard == 0) {
      EXPECT_THROW(merged.merge(part), std::runtime_error);  // a shard given twice
    }
  }
  EXPECT_EQ(calls, 6);  // progress once per row
  ASSERT_EQ(merged.hardCases.size(), cases.size());
  ASSERT_EQ(merged.badInputs.size(), inputs.size());
  for (size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(merged.hardCases[i].index, cases[i]);
    EXPECT_EQ(merged.hardCases[i].cells, whole.hardCases[i].cells) << hardCases()[cases[i]].name;
    ASSERT_EQ(merged.hardCases[i].cells.size(), methods.size());
    for (const std::string& cell : merged.hardCases[i].cells) EXPECT_EQ(cell.find("Failure"), std::string::npos) << cell;
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    EXPECT_EQ(merged.badInputs[i].index, inputs[i]);
    EXPECT_EQ(merged.badInputs[i].exitCode, 2) << badInputs()[inputs[i]].name;
    EXPECT_EQ(merged.badInputs[i].message, whole.badInputs[i].message);
    EXPECT_NE(merged.badInputs[i].message.find(badInputs()[inputs[i]].expectInError), std::string::npos)
        << merged.badInputs[i].message;
  }
  EXPECT_EQ(reportRowsMarkdown(methods, merged), reportRowsMarkdown(methods, whole));
  // A merge that lacks rows says which; a file from another build's cases or methods is refused.
  try {
    merged.checkComplete();
    ADD_FAILURE() << "three of the hard cases passed for all of them";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + hardCases()[0].name + "'"), std::string::npos) << e.what();
  }
  nlohmann::json file = reportRowsJson(merged);
  EXPECT_THROW(reportRowsFromJson(file, methods.size() + 1), std::runtime_error);
  file["hard_cases"][0]["case"] = "renamed";
  EXPECT_THROW(reportRowsFromJson(file, methods.size()), std::runtime_error);
}

TEST_F(StressShardTest, PrintedConfigurationRendersAsTheStressedOne) {
  // vshadow_stress --print-config N: the report names configurations; their scene files, loaded
  // as a user would (vshadow run --scene), must render what the stress rendered.
  std::string dir = makeTempDir("stress-config");
  for (uint32_t index : {3u, 422u}) {
    std::string path = dir + "/config" + std::to_string(index) + ".json";
    writeFileAtomic(path, randomStressSceneJson(1, index));
    Scene loaded = loadScene(path), stressed = randomStressScene(1, index);
    EXPECT_EQ(loaded.contentHash, stressed.contentHash) << index;
    MethodRun a = renderScene(loaded, "raymarch:steps=16", 16, 12), b = renderScene(stressed, "raymarch:steps=16", 16, 12);
    ASSERT_EQ(a.status, RunStatus::Success) << a.reason;
    ASSERT_EQ(b.status, RunStatus::Success) << b.reason;
    EXPECT_EQ(a.inscatter.rgb, b.inscatter.rgb) << index;
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, StressSliceTest, ::testing::ValuesIn(methodNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// "case__method", with every character a test name cannot hold as '_'.
std::string caseAndMethodName(const ::testing::TestParamInfo<std::tuple<std::string, std::string>>& info) {
  std::string name = std::get<0>(info.param) + "__" + std::get<1>(info.param);
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(TemporalHardCases, TemporalStabilityTest,
                         ::testing::Combine(::testing::ValuesIn(temporalCaseNames()), ::testing::ValuesIn(methodNames())),
                         caseAndMethodName);

INSTANTIATE_TEST_SUITE_P(HardCases, StabilityTest,
                         ::testing::Combine(::testing::ValuesIn(caseNames()), ::testing::ValuesIn(methodNames())),
                         caseAndMethodName);

}  // namespace
}  // namespace vs::testing
