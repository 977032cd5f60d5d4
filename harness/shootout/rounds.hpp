// Interleaved rounds (--rounds): every job runs once per round, in turn (A B C, A B C); a row shows
// the median of its rounds' figures and their range. Takes each round's MethodRun, gives the
// combined TimingStats.
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "harness/gl/timer.hpp"
#include "harness/pipeline/runner.hpp"

namespace vs::shootout {

// A job's timings per round: its frame, pass and scattering figures.
struct RoundTimings {
  std::vector<TimingStats> frame;
  std::map<std::string, std::vector<TimingStats>> passes;
  std::vector<double> scatter;

  void add(const MethodRun& r);
  int count() const { return int(frame.size()); }
};

// Median of the rounds' medians (and of their MdAPE and percentiles), min and max over every frame,
// all frames. No rounds: zeros.
TimingStats combineRounds(const std::vector<TimingStats>& rounds);

// Range of the rounds' medians ({0, 0} without any).
std::pair<double, double> roundRange(const std::vector<TimingStats>& rounds);

}  // namespace vs::shootout
