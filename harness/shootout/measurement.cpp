#include "harness/shootout/measurement.hpp"

#include <algorithm>
#include <cstdio>

namespace vs::shootout {

namespace {

RunOptions sequenceOptions(RunOptions options, bool sequence) {
  options.sequence = sequence;
  return options;
}

}  // namespace

Measurement::Measurement(const RowContext& rows, const MethodRegistry& registry, const gl::Limits& limits,
                         const RunOptions& options, ResultFiles& files, Progress& progress)
    : rows_(rows), registry_(registry), limits_(limits), files_(files), progress_(progress), options_(options),
      sequence_(rows.plan.scene.animation.moves() && rows.plan.haveReference),
      runner_(rows.plan.scene, limits, sequenceOptions(options, sequence_)),
      guard_([this] { return probe().measure(); },
             DriftPolicy{rows.req.driftThresholdPct, rows.req.driftRetries, rows.req.driftThresholdPct > 0.0}),
      frameReferences_(rows.req, rows.plan, rows.base, limits, registry, options, progress),
      firsts_(rows.plan.jobs.size()), timings_(rows.plan.jobs.size()), matches_(rows.plan.jobs.size()),
      drift_(rows.plan.jobs.size()), sequenceMetrics_(rows.plan.jobs.size()) {
  const RunPlan& plan = rows.plan;
  later_ = FrameSchedule::of(options);
  later_.workCounters = later_.sequence = false;
  if (rows.req.equalQuality && plan.haveReference && plan.effects.scattering) {
    const Image& truth = plan.equalQualityExact ? rows.base.exact.inscatter : rows.base.reference.inscatter;
    if (plan.movedScene) stillRunner_ = std::make_unique<Runner>(plan.stillScene(), limits, options);
    equalQuality_ = std::make_unique<EqualQuality>(
        std::make_unique<RenderedBaseline>(plan, limits, registry, options, truth, runner_,
                                           stillRunner_ ? *stillRunner_ : runner_),
        progress);
  }
}

int Measurement::runAll(int& item) {
  std::printf("%-10s %-40s %-11s %10s %10s %8s %7s\n", "method", "params", "status", "frame_ms", "rmse", "psnr",
              "ssim");
  const int rounds = rows_.req.rounds;
  for (int round = 0; round < rounds; ++round)
    for (size_t j = 0; j < rows_.plan.jobs.size(); ++j) {
      if (round > 0 && firsts_[j].run.status != RunStatus::Success) continue;  // its row is written
      const Job& job = rows_.plan.jobs[j];
      progress_.item(item++, rounds > 1 ? job.label + " (round " + std::to_string(round + 1) + "/" +
                                              std::to_string(rounds) + ")"
                                        : job.label);
      measureRound(j, round);
      writeRow(j, round);
    }
  return failures_;
}

nlohmann::json Measurement::driftJson() const {
  using json = nlohmann::json;
  json samples = json::array();
  for (const CalibrationSample& c : guard_.history()) samples.push_back({{"draw_ms", c.drawMs}, {"compute_ms", c.computeMs}});
  int disturbedRows = 0;
  double driftMax = 0.0, shiftMax = 0.0;
  for (const RowDrift& d : drift_) {
    disturbedRows += d.disturbed ? 1 : 0;
    driftMax = std::max(driftMax, d.driftPct);
    shiftMax = std::max(shiftMax, d.shiftPct);
  }
  const DriftPolicy& p = guard_.policy();
  return {{"enabled", p.enabled},
          {"threshold_pct", p.thresholdPct},
          {"max_retries", p.maxRetries},
          {"workload", probe_ ? json{{"draw_iterations", probe_->drawIterations()},
                                     {"compute_iterations", probe_->computeIterations()},
                                     {"size", "256x256 fragments; 256x256 invocations"}}
                              : json(nullptr)},
          {"samples", samples},
          {"drift_max_pct", driftMax},
          {"shift_max_pct", shiftMax},
          {"disturbed_rounds", guard_.disturbedRounds()},
          {"retries", guard_.retries()},
          {"disturbed_rows", disturbedRows}};
}

CalibrationProbe& Measurement::probe() {
  if (!probe_) probe_ = std::make_unique<CalibrationProbe>();
  return *probe_;
}

// One round of job j, guarded: run again while the calibration around it moved.
void Measurement::measureRound(size_t j, int round) {
  const Job& job = rows_.plan.jobs[j];
  Measured& first = firsts_[j];
  MethodRun kept;  // this round's timings
  kept.status = RunStatus::Failure;
  std::vector<double> baselineMs;
  GuardedRound guarded = guard_.run([&](int attempt) {
    if (attempt > 0)
      progress_.note("round disturbed (calibration moved " + num(guardLastDrift()) + " %): timing " + job.label +
                     " again");
    if (round == 0 && attempt == 0) {
      measureFirst(j);
      if (first.run.status != RunStatus::Success) return false;
      kept = first.run;
    } else {
      auto method = createMethod(registry_, job.method);
      kept = runner_.run(*method, job.params, later_, [&](int done, int total) { progress_.frames(done, total); });
    }
    if (equalQuality_)
      baselineMs = timeMatchedBaselines(matches_[j], runner_, later_, registry_, limits_, *equalQuality_,
                                        first.run.shadowMapSize, progress_);
    return kept.status == RunStatus::Success;
  });
  warnOfDrift();
  if (kept.status != RunStatus::Success) return;
  timings_[j].add(kept);
  drift_[j].add(guarded);
  for (size_t b = 0; b < baselineMs.size(); ++b)
    if (matches_[j].baselines[b].match.reached) matches_[j].baselines[b].roundMs.push_back(baselineMs[b]);
}

// Once per run, at the first disturbed round.
void Measurement::warnOfDrift() {
  if (!guard_.takeFirstWarning()) return;
  progress_.note("warning: the machine's speed changed during a round (calibration moved " +
                 num(guard_.firstDisturbancePct()) + " %, threshold " + num(guard_.policy().thresholdPct) +
                 " %); disturbed rounds are repeated up to " + std::to_string(guard_.policy().maxRetries) +
                 " times and rows still measured so are marked disturbed=1 in runs.csv");
}

double Measurement::guardLastDrift() const {
  const auto& h = guard_.history();
  return h.size() < 2 ? 0.0 : calibrationChangePct(h[h.size() - 2], h.back());
}

// The first round's run: images, errors, work counters, and the equal-quality bisection.
void Measurement::measureFirst(size_t j) {
  Measured& first = firsts_[j];
  first = measureJob(runner_, rows_.plan.jobs[j], registry_, rows_.plan, rows_.base, progress_);
  if (sequence_ && first.run.status == RunStatus::Success) measureSequence(j);
  if (first.run.status == RunStatus::Failure) ++failures_;
  if (first.run.status != RunStatus::Success) progress_.skip(rows_.req.rounds - 1);  // no later rounds
  files_.writeImages(first.run, rows_.base, rows_.plan.haveReference);
  first.run.inscatter = Image();  // the errors are measured: the images are not kept
  first.run.final = Image();
  if (equalQuality_) matches_[j] = matchRow(first, *equalQuality_, rows_.plan);
}

// A moving scene's errors over the first round's measured frames, its frame images and frames.csv.
void Measurement::measureSequence(size_t j) {
  MethodRun& r = firsts_[j].run;
  std::vector<const Image*> frames, references;
  for (const MethodRun::SequenceFrame& f : r.sequence) {
    frames.push_back(&f.inscatter);
    references.push_back(&frameReferences_.at(f.index));
  }
  SequenceMetrics& m = sequenceMetrics_[j];
  m = sequenceMetrics(frames, references);
  files_.writeSequenceImages(r, references, rows_.base.inscatterExposure);
  files_.addFrames(r, m.perFrame, rows_.plan.scene.name, rows_.timer, rows_.renderer);
  m.perFrame.clear();
  r.sequence.clear();  // measured: the images are not kept
}

// The row of job j after `round`: the first round's errors with the rounds' timings so far.
void Measurement::writeRow(size_t j, int round) {
  Measured m = firsts_[j];
  const RoundTimings& t = timings_[j];
  if (m.run.status == RunStatus::Success && t.count() > 1) {
    m.run.frame = combineRounds(t.frame);
    for (auto& [pass, stats] : m.run.passStats)
      if (t.passes.count(pass)) stats = combineRounds(t.passes.at(pass));
  }
  const MethodRun& r = m.run;
  ResultRow row = runRow(m, rows_);
  row.set("series", rows_.plan.jobs[j].series);
  if (r.status == RunStatus::Success && t.count() > 0) {
    row.set("scatter_ms", r.scatterMs()).set("rounds", t.count());
    setRoundColumns(row, j);
  }
  bool lastRound = round == rows_.req.rounds - 1;
  if (equalQuality_ && lastRound) addEqualQuality(row, m, matches_[j], *equalQuality_, rows_.plan, t.scatter);
  files_.addRows(row, r, rows_.plan.scene.name, rows_.timer, rows_.renderer, t);
  progress_.finished(jobSummary(m) + (drift_[j].disturbed ? " (disturbed)" : ""));
  if (!lastRound && r.status == RunStatus::Success) return;  // printed once, after the last round
  printRow(m);
}

// The ranges over the rounds so far, a moving scene's sequence errors and the drift columns.
void Measurement::setRoundColumns(ResultRow& row, size_t j) const {
  const RoundTimings& t = timings_[j];
  auto [frameLo, frameHi] = roundRange(t.frame);
  row.set("frame_round_min_ms", frameLo).set("frame_round_max_ms", frameHi);
  row.set("scatter_round_min_ms", *std::min_element(t.scatter.begin(), t.scatter.end()));
  row.set("scatter_round_max_ms", *std::max_element(t.scatter.begin(), t.scatter.end()));
  if (const SequenceMetrics& q = sequenceMetrics_[j]; q.measured) {
    row.set("seq_frames", q.frames).set("seq_ls_rmse_mean", q.rmseMean).set("seq_ls_rmse_max", q.rmseMax);
    row.set("seq_ls_relmse_mean", q.relmseMean).set("seq_ls_relmse_max", q.relmseMax);
    row.set("temporal_ls_rmse", q.temporal.rmse).set("temporal_ls_rel", q.temporal.relative);
  }
  if (guard_.policy().enabled) {
    const RowDrift& d = drift_[j];
    row.set("calibration_drift_pct", d.driftPct).set("calibration_shift_pct", d.shiftPct);
    row.set("disturbed", d.disturbed ? "1" : "0").set("disturbed_retries", d.retries);
  }
}

void Measurement::printRow(const Measured& m) const {
  const MethodRun& r = m.run;
  bool ok = r.status == RunStatus::Success;
  std::printf("%-10s %-40s %-11s %10s %10s %8s %7s\n", r.method.c_str(), r.params.c_str(), runStatusName(r.status),
              ok ? num(r.frame.medianMs).c_str() : "-", m.measured ? num(m.finalErr.rmse).c_str() : "-",
              m.measured ? num(m.finalErr.psnr).c_str() : "-", m.measured ? num(m.finalErr.ssim).c_str() : "-");
  std::fflush(stdout);
}

}  // namespace vs::shootout
