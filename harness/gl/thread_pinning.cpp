#include "harness/gl/thread_pinning.hpp"

#include <algorithm>
#include <fstream>

#ifdef __linux__
#include <dirent.h>
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace vs {

std::vector<PinnedThread> otherThreads() {
  std::vector<PinnedThread> out;
#ifdef __linux__
  const int self = int(syscall(SYS_gettid));
  DIR* dir = opendir("/proc/self/task");
  if (!dir) return out;
  while (dirent* entry = readdir(dir)) {
    const std::string id = entry->d_name;
    if (id.empty() || !std::all_of(id.begin(), id.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    PinnedThread t;
    t.tid = std::stoi(id);
    if (t.tid == self) continue;
    std::ifstream comm("/proc/self/task/" + id + "/comm");
    std::getline(comm, t.name);
    out.push_back(t);
  }
  closedir(dir);
  std::sort(out.begin(), out.end(), [](const PinnedThread& a, const PinnedThread& b) { return a.tid < b.tid; });
#endif
  return out;
}

ThreadPinning pinDriverThreads(const std::string& mode, bool wallClockTiming) {
  ThreadPinning p;
  p.mode = mode;
  if (mode == "off") {
    p.reason = "off (--pin-threads off)";
    return p;
  }
  if (mode == "auto" && !wallClockTiming) {
    p.reason = "not needed: passes are timed by the driver's timestamps";
    return p;
  }
#ifdef __linux__
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) {
    p.reason = "the CPU affinity could not be read";
    return p;
  }
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &allowed)) cpus.push_back(c);
  if (cpus.size() < 2) {
    p.reason = "one CPU only: nothing to spread";
    return p;
  }
  std::vector<PinnedThread> threads = otherThreads();
  if (threads.empty()) {
    p.reason = "the driver runs no threads in this process";
    return p;
  }
  for (size_t k = 0; k < threads.size(); ++k) {
    PinnedThread t = threads[k];
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpus[k % cpus.size()], &one);
    if (sched_setaffinity(pid_t(t.tid), sizeof one, &one) != 0) continue;  // a thread that has ended
    t.cpu = cpus[k % cpus.size()];
    p.threads.push_back(t);
  }
  p.applied = !p.threads.empty();
  p.reason = p.applied ? "the driver's threads, one per CPU in turn (wall-clock pass timing)"
                       : "no thread could be pinned";
#else
  p.reason = "not supported on this system";
#endif
  return p;
}

nlohmann::json toJson(const ThreadPinning& pinning) {
  nlohmann::json threads = nlohmann::json::array();
  for (const PinnedThread& t : pinning.threads) threads.push_back({{"tid", t.tid}, {"name", t.name}, {"cpu", t.cpu}});
  return {{"mode", pinning.mode}, {"applied", pinning.applied}, {"reason", pinning.reason}, {"threads", threads}};
}

std::string describe(const ThreadPinning& pinning) {
  if (!pinning.applied) return "driver threads not pinned: " + pinning.reason;
  std::string s = "driver threads pinned one per CPU:";
  for (size_t k = 0; k < pinning.threads.size(); ++k)
    s += (k ? ", " : " ") + pinning.threads[k].name + " -> " + std::to_string(pinning.threads[k].cpu);
  return s;
}

}  // namespace vs
