// Pinning the GL driver's worker threads, one per CPU in turn, for wall-clock pass timing.
//
// When the "GPU" is a CPU rasterizer (llvmpipe), each glFinish-bracketed pass starts from idle
// worker threads that the OS scheduler wakes wherever it likes: short passes read up to twice
// their time in some frames while long ones barely move, so leaving the threads free penalised
// the short passes of the fast methods against the baselines (figures: README "Timing",
// scripts/pinning-ab). Every result records what was pinned.
#pragma once
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace vs {

struct PinnedThread {
  int tid = 0;
  std::string name;
  int cpu = -1;
};

struct ThreadPinning {
  std::string mode;  // auto | on | off
  bool applied = false;
  std::string reason;
  std::vector<PinnedThread> threads;
};

// The threads of this process other than the calling one, in creation (thread id) order; on
// Linux through /proc/self/task, elsewhere none.
std::vector<PinnedThread> otherThreads();

// mode "on": pins every thread but the caller (call it once the GL context exists: llvmpipe starts
// its workers with it; and before starting threads of one's own), the k-th to the k-th CPU of
// the caller's affinity set modulo its size, so that any run of consecutive workers lands on
// distinct CPUs. "auto": the same when `wallClockTiming` (the driver's timestamps could not be
// trusted, so passes are timed by glFinish and the wall clock), else nothing. "off": nothing.
// The caller's own affinity is left as it is, so threads it starts later are free.
ThreadPinning pinDriverThreads(const std::string& mode, bool wallClockTiming);

nlohmann::json toJson(const ThreadPinning& pinning);
// "pinned one per CPU: llvmpipe-0 -> 0, llvmpipe-1 -> 1, ..." or why not.
std::string describe(const ThreadPinning& pinning);

}  // namespace vs
