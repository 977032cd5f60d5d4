// Pinning the GL driver's worker threads, one per CPU in turn, for wall-clock pass timing.
//
// When the "GPU" is a CPU rasterizer (llvmpipe), each glFinish-bracketed pass starts from idle
// worker threads that the OS scheduler wakes wherever it likes. Measured on 2 cores: a 5.5 ms
// fullscreen pass read 5.5 ms in some frames and 10.7 ms in others (both workers woken on one
// CPU), a frame-to-frame MdAPE of 26 %; with the workers pinned one per CPU, 0.7 %. Long passes
// (a 40 ms ray march) were the same either way, so leaving the threads free penalised the short
// passes of the fast methods against the baselines. Every result records what was pinned.
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

// mode "on": pins every thread but the caller (call it right after the GL context exists and has
// run a draw and a dispatch, before starting threads of one's own), the k-th to the k-th CPU of
// the caller's affinity set modulo its size, so that any run of consecutive workers lands on
// distinct CPUs. "auto": the same when `wallClockTiming` (the driver's timestamps could not be
// trusted, so passes are timed by glFinish and the wall clock), else nothing. "off": nothing.
// The caller's own affinity is left as it is, so threads it starts later are free.
ThreadPinning pinDriverThreads(const std::string& mode, bool wallClockTiming);

nlohmann::json toJson(const ThreadPinning& pinning);
// "pinned one per CPU: llvmpipe-0 -> 0, llvmpipe-1 -> 1, ..." or why not.
std::string describe(const ThreadPinning& pinning);

}  // namespace vs
