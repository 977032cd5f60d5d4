#include "harness/bench/benchmark_kit.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "harness/cli/app.hpp"
#include "harness/gl/thread_pinning.hpp"

namespace vs {

namespace {
BenchmarkSession* gCurrent = nullptr;

std::string fixed(double v, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}
}  // namespace

std::string parseBenchmarkOptions(int& argc, char** argv, BenchmarkOptions& options) {
  int kept = 1;
  std::string error;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--seed") != 0) {
      argv[kept++] = argv[i];
      continue;
    }
    const char* value = i + 1 < argc ? argv[++i] : "";
    char* end = nullptr;
    errno = 0;
    unsigned long long seed = std::strtoull(value, &end, 10);
    if (*value == '\0' || *value == '-' || *end != '\0' || errno != 0 || seed > 0xffffffffull) {
      if (error.empty()) error = std::string("--seed wants an integer in [0, 4294967295], got '") + value + "'";
      continue;
    }
    options.seed = uint32_t(seed);
  }
  argc = kept;
  argv[argc] = nullptr;
  return error;
}

BenchmarkOptions takeBenchmarkOptions(int& argc, char** argv) {
  BenchmarkOptions options;
  const std::string program = argc > 0 ? argv[0] : "benchmark";
  std::string error = parseBenchmarkOptions(argc, argv, options);
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", program.c_str(), error.c_str());
    std::exit(2);
  }
  return options;
}

BenchmarkSession::BenchmarkSession(BenchmarkOptions options, DriftPolicy policy)
    : options_(options), context_(false) {
  // Passes are timed by glFinish and the wall clock: the driver's workers, one per CPU.
  pinning_ = describe(pinDriverThreads("on", true));
  gl::installDebugOutput(false);
  limits_ = gl::queryLimits();
  probe_ = std::make_unique<CalibrationProbe>();
  guard_ = std::make_unique<DriftGuard>([this] { return probe_->measure(); }, policy);
  gCurrent = this;
}

BenchmarkSession::~BenchmarkSession() {
  if (gCurrent == this) gCurrent = nullptr;
}

BenchmarkSession* BenchmarkSession::current() { return gCurrent; }

std::string BenchmarkSession::preamble(const std::string& bullet) const {
  const DriftPolicy& p = guard_->policy();
  return bullet + "provenance: " + provenanceLine(info()) + "\n" + bullet + "seed: " + std::to_string(seed()) +
         " (the jitter of every run)\n" + bullet + "threads: " + pinning_ + "\n" + bullet +
         "drift: a calibration workload (" + std::to_string(probe_->drawIterations()) + "/" +
         std::to_string(probe_->computeIterations()) +
         " iterations of a 256x256 fragment pass/compute dispatch) timed before and after every timed run; a run "
         "during which it moved more than " +
         fixed(p.thresholdPct, 0) + " % is repeated, at most " + std::to_string(p.maxRetries) + " times\n";
}

std::string BenchmarkSession::driftSummary(const std::string& bullet) const {
  const auto& h = guard_->history();
  if (h.empty()) return bullet + "drift: no timed run\n";
  auto [drawLo, drawHi] = std::minmax_element(h.begin(), h.end(), [](auto& a, auto& b) { return a.drawMs < b.drawMs; });
  auto [compLo, compHi] =
      std::minmax_element(h.begin(), h.end(), [](auto& a, auto& b) { return a.computeMs < b.computeMs; });
  return bullet + "drift: calibration " + fixed(h.front().drawMs, 2) + "/" + fixed(h.front().computeMs, 2) +
         " ms (fragment/compute) at the start, " + fixed(drawLo->drawMs, 2) + "–" + fixed(drawHi->drawMs, 2) + " / " +
         fixed(compLo->computeMs, 2) + "–" + fixed(compHi->computeMs, 2) + " ms over " + std::to_string(h.size()) +
         " samples; " + std::to_string(guard_->retries()) + " run(s) repeated because the machine's speed moved, " +
         std::to_string(disturbedKept_) + " kept while still disturbed\n";
}

}  // namespace vs
