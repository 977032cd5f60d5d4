#include "harness/gl/timer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace vs {

using Clock = std::chrono::steady_clock;
static double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

const char* timerStrategyName(TimerStrategy s) {
  return s == TimerStrategy::GpuTimestamp ? "gpu-timestamp" : "wall-clock";
}

double medianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double percentileOf(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  double rank = std::ceil(std::clamp(p, 0.0, 100.0) / 100.0 * double(v.size()));
  return v[size_t(std::clamp(rank, 1.0, double(v.size()))) - 1];
}

TimingStats summarise(std::vector<double> samplesMs) {
  TimingStats s;
  s.samples = samplesMs.size();
  if (samplesMs.empty()) return s;
  s.medianMs = medianOf(samplesMs);
  s.minMs = *std::min_element(samplesMs.begin(), samplesMs.end());
  s.maxMs = *std::max_element(samplesMs.begin(), samplesMs.end());
  s.p95Ms = percentileOf(samplesMs, 95.0);
  s.p99Ms = percentileOf(samplesMs, 99.0);
  std::vector<double> ape;
  for (double x : samplesMs) ape.push_back(s.medianMs > 0 ? std::fabs(x - s.medianMs) / s.medianMs * 100.0 : 0.0);
  s.mdapePct = medianOf(ape);
  return s;
}

// ---- PassTimer

PassTimer::PassTimer(TimerStrategy strategy) : strategy_(strategy) {}

PassTimer::~PassTimer() {
  if (!allQueries_.empty()) glDeleteQueries(GLsizei(allQueries_.size()), allQueries_.data());
}

PassTimer::Scope::Scope(PassTimer& timer, std::string name) : timer_(timer), name_(std::move(name)) {
  timer_.begin(name_);
}
PassTimer::Scope::~Scope() { timer_.end(name_); }

GLuint PassTimer::acquireQuery() {
  if (freeQueries_.empty()) {
    GLuint q = 0;
    glGenQueries(1, &q);
    allQueries_.push_back(q);
    return q;
  }
  GLuint q = freeQueries_.back();
  freeQueries_.pop_back();
  return q;
}

void PassTimer::record(const std::string& name, double ms) {
  if (!samples_.count(name)) order_.push_back(name);
  samples_[name].push_back(ms);
}

// A pass that runs several times in a frame (once per virtual point light, per cube face) counts
// once per frame, with the sum of its runs.
void PassTimer::addToFrame(const std::string& name, double ms) {
  for (auto& [pass, total] : frameTotals_)
    if (pass == name) {
      total += ms;
      return;
    }
  frameTotals_.emplace_back(name, ms);
}

void PassTimer::flushFrame() {
  std::map<std::string, double> frame;
  for (const auto& [pass, total] : frameTotals_) {
    record(pass, total);
    frame[pass] = total;
  }
  frames_.push_back(std::move(frame));
  frameTotals_.clear();
}

void PassTimer::beginFrame(bool record) {
  if (inFrame_) throw std::logic_error("PassTimer::beginFrame inside a frame");
  inFrame_ = true;
  recording_ = record;
  current_ = {};
  frameTotals_.clear();
  if (strategy_ == TimerStrategy::WallClock) {
    glFinish();
    frameStart_ = Clock::now();
  } else {
    Pending frame{kFrame, acquireQuery(), 0};
    glQueryCounter(frame.begin, GL_TIMESTAMP);
    current_.passes.push_back(frame);
  }
}

void PassTimer::endFrame() {
  if (!inFrame_) throw std::logic_error("PassTimer::endFrame outside a frame");
  if (!open_.empty()) throw std::logic_error("PassTimer: pass '" + open_.back() + "' still open at frame end");
  inFrame_ = false;
  if (strategy_ == TimerStrategy::WallClock) {
    glFinish();
    if (recording_) {
      addToFrame(kFrame, msSince(frameStart_));
      flushFrame();
    }
    return;
  }
  current_.passes[0].end = acquireQuery();
  glQueryCounter(current_.passes[0].end, GL_TIMESTAMP);
  if (recording_) {
    ring_.push_back(std::move(current_));
  } else {
    for (auto& p : current_.passes) {
      freeQueries_.push_back(p.begin);
      freeQueries_.push_back(p.end);
    }
  }
  current_ = {};
  resolve(false);
}

void PassTimer::begin(const std::string& name) {
  open_.push_back(name);
  if (strategy_ == TimerStrategy::WallClock) {
    glFinish();
    wallStarts_.push_back(Clock::now());
    return;
  }
  current_.passes.push_back({name, acquireQuery(), 0});
  glQueryCounter(current_.passes.back().begin, GL_TIMESTAMP);
}

void PassTimer::end(const std::string& name) {
  if (open_.empty() || open_.back() != name) throw std::logic_error("PassTimer: scopes must nest: " + name);
  open_.pop_back();
  if (strategy_ == TimerStrategy::WallClock) {
    glFinish();
    double ms = msSince(wallStarts_.back());
    wallStarts_.pop_back();
    if (recording_ && inFrame_) addToFrame(name, ms);
    return;
  }
  // The innermost unfinished pass of this name.
  auto it = std::find_if(current_.passes.rbegin(), current_.passes.rend(),
                         [&](const Pending& p) { return p.name == name && p.end == 0; });
  it->end = acquireQuery();
  glQueryCounter(it->end, GL_TIMESTAMP);
}

