// The measuring stage: takes the plan's jobs and the baselines, gives every row to the result
// files. Every job runs once per round, in turn (A B C, A B C); the first round renders the images
// and errors (and the equal-quality match), later rounds only time. Each row's round (the row and
// its matched baselines) runs between two timings of the calibration workload and again when the
// machine's speed moved meanwhile (DriftGuard). A row is written after each of its rounds, so an
// interrupted run keeps every finished row; its console line is printed after its last round.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "harness/bench/drift.hpp"
#include "harness/cli/progress.hpp"
#include "harness/shootout/equal_quality.hpp"
#include "harness/shootout/measured.hpp"
#include "harness/shootout/result_files.hpp"
#include "harness/shootout/rounds.hpp"
#include "harness/shootout/rows.hpp"
#include "harness/shootout/sequence.hpp"

namespace vs::shootout {

class Measurement {
 public:
  Measurement(const RowContext& rows, const MethodRegistry& registry, const gl::Limits& limits,
              const RunOptions& options, ResultFiles& files, Progress& progress);
  bool equalQuality() const { return equalQuality_ != nullptr; }

  // Runs every round of every job, progress items from `item` on; returns the number of failed rows.
  int runAll(int& item);

  // The calibration's figures for meta.json's "drift".
  nlohmann::json driftJson() const;

 private:
  CalibrationProbe& probe();
  void measureRound(size_t j, int round);
  void warnOfDrift();
  double guardLastDrift() const;
  void measureFirst(size_t j);
  void measureSequence(size_t j);
  void writeRow(size_t j, int round);
  void setRoundColumns(ResultRow& row, size_t j) const;
  void printRow(const Measured& m) const;

  const RowContext& rows_;
  const MethodRegistry& registry_;
  const gl::Limits& limits_;
  ResultFiles& files_;
  Progress& progress_;
  RunOptions options_;
  bool sequence_;  // a moving scene with a reference: errors over every measured frame
  // One runner per scene state: the scene, and for a moving scene its compared frame held still
  // (the equal-quality baselines' errors). Later rounds and repeated ones only time: no images,
  // errors, work counters or sequence (those come from the first).
  Runner runner_;
  std::unique_ptr<Runner> stillRunner_;
  FrameSchedule later_;
  std::unique_ptr<EqualQuality> equalQuality_;
  std::unique_ptr<CalibrationProbe> probe_;
  DriftGuard guard_;
  FrameReferences frameReferences_;
  std::vector<Measured> firsts_;
  std::vector<RoundTimings> timings_;
  std::vector<RowMatches> matches_;
  std::vector<RowDrift> drift_;
  std::vector<SequenceMetrics> sequenceMetrics_;
  int failures_ = 0;
};

}  // namespace vs::shootout
