// Tests for the plan stage: the rungs --rungs picks, what planBeforeContext checks and plans, and the
// jobs planJobs lists (with GL limits given: no context needed).
#include <gtest/gtest.h>

#include "harness/pipeline/runner.hpp"
#include "harness/shootout/plan.hpp"
#include "methods/registry.hpp"

namespace vs::shootout {
namespace {

using Rungs = std::vector<size_t>;

RunRequest request(const std::string& scene) {
  RunRequest r;
  r.scene = scene;
  r.size = "32x24";
  r.frames = 2;
  r.warmup = 1;
  return r;
}

gl::Limits roomyLimits() {
  gl::Limits l;
  l.maxTextureSize = l.maxCubeMapSize = l.maxRenderbufferSize = l.maxViewportW = l.maxViewportH = 16384;
  l.maxTexture3DSize = 2048;
  l.maxDrawBuffers = l.maxColorAttachments = 8;
  l.maxFragmentTextureUnits = l.maxComputeTextureUnits = 32;
  return l;
}

RunPlan planned(const RunRequest& r, bool shootout, const gl::Limits& limits = roomyLimits()) {
  RunPlan plan = planBeforeContext(r, shootout, registeredMethods());
  planJobs(plan, r, shootout, registeredMethods(), limits);
  return plan;
}

TEST(PickRungs, NoWordsPickEveryRung) { EXPECT_EQ(pickRungs({}, 4), (Rungs{0, 1, 2, 3})); }

TEST(PickRungs, NamedRungs) {
  EXPECT_EQ(pickRungs({"first"}, 6), Rungs{0});
  EXPECT_EQ(pickRungs({"middle"}, 6), Rungs{3});
  EXPECT_EQ(pickRungs({"middle"}, 5), Rungs{2});
  EXPECT_EQ(pickRungs({"last"}, 6), Rungs{5});
  EXPECT_EQ(pickRungs({"all"}, 3), (Rungs{0, 1, 2}));
  EXPECT_EQ(pickRungs({"4"}, 6), Rungs{4});
}

TEST(PickRungs, InLadderOrderEachOnce) {
  EXPECT_EQ(pickRungs({"last", "2", "first", "last"}, 6), (Rungs{0, 2, 5}));
  EXPECT_EQ(pickRungs({"1", "all"}, 3), (Rungs{0, 1, 2}));
  EXPECT_EQ(pickRungs({"first", "last"}, 1), Rungs{0});
}

TEST(PickRungs, IndexPastTheEndPicksNothing) {
  EXPECT_EQ(pickRungs({"6"}, 6), Rungs{});
  EXPECT_EQ(pickRungs({"first", "middle", "last"}, 0), Rungs{});
}

TEST(PickRungs, OtherWordsAreUsageErrors) {
  for (std::string bad : {"", "mid", "First", "-1", "1.5", "123456", "2,3", "all "})
    EXPECT_THROW(pickRungs({"first", bad}, 6), UsageError) << "'" << bad << "'";
}

TEST(PlanBeforeContext, StillScene) {
  RunPlan plan = planBeforeContext(request("spheres"), true, registeredMethods());
  EXPECT_EQ(plan.width, 32);
  EXPECT_EQ(plan.height, 24);
  EXPECT_EQ(plan.scene.name, "spheres");
  EXPECT_FALSE(plan.movedScene.has_value());
  EXPECT_EQ(&plan.stillScene(), &plan.scene);
  EXPECT_EQ(plan.comparedFrame, 2u);  // warm-up + frames - 1
  EXPECT_TRUE(plan.effects.scattering);
  EXPECT_TRUE(plan.haveReference);
  EXPECT_FALSE(plan.haveExact);
  EXPECT_FALSE(plan.exactReference);
  EXPECT_TRUE(plan.jobs.empty());  // planJobs lists them
}

TEST(PlanBeforeContext, MovingSceneIsComparedAtItsLastFrame) {
  RunRequest r = request("roomspin");
  r.frames = 3;
  r.warmup = 2;
  RunPlan plan = planBeforeContext(r, true, registeredMethods());
  EXPECT_EQ(plan.comparedFrame, 4u);
  ASSERT_TRUE(plan.movedScene.has_value());
  EXPECT_EQ(&plan.stillScene(), &*plan.movedScene);
}

TEST(PlanBeforeContext, ReferenceAndGroundTruth) {
  RunRequest r = request("spheres");
  r.referenceSpec = "exact";
  RunPlan plan = planBeforeContext(r, true, registeredMethods());
  EXPECT_TRUE(plan.exactReference);
  EXPECT_TRUE(plan.haveExact);
  EXPECT_TRUE(plan.haveReference);

  r = request("spheres");
  r.noReference = true;
  r.exact = true;
  plan = planBeforeContext(r, true, registeredMethods());
  EXPECT_FALSE(plan.haveReference);
  EXPECT_TRUE(plan.haveExact);
  EXPECT_FALSE(plan.exactReference);
}

TEST(PlanBeforeContext, EqualQualityMatchesAgainstTheGroundTruth) {
  RunRequest r = request("spheres");
  r.equalQuality = true;
  RunPlan plan = planBeforeContext(r, true, registeredMethods());
  EXPECT_TRUE(plan.equalQualityExact);
  EXPECT_TRUE(plan.equalQualityNote.empty());
  EXPECT_TRUE(plan.haveExact);
  // Without a reference there is no equal quality, so no ground truth either.
  r.noReference = true;
  plan = planBeforeContext(r, true, registeredMethods());
  EXPECT_FALSE(plan.equalQualityExact);
  EXPECT_FALSE(plan.haveExact);
}

TEST(PlanBeforeContext, BadInputIsAUsageError) {
  auto plan = [](const RunRequest& r, bool shootout) { planBeforeContext(r, shootout, registeredMethods()); };
  auto with = [](auto change) {
    RunRequest r = request("spheres");
    change(r);
    return r;
  };
  EXPECT_THROW(plan(with([](RunRequest& r) { r.size = "32by24"; }), true), UsageError);
  EXPECT_THROW(plan(with([](RunRequest& r) { r.size = "0x24"; }), true), UsageError);
  EXPECT_THROW(plan(with([](RunRequest& r) { r.methods = {"nosuch"}; }), true), UsageError);
  EXPECT_THROW(plan(with([](RunRequest& r) { r.methods = {"nosuch:steps=8"}; }), false), UsageError);
  // shootout filters by method name, not by spec
  EXPECT_THROW(plan(with([](RunRequest& r) { r.methods = {"raymarch:steps=8"}; }), true), UsageError);
  EXPECT_NO_THROW(plan(with([](RunRequest& r) { r.methods = {"raymarch:steps=8"}; }), false));
  EXPECT_THROW(plan(with([](RunRequest& r) { r.rungs = {"firsts"}; }), true), UsageError);
  EXPECT_THROW(plan(with([](RunRequest& r) { r.referenceSpec = "nosuch:steps=8"; }), true), UsageError);
  EXPECT_THROW(plan(with([](RunRequest& r) {
                 r.minTimeMs = 5;
                 r.warmup = 0;
               }),
                    true),
               UsageError);
  EXPECT_ANY_THROW(plan(request("no-such-scene"), true));
}

TEST(PlanJobs, ShootoutRunsThePickedRungsOfEveryLadder) {
  RunRequest r = request("spheres");
  r.methods = {"raymarch"};
  r.rungs = {"last", "first"};
  RunPlan plan = planned(r, true);
  auto series = createMethod(registeredMethods(), "raymarch")->qualitySeries(plan.effects);
  ASSERT_EQ(series.size(), 2u);  // a point light: uniform and equiangular steps
  ASSERT_EQ(plan.jobs.size(), 4u);
  for (size_t k = 0; k < plan.jobs.size(); ++k) {
    const Job& job = plan.jobs[k];
    const auto& ladder = series[k / 2];
    const std::string& rung = k % 2 == 0 ? ladder.rungs.front() : ladder.rungs.back();
    ResolvedSpec expected = resolveSpec("raymarch:" + rung, roomyLimits(), registeredMethods());
    EXPECT_EQ(job.method, "raymarch");
    EXPECT_EQ(job.series, ladder.name);
    EXPECT_EQ(job.params.canonical(), expected.params.canonical()) << k;
    EXPECT_EQ(job.label, "raymarch " + expected.params.canonical());
  }
}

TEST(PlanJobs, EveryMethodWithoutAFilter) {
  RunRequest r = request("spheres");
  r.rungs = {"first"};
  RunPlan plan = planned(r, true);
  for (const MethodInfo& info : registeredMethods())
    EXPECT_TRUE(std::any_of(plan.jobs.begin(), plan.jobs.end(), [&](const Job& j) { return j.method == info.name; }))
        << info.name;
}

TEST(PlanJobs, AMethodThatCannotRenderTheSceneGetsOneJob) {
  RunRequest r = request("spheres");  // no volume data: dsm cannot run it
  r.methods = {"dsm"};
  RunPlan plan = planned(r, true);
  ASSERT_EQ(plan.jobs.size(), 1u);
  EXPECT_EQ(plan.jobs[0].method, "dsm");
}

TEST(PlanJobs, PointLightMethodsMeetAnAreaLightThroughVpls) {
  RunRequest r = request("arealight");
  r.methods = {"minmax", "raymarch"};
  r.rungs = {"first"};
  RunPlan plan = planned(r, true);
  ASSERT_FALSE(plan.jobs.empty());
  for (const Job& job : plan.jobs)
    EXPECT_EQ(job.params.getInt("vpls"), job.method == "minmax" ? kShootoutVpls : 0) << job.label;
}

TEST(PlanJobs, RunTakesTheSpecsAsGiven) {
  RunRequest r = request("spheres");
  r.methods = {"raymarch:steps=16", "raymarch:steps=8:sm=128"};
  RunPlan plan = planned(r, false);
  ASSERT_EQ(plan.jobs.size(), 2u);
  EXPECT_EQ(plan.jobs[0].params.getInt("steps"), 16);
  EXPECT_EQ(plan.jobs[1].params.getInt("steps"), 8);
  EXPECT_EQ(plan.jobs[1].params.getInt("sm"), 128);
  EXPECT_EQ(plan.jobs[0].series, "");
}

TEST(PlanJobs, SizeOverTheGlLimitsIsAUsageError) {
  gl::Limits small = roomyLimits();
  small.maxViewportW = 16;
  RunRequest r = request("spheres");
  RunPlan plan = planBeforeContext(r, true, registeredMethods());
  EXPECT_THROW(planJobs(plan, r, true, registeredMethods(), small), UsageError);
  r.methods = {"raymarch:steps=8:sm=99999"};
  plan = planBeforeContext(r, false, registeredMethods());
  EXPECT_THROW(planJobs(plan, r, false, registeredMethods(), roomyLimits()), UsageError);
}

}  // namespace
}  // namespace vs::shootout
