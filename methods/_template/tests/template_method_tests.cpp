// TEMPLATE: the method's own tests. The conformance suite (tests/conformance_tests.cpp) and the
// hard cases (tests/stability_tests.cpp) already run every registered method; test here what only
// this method promises, against an independent oracle where one exists.
#include <gtest/gtest.h>

#include "gl_test.hpp"
#include "harness/evaluation/metrics.hpp"

namespace vs::testing {
namespace {

class TemplateMethodTest : public GlTest {};

// More steps converge on the reference: 128 steps are closer to it than 8.
TEST_F(TemplateMethodTest, MoreStepsConvergeOnTheReference) {
  Scene scene = sceneFromJson(R"({
    "camera": {"position": [0, 1.5, 6], "target": [0, 1, 0], "fov_y_deg": 55, "near": 0.05, "far": 30},
    "light": {"type": "point", "position": [0.5, 3, -1], "intensity": 40},
    "medium": {"sigma_s": 0.08, "sigma_a": 0.02, "phase": "isotropic"},
    "geometry": [{"generator": "plane", "params": {"center": [0, 0, 0], "size": [12, 12]}},
                 {"generator": "box", "params": {"center": [0, 1, 0], "size": [1, 1, 1]}}]})");
  MethodRun ref = renderScene(scene, "raymarch:steps=1024:sampling=equiangular", 48, 36);
  MethodRun coarse = renderScene(scene, "template:steps=8", 48, 36);
  MethodRun fine = renderScene(scene, "template:steps=128", 48, 36);
  ASSERT_EQ(ref.status, RunStatus::Success) << ref.reason;
  ASSERT_EQ(coarse.status, RunStatus::Success) << coarse.reason;
  ASSERT_EQ(fine.status, RunStatus::Success) << fine.reason;
  double coarseError = compareImages(coarse.inscatter, ref.inscatter).relmse;
  double fineError = compareImages(fine.inscatter, ref.inscatter).relmse;
  EXPECT_LT(fineError, coarseError);
  EXPECT_LT(fineError, 0.01);
}

}  // namespace
}  // namespace vs::testing
