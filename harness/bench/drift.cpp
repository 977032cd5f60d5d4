#include "harness/bench/drift.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "harness/gl/gl.hpp"
#include "harness/gl/timer.hpp"

namespace vs {

double calibrationChangePct(const CalibrationSample& from, const CalibrationSample& to) {
  auto change = [](double a, double b) { return a > 0.0 && b > 0.0 ? std::fabs(b - a) / a * 100.0 : 0.0; };
  return std::max(change(from.drawMs, to.drawMs), change(from.computeMs, to.computeMs));
}

// ---- CalibrationProbe

struct CalibrationProbe::Gl {
  static constexpr int kSize = 256;
  gl::Program draw = gl::buildFullscreen("harness/shaders/calibrate.frag");
  gl::Program compute = gl::buildCompute("harness/shaders/calibrate.comp");
  gl::Texture target = gl::createTexture2D(GL_RGBA8, kSize, kSize);
  gl::Framebuffer fbo = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, target.id()}});
  gl::Buffer sink = gl::createBuffer(size_t(kSize) * kSize * 4);
  int drawIterations = 16, computeIterations = 16;

  void drawOnce() const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    glViewport(0, 0, kSize, kSize);
    glUseProgram(draw.id());
    glUniform1i(0, drawIterations);
    gl::drawFullscreenTriangle();
  }
  void computeOnce() const {
    glUseProgram(compute.id());
    glUniform1i(0, computeIterations);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, sink.id());
    glDispatchCompute(kSize / 8, kSize / 8, 1);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
  }
  // Median wall-clock ms of `runs` runs of `work`, each bracketed by glFinish.
  template <typename Work>
  static double time(Work&& work, int runs) {
    std::vector<double> ms;
    for (int i = 0; i < runs; ++i) {
      glFinish();
      auto t = std::chrono::steady_clock::now();
      work();
      glFinish();
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count());
    }
    return medianOf(ms);
  }
  // Grows `iterations` until one run of `work` takes about targetMs.
  template <typename Work>
  static void size(int& iterations, Work&& work, double targetMs) {
    work();  // first use: compilation, allocation
    double ms = time(work, 3);
    for (int k = 0; k < 24 && ms < targetMs && iterations < (1 << 22); ++k) {
      double factor = ms > 0.05 ? std::clamp(targetMs / ms, 1.2, 16.0) : 16.0;
      iterations = int(std::ceil(iterations * factor));
      ms = time(work, 3);
    }
  }
};

CalibrationProbe::CalibrationProbe(double targetMs) : gl_(std::make_unique<Gl>()) {
  Gl::size(gl_->drawIterations, [&] { gl_->drawOnce(); }, targetMs);
  Gl::size(gl_->computeIterations, [&] { gl_->computeOnce(); }, targetMs);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
}

CalibrationProbe::~CalibrationProbe() = default;

CalibrationSample CalibrationProbe::measure() {
  constexpr int kRuns = 5;
  CalibrationSample s;
  s.drawMs = Gl::time([&] { gl_->drawOnce(); }, kRuns);
  s.computeMs = Gl::time([&] { gl_->computeOnce(); }, kRuns);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
  return s;
}

int CalibrationProbe::drawIterations() const { return gl_->drawIterations; }
int CalibrationProbe::computeIterations() const { return gl_->computeIterations; }

// ---- DriftGuard

DriftGuard::DriftGuard(std::function<CalibrationSample()> probe, DriftPolicy policy)
    : probe_(std::move(probe)), policy_(policy) {}

CalibrationSample DriftGuard::sample() {
  history_.push_back(probe_());
  return history_.back();
}

GuardedRound DriftGuard::run(const std::function<bool(int)>& attempt) {
  GuardedRound round;
  if (!policy_.enabled) {
    attempt(0);
    return round;
  }
  if (history_.empty()) {
    // The run's first calibration, which every later one is compared with: the median of three,
    // so that one noisy timing does not shift the whole run.
    std::vector<double> draw, compute;
    for (int i = 0; i < 3; ++i) {
      CalibrationSample c = probe_();
      draw.push_back(c.drawMs);
      compute.push_back(c.computeMs);
    }
    history_.push_back({medianOf(draw), medianOf(compute)});
  }
  const CalibrationSample first = history_.front();
  for (int k = 0;; ++k) {
    round.before = history_.back();
    bool timed = attempt(k);
    if (!timed) {  // nothing to check; the next round starts from this calibration
      round.after = round.before;
      break;
    }
    round.after = sample();
    round.driftPct = calibrationChangePct(round.before, round.after);
    const CalibrationSample during = {0.5 * (round.before.drawMs + round.after.drawMs),
                                      0.5 * (round.before.computeMs + round.after.computeMs)};
    round.shiftPct = calibrationChangePct(first, during);
    bool drifted = round.driftPct > policy_.thresholdPct;
    round.disturbed = drifted || round.shiftPct > policy_.thresholdPct;
    if (round.disturbed) {
      ++disturbedRounds_;
      if (!warned_ && !pendingWarning_) {
        pendingWarning_ = true;
        firstDisturbancePct_ = std::max(round.driftPct, round.shiftPct);
      }
    }
    // A shift alone is the machine's state, which repeating the round would not change.
    if (!drifted || k >= policy_.maxRetries) break;
    ++round.retries;
    ++retries_;
  }
  return round;
}

bool DriftGuard::takeFirstWarning() {
  if (!pendingWarning_) return false;
  pendingWarning_ = false;
  warned_ = true;
  return true;
}

void RowDrift::add(const GuardedRound& round) {
  driftPct = std::max(driftPct, round.driftPct);
  shiftPct = std::max(shiftPct, round.shiftPct);
  retries += round.retries;
  disturbed = disturbed || round.disturbed;
  last = round.after;
}

}  // namespace vs
