#include "harness/shootout/result_files.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "harness/gl/timer.hpp"

namespace vs::shootout {

namespace fs = std::filesystem;

namespace {

std::string sanitize(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(uint8_t(c)) || c == '-' || c == '.') ? c : '_';
  return out.empty() ? "default" : out;
}

}  // namespace

void prepareOutputDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw std::runtime_error("cannot create output folder " + dir + ": " + ec.message());
  std::string probe = dir + "/.vshadow-write-test" + std::to_string(::getpid());
  std::ofstream out(probe);
  if (!out) throw std::runtime_error("output folder " + dir + " is not writable");
  out.close();
  fs::remove(probe, ec);
}

ResultFiles::ResultFiles(const std::string& dir, const std::string& sceneName, bool images)
    : runs_(runsColumns(), kRunsKeyColumns), passes_(passesColumns(), kPassesKeyColumns),
      frames_(framesColumns(), kFramesKeyColumns), images_(images) {
  prepareOutputDir(dir);
  runsPath_ = dir + "/runs.csv";
  passesPath_ = dir + "/passes.csv";
  framesPath_ = dir + "/frames.csv";
  metaPath_ = dir + "/meta.json";
  runs_.loadExisting(runsPath_);
  passes_.loadExisting(passesPath_);
  frames_.loadExisting(framesPath_);
  imageDir_ = fs::path(dir) / "images" / sanitize(sceneName);
  if (images_) fs::create_directories(imageDir_);
}

void ResultFiles::writeMeta(const nlohmann::json& meta) const { writeFileAtomic(metaPath_, meta.dump(2) + "\n"); }

void ResultFiles::writeReferenceImages(const Reference& ref, float exposure) const {
  if (!images_) return;
  writeExr((imageDir_ / "reference.final.exr").string(), ref.final);
  writeExr((imageDir_ / "reference.ls.exr").string(), ref.inscatter);
  writePngTonemapped((imageDir_ / "reference.png").string(), ref.final, exposure);
}

void ResultFiles::writeImages(const MethodRun& r, const Baselines& base, bool haveReference) const {
  if (!images_ || r.status != RunStatus::Success) return;
  std::string stem = (imageDir_ / (sanitize(r.method) + "_" + sanitize(r.params))).string();
  writeExr(stem + ".final.exr", r.final);
  writeExr(stem + ".ls.exr", r.inscatter);
  writePngTonemapped(stem + ".png", r.final, haveReference ? base.exposure : autoExposure(r.final));
  if (haveReference)
    writePng8(stem + ".error.png", r.final.width, r.final.height,
              falseColourError(r.final, base.reference.final, 0.1f / std::max(base.exposure, 1e-20f)));
}

void ResultFiles::writeSequenceImages(const MethodRun& r, const std::vector<const Image*>& references,
                                      float exposure) {
  if (!images_ || r.status != RunStatus::Success) return;
  const fs::path frames = imageDir_ / "frames";
  const fs::path own = frames / (sanitize(r.method) + "_" + sanitize(r.params));
  fs::create_directories(own);
  fs::create_directories(frames / "reference");
  const float fullScale = 0.1f / std::max(exposure, 1e-20f);
  for (size_t k = 0; k < r.sequence.size() && k < references.size(); ++k) {
    const MethodRun::SequenceFrame& f = r.sequence[k];
    char name[32];
    std::snprintf(name, sizeof name, "%04u", f.index);
    if (referenceFramesWritten_.insert(f.index).second)
      writePngTonemapped((frames / "reference" / (std::string(name) + ".png")).string(), *references[k], exposure);
    writePngTonemapped((own / (std::string(name) + ".png")).string(), f.inscatter, exposure);
    writePng8((own / (std::string(name) + ".error.png")).string(), f.inscatter.width, f.inscatter.height,
              falseColourError(f.inscatter, *references[k], fullScale));
  }
}

void ResultFiles::addRows(const ResultRow& run, const MethodRun& r, const std::string& sceneName,
                          const std::string& timer, const std::string& renderer, const RoundTimings& rounds) {
  runs_.upsert(run);
  passes_.removeWhere({{"scene", sceneName}, {"method", r.method}, {"params", r.params}});
  auto addPass = [&](const std::string& pass, const TimingStats& s, const std::vector<TimingStats>* perRound) {
    ResultRow row(passesColumns());
    row.set("scene", sceneName).set("method", r.method).set("params", r.params).set("pass", pass);
    row.set("median_ms", s.medianMs).set("min_ms", s.minMs).set("max_ms", s.maxMs).set("mdape_pct", s.mdapePct);
    row.set("p95_ms", s.p95Ms).set("p99_ms", s.p99Ms);
    row.set("frames", s.samples).set("timer", timer).set("renderer", renderer);
    if (perRound && !perRound->empty()) {
      auto [lo, hi] = roundRange(*perRound);
      row.set("rounds", int(perRound->size())).set("round_min_ms", lo).set("round_max_ms", hi);
    }
    passes_.upsert(row);
  };
  for (const auto& p : r.passes) {
    auto it = rounds.passes.find(p);
    addPass(p, r.passStats.at(p), it == rounds.passes.end() ? nullptr : &it->second);
  }
  if (r.status == RunStatus::Success) addPass(PassTimer::kFrame, r.frame, &rounds.frame);
  runs_.save(runsPath_);
  passes_.save(passesPath_);
}

void ResultFiles::addFrames(const MethodRun& r, const std::vector<ErrorMetrics>& errors, const std::string& sceneName,
                            const std::string& timer, const std::string& renderer) {
  frames_.removeWhere({{"scene", sceneName}, {"method", r.method}, {"params", r.params}});
  for (size_t k = 0; k < r.sequence.size(); ++k) {
    const MethodRun::SequenceFrame& f = r.sequence[k];
    std::string passes;
    for (const auto& [pass, ms] : f.passMs)
      if (pass != PassTimer::kFrame) passes += (passes.empty() ? "" : ";") + pass + "=" + num(ms);
    ResultRow row(framesColumns());
    row.set("scene", sceneName).set("method", r.method).set("params", r.params).set("frame", double(f.index));
    row.set("time_s", f.timeS).set("pass_ms", passes).set("timer", timer).set("renderer", renderer);
    auto frameMs = f.passMs.find(PassTimer::kFrame);
    if (frameMs != f.passMs.end()) row.set("frame_ms", frameMs->second);
    if (k < errors.size()) row.set("ls_rmse", errors[k].rmse).set("ls_relmse", errors[k].relmse);
    frames_.upsert(row);
  }
  frames_.save(framesPath_);
  wroteFrames_ = true;
}

std::string ResultFiles::summary() const {
  return "results: " + runsPath_ + "  " + passesPath_ + (wroteFrames_ ? "  " + framesPath_ : "") + "  " + metaPath_;
}

}  // namespace vs::shootout
