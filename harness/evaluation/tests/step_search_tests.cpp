// Tests for harness/step_search.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "harness/evaluation/step_search.hpp"

namespace {

struct Probe {
  int answer;  // the first passing count (0: none passes)
  std::multiset<int> evaluated;
  bool operator()(int n) {
    evaluated.insert(n);
    return answer > 0 && n >= answer;
  }
};

}  // namespace

TEST(StepSearchTest, FindsTheFirstPassingCountAndEvaluatesEachOnce) {
  for (int most : {1, 7, 16, 100, 4096})
    for (int answer = 1; answer <= most; answer += std::max(1, answer / 3)) {
      Probe probe{answer, {}};
      int found = vs::smallestPassingSteps([&](int n) { return probe(n); }, most);
      EXPECT_EQ(found, answer) << "most " << most;
      for (int n : probe.evaluated) {
        EXPECT_EQ(probe.evaluated.count(n), 1u) << n << " evaluated twice";
        EXPECT_GE(n, 1);
        EXPECT_LE(n, most);
      }
    }
}

TEST(StepSearchTest, NeverEvaluatesMuchAboveTheAnswer) {
  for (int answer : {1, 2, 5, 16, 17, 100, 700, 3000}) {
    Probe probe{answer, {}};
    ASSERT_EQ(vs::smallestPassingSteps([&](int n) { return probe(n); }, 4096), answer);
    EXPECT_LE(*probe.evaluated.rbegin(), std::max(16, 2 * answer)) << "answer " << answer;
    // Doubling up to the answer, then bisection of one octave to the integer.
    size_t octaves = size_t(std::ceil(std::log2(double(std::max(16, answer)))));
    EXPECT_LE(probe.evaluated.size(), 2 * octaves + 1) << "answer " << answer;
  }
}

TEST(StepSearchTest, NothingPassingGivesZeroAfterTryingTheMost) {
  Probe probe{0, {}};
  EXPECT_EQ(vs::smallestPassingSteps([&](int n) { return probe(n); }, 4096), 0);
  EXPECT_EQ(*probe.evaluated.rbegin(), 4096);
  EXPECT_EQ(vs::smallestPassingSteps([](int) { return true; }, 0), 0);
}

TEST(StepSearchTest, ToleranceStopsWithinItsFractionAboveTheAnswerAndSavesEvaluations) {
  for (int answer : {1, 5, 40, 64, 100, 700, 1160, 3000}) {
    Probe exact{answer, {}}, loose{answer, {}};
    ASSERT_EQ(vs::smallestPassingSteps([&](int n) { return exact(n); }, 4096), answer);
    int found = vs::smallestPassingSteps([&](int n) { return loose(n); }, 4096, 16, 1.0 / 64);
    EXPECT_GE(found, answer);  // it passes
    EXPECT_LE(found - answer, std::max(1, found / 64) - 1) << "answer " << answer;
    if (answer <= 64) {
      EXPECT_EQ(found, answer);  // integer precision below 1/tolerance
    }
    EXPECT_LE(loose.evaluated.size(), exact.evaluated.size()) << "answer " << answer;
    if (answer >= 700) {
      EXPECT_LT(loose.evaluated.size(), exact.evaluated.size()) << "answer " << answer;
    }
  }
}
