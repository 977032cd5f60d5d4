// The result folder of a run: runs.csv, passes.csv, frames.csv, meta.json and images. Takes the
// rows as they are finished; every file is replaced atomically, so an interrupted run keeps every
// finished row and never a partial file. Rows of earlier runs into the same folder are kept,
// replaced where their keys match.
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "harness/evaluation/metrics.hpp"
#include "harness/io/results.hpp"
#include "harness/pipeline/runner.hpp"
#include "harness/shootout/baselines.hpp"
#include "harness/shootout/rounds.hpp"

namespace vs::shootout {

// Checks that `dir` can hold results before anything else is written there (std::runtime_error).
void prepareOutputDir(const std::string& dir);

class ResultFiles {
 public:
  // `images`: write the images (not with --no-images). Throws std::runtime_error when `dir` cannot
  // hold results.
  ResultFiles(const std::string& dir, const std::string& sceneName, bool images);
  void writeMeta(const nlohmann::json& meta) const;
  void writeReferenceImages(const Reference& ref, float exposure) const;
  // A successful run's images: L and L_s as EXR, L tonemapped, and its error map against the reference.
  void writeImages(const MethodRun& r, const Baselines& base, bool haveReference) const;
  // A moving scene's measured frames, for scripts/video: frames/reference/NNNN.png and
  // frames/METHOD_PARAMS/NNNN.png with NNNN.error.png, where NNNN is the frame of the sequence:
  // L_s at one exposure for the whole sequence, and its error map against the reference of the
  // frame's time (|ΔL_s| luminance, full scale 10 % of display white).
  void writeSequenceImages(const MethodRun& r, const std::vector<const Image*>& references, float exposure);
  // runs.csv's row and passes.csv's rows of `r`; `rounds`: the job's timings per round (r holds
  // their combination).
  void addRows(const ResultRow& run, const MethodRun& r, const std::string& sceneName, const std::string& timer,
               const std::string& renderer, const RoundTimings& rounds);
  // frames.csv: a moving scene's row, frame by frame (time, frame and pass times, L_s errors).
  void addFrames(const MethodRun& r, const std::vector<ErrorMetrics>& errors, const std::string& sceneName,
                 const std::string& timer, const std::string& renderer);
  // "results: runs.csv passes.csv [frames.csv] meta.json" with their paths.
  std::string summary() const;

 private:
  CsvTable runs_, passes_, frames_;
  bool images_, wroteFrames_ = false;
  std::string runsPath_, passesPath_, framesPath_, metaPath_;
  std::filesystem::path imageDir_;
  std::set<uint32_t> referenceFramesWritten_;  // frames/reference/ images written by this process
};

}  // namespace vs::shootout
