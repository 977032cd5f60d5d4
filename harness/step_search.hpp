#pragma once
// Searches over a brute-force estimator's step count, where one evaluation costs time in proportion
// to the count: the equal-quality matches of the shootout and the benchmarks.
#include <functional>

namespace vs {

// The smallest n in [1, most] with passes(n), passes taken as monotone (false up to some n, true
// from there). Doubling from `start` brackets the answer, bisection in log(n) then narrows it, so
// no count much above the answer is ever evaluated (a fixed bracket [1, most] evaluates `most`
// first, the dearest of all). Each n is evaluated at most once. 0: passes(most) is false.
int smallestPassingSteps(const std::function<bool(int)>& passes, int most, int start = 16);

}  // namespace vs
