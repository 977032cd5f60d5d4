// What `vshadow run` and `vshadow shootout` are asked to do, as the command line gives it; the
// plan stage (plan.hpp) checks it.
#pragma once
#include <string>
#include <vector>

namespace vs {

struct RunRequest {
  std::string scene;
  std::vector<std::string> methods;  // specs; for shootout, optional method-name filter
  std::vector<std::string> rungs;    // shootout: which rungs of each ladder (all, first, middle, last, index); empty: all
  std::string size = "512x512";
  std::string out = "vshadow-results";
  std::string cacheDir;              // empty: defaultCacheDir()
  std::string referenceSpec;         // empty: the registered reference method; "exact": ground truth
  std::string timer = "auto";        // auto | gpu | wall
  std::string pinThreads = "auto";   // auto | on | off: the GL driver's threads, one per CPU (thread_pinning.hpp)
  int frames = 20, warmup = 3;
  // --min-time: > 0, a run measures as many of its frames as fill this many ms at its warm-up
  // frame's time (at least one; RunOptions::minTimeMs).
  double minTimeMs = 0;
  // Interleaved rounds (--rounds): every job runs once per round, in turn (A B C, A B C, ...), and
  // its timings are the medians over the rounds, with their spread.
  int rounds = 1;
  // Drift detection (harness/bench/drift.hpp): --drift-threshold (0: off) and --drift-retries.
  double driftThresholdPct = 15.0;
  int driftRetries = 2;
  long long seed = 1;
  bool noReference = false;
  bool exact = false;                // also measure against the exact-visibility ground truth
  int exactSteps = 2048;
  bool noImages = false;
  // Equal-quality columns (--equal-quality): the brute-force baselines' step counts and times at
  // each row's L_s error (bisection), and their error at each row's scattering time.
  bool equalQuality = false;
  bool strictGl = false;
  std::string commandLine;
};

// "WxH" into width and height; UsageError for anything else.
void parseSize(const std::string& text, int& w, int& h);

}  // namespace vs