// Reads frames older than kFramesInFlight (or all of them when waiting).
void PassTimer::resolve(bool wait) {
  while (!ring_.empty() && (wait || ring_.size() > kFramesInFlight)) {
    auto& frame = ring_.front();
    for (auto& p : frame.passes) {
      GLuint64 t0 = 0, t1 = 0;
      glGetQueryObjectui64v(p.begin, GL_QUERY_RESULT, &t0);
      glGetQueryObjectui64v(p.end, GL_QUERY_RESULT, &t1);
      addToFrame(p.name, t1 > t0 ? double(t1 - t0) * 1e-6 : 0.0);
      freeQueries_.push_back(p.begin);
      freeQueries_.push_back(p.end);
    }
    flushFrame();
    ring_.pop_front();
  }
}

void PassTimer::finish() { resolve(true); }

// ---- calibration

namespace {
struct Measured {
  double wallMs, timestampMs, elapsedMs;
};

template <typename Work>
Measured measureBothWays(Work&& work) {
  GLuint q[3];
  glGenQueries(3, q);
  std::vector<double> wall, stamp, elapsed;
  work();  // warm-up: compile, first-use allocation
  glFinish();
  for (int i = 0; i < 3; ++i) {
    glFinish();
    auto t = Clock::now();
    glQueryCounter(q[0], GL_TIMESTAMP);
    glBeginQuery(GL_TIME_ELAPSED, q[2]);
    work();
    glEndQuery(GL_TIME_ELAPSED);
    glQueryCounter(q[1], GL_TIMESTAMP);
    glFinish();
    wall.push_back(msSince(t));
    GLuint64 t0 = 0, t1 = 0, e = 0;
    glGetQueryObjectui64v(q[0], GL_QUERY_RESULT, &t0);
    glGetQueryObjectui64v(q[1], GL_QUERY_RESULT, &t1);
    glGetQueryObjectui64v(q[2], GL_QUERY_RESULT, &e);
    stamp.push_back(t1 > t0 ? double(t1 - t0) * 1e-6 : 0.0);
    elapsed.push_back(double(e) * 1e-6);
  }
  glDeleteQueries(3, q);
  return {medianOf(wall), medianOf(stamp), medianOf(elapsed)};
}
}  // namespace

TimerCalibration calibrateTimer() {
  TimerCalibration c;
  // A known fragment-heavy draw and a known compute dispatch; sized to take several ms here.
  gl::Program draw = gl::buildFullscreen("harness/shaders/calibrate.frag");
  gl::Program compute = gl::buildCompute("harness/shaders/calibrate.comp");
  gl::Texture target = gl::createTexture2D(GL_RGBA8, 256, 256);
  gl::Framebuffer fbo = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, target.id()}});
  gl::Buffer sink = gl::createBuffer(256 * 256 * 4);
  int iterations = 64;
  auto drawWork = [&] {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    glViewport(0, 0, 256, 256);
    glUseProgram(draw.id());
    glUniform1i(0, iterations);
    gl::drawFullscreenTriangle();
  };
  auto computeWork = [&] {
    glUseProgram(compute.id());
    glUniform1i(0, iterations);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, sink.id());
    glDispatchCompute(256 / 8, 256 / 8, 1);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
  };
  // Grow the workload until the draw takes >= 4 ms so fixed overheads do not dominate.
  Measured d = measureBothWays(drawWork);
  while (d.wallMs < 4.0 && iterations < (1 << 20)) {
    iterations *= d.wallMs > 0.5 ? int(std::ceil(4.0 / d.wallMs)) + 1 : 8;
    d = measureBothWays(drawWork);
  }
  Measured k = measureBothWays(computeWork);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
  c.drawWallMs = d.wallMs;
  c.drawTimestampMs = d.timestampMs;
  c.drawElapsedMs = d.elapsedMs;
  c.computeWallMs = k.wallMs;
  c.computeTimestampMs = k.timestampMs;
  c.computeElapsedMs = k.elapsedMs;
  auto agrees = [](double gpu, double wall) { return wall > 0 && std::fabs(gpu - wall) / wall < 0.25; };
  bool drawOk = agrees(d.timestampMs, d.wallMs), computeOk = agrees(k.timestampMs, k.wallMs);
  c.chosen = drawOk && computeOk ? TimerStrategy::GpuTimestamp : TimerStrategy::WallClock;
  char buf[256];
  std::snprintf(buf, sizeof buf, "draw: wall %.2f ms, timestamps %.2f ms; compute: wall %.2f ms, timestamps %.2f ms; %s",
                d.wallMs, d.timestampMs, k.wallMs, k.timestampMs,
                c.chosen == TimerStrategy::GpuTimestamp ? "queries agree with the wall clock"
                                                        : "queries disagree with the wall clock");
  c.reason = buf;
  return c;
}

}  // namespace vs
