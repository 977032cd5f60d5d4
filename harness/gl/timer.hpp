// Per-pass timing with two strategies, chosen by a calibration run at start-up:
//  - GpuTimestamp: glQueryCounter(GL_TIMESTAMP) pairs, read a few frames late from a ring;
//  - WallClock: glFinish before and after each pass, steady_clock in between.
// llvmpipe's queries under-report draws and read 0 for compute, so there the wall clock wins.
#pragma once
#include <chrono>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "harness/gl/gl.hpp"

namespace vs {

enum class TimerStrategy { GpuTimestamp, WallClock };
const char* timerStrategyName(TimerStrategy s);

struct TimerCalibration {
  TimerStrategy chosen = TimerStrategy::WallClock;
  double drawWallMs = 0, drawTimestampMs = 0, drawElapsedMs = 0;
  double computeWallMs = 0, computeTimestampMs = 0, computeElapsedMs = 0;
  std::string reason;
};
// Times a fragment-heavy draw and a compute dispatch both ways; picks GpuTimestamp only when its
// deltas agree with the wall clock within 25 % for both.
TimerCalibration calibrateTimer();

struct TimingStats {
  double medianMs = 0, minMs = 0, maxMs = 0, mdapePct = 0;
  // Nearest-rank percentiles: a moving scene's frame-time spikes (a pass whose cost jumps when
  // the epipole enters the screen) sit far from the median.
  double p95Ms = 0, p99Ms = 0;
  size_t samples = 0;
};
// The nearest-rank p-th percentile (p in [0, 100]) of the values (0 without any).
double percentileOf(std::vector<double> values, double p);
// The median of the values (0 without any).
double medianOf(std::vector<double> values);
// MdAPE: median over samples of |x - median| / median, in percent.
TimingStats summarise(std::vector<double> samplesMs);

class PassTimer {
 public:
  explicit PassTimer(TimerStrategy strategy);
  ~PassTimer();
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

  class Scope {
   public:
    Scope(PassTimer& timer, std::string name);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    PassTimer& timer_;
    std::string name_;
  };
  // Times everything issued until the returned object goes out of scope, under `name`.
  Scope scope(std::string name) { return Scope(*this, std::move(name)); }

  void beginFrame(bool record);
  void endFrame();
  void finish();  // reads every outstanding query

  // Samples per pass name (ms), one per frame, in first-seen order; "Frame" holds whole frames.
  const std::vector<std::string>& passOrder() const { return order_; }
  const std::map<std::string, std::vector<double>>& samples() const { return samples_; }
  // Per recorded frame, in order: each pass's ms in that frame (the passes that ran) and "Frame".
  const std::vector<std::map<std::string, double>>& frames() const { return frames_; }
  TimerStrategy strategy() const { return strategy_; }
  static constexpr const char* kFrame = "Frame";

 private:
  void begin(const std::string& name);
  void end(const std::string& name);
  void record(const std::string& name, double ms);
  void addToFrame(const std::string& name, double ms);
  void flushFrame();
  GLuint acquireQuery();
  void resolve(bool wait);

  struct Pending {
    std::string name;
    GLuint begin = 0, end = 0;
  };
  struct PendingFrame {
    std::vector<Pending> passes;
  };
  TimerStrategy strategy_;
  bool recording_ = false;
  bool inFrame_ = false;
  std::chrono::steady_clock::time_point frameStart_;
  std::vector<std::chrono::steady_clock::time_point> wallStarts_;
  std::vector<std::string> open_;
  std::vector<std::string> order_;
  std::map<std::string, std::vector<double>> samples_;
  std::vector<std::map<std::string, double>> frames_;
  std::vector<std::pair<std::string, double>> frameTotals_;  // the frame being recorded or resolved
  std::vector<GLuint> freeQueries_, allQueries_;
  PendingFrame current_;
  std::deque<PendingFrame> ring_;
  static constexpr size_t kFramesInFlight = 3;
};

}  // namespace vs
