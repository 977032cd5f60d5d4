#pragma once
// Searches over a brute-force estimator's step count, where one evaluation costs time in proportion
// to the count: the equal-quality matches of the shootout and the benchmarks.
#include <functional>

namespace vs {

// The smallest n in [1, most] with passes(n), passes taken as monotone (false up to some n, true
// from there). Doubling from `start` brackets the answer, bisection in log(n) then narrows it, so
// no count much above the answer is ever evaluated (a fixed bracket [1, most] evaluates `most`
// first, the dearest of all). Each n is evaluated at most once. 0: passes(most) is false.
// tolerance > 0: the bisection stops once hi - lo <= tolerance * hi and returns hi, which passes
// and exceeds the answer by at most that fraction (answers near 1,000 at 1/64: 6 evaluations into
// their octave instead of 10).
int smallestPassingSteps(const std::function<bool(int)>& passes, int most, int start = 16, double tolerance = 0.0);

// The tolerance of the equal-quality matches (shootout, benchmarks): a matched step count exceeds
// the smallest one reaching the error by at most 1/64 (none below 64 steps); finer would bisect
// timing noise.
constexpr double kStepTolerance = 1.0 / 64;

}  // namespace vs
