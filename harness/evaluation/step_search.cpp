#include "harness/evaluation/step_search.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace vs {

int smallestPassingSteps(const std::function<bool(int)>& passes, int most, int start, double tolerance) {
  if (most < 1) return 0;
  std::map<int, bool> seen;
  auto test = [&](int n) {
    auto it = seen.find(n);
    return it != seen.end() ? it->second : (seen[n] = passes(n));
  };
  // Bracket: lo fails (0 stands for "nothing below 1"), hi passes.
  int lo = 0, hi = std::clamp(start, 1, most);
  while (!test(hi)) {
    if (hi == most) return 0;
    lo = hi;
    hi = int(std::min<long long>(2LL * hi, most));
  }
  if (lo == 0 && hi > 1) {
    if (test(1)) return 1;
    lo = 1;
  }
  while (hi - lo > std::max(1, int(tolerance * hi))) {
    int mid = std::clamp(int(std::lround(std::sqrt(double(lo) * double(hi)))), lo + 1, hi - 1);
    if (test(mid)) hi = mid;
    else lo = mid;
  }
  return hi;
}

}  // namespace vs
