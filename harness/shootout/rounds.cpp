#include "harness/shootout/rounds.hpp"

#include <algorithm>

namespace vs::shootout {

void RoundTimings::add(const MethodRun& r) {
  frame.push_back(r.frame);
  for (const auto& [pass, stats] : r.passStats) passes[pass].push_back(stats);
  scatter.push_back(r.scatterMs());
}

TimingStats combineRounds(const std::vector<TimingStats>& rounds) {
  TimingStats out;
  if (rounds.empty()) return out;
  std::vector<double> medians, mdapes, p95s, p99s;
  out.minMs = rounds.front().minMs;
  out.maxMs = rounds.front().maxMs;
  for (const TimingStats& r : rounds) {
    medians.push_back(r.medianMs);
    mdapes.push_back(r.mdapePct);
    p95s.push_back(r.p95Ms);
    p99s.push_back(r.p99Ms);
    out.minMs = std::min(out.minMs, r.minMs);
    out.maxMs = std::max(out.maxMs, r.maxMs);
    out.samples += r.samples;
  }
  out.medianMs = medianOf(medians);
  out.mdapePct = medianOf(mdapes);
  out.p95Ms = medianOf(p95s);
  out.p99Ms = medianOf(p99s);
  return out;
}

std::pair<double, double> roundRange(const std::vector<TimingStats>& rounds) {
  double lo = 0.0, hi = 0.0;
  for (size_t i = 0; i < rounds.size(); ++i) {
    lo = i == 0 ? rounds[i].medianMs : std::min(lo, rounds[i].medianMs);
    hi = i == 0 ? rounds[i].medianMs : std::max(hi, rounds[i].medianMs);
  }
  return {lo, hi};
}

}  // namespace vs::shootout
