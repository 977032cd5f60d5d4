// The rows stage: takes a measured job, gives its runs.csv row (the columns every run and shootout
// fills; Measurement adds the rounds', drift and equal-quality columns) and its one-line summary.
#pragma once
#include <string>

#include "harness/io/results.hpp"
#include "harness/shootout/measured.hpp"

namespace vs::shootout {

// What run and shootout write with every row, fixed for the run.
struct RowContext {
  const RunRequest& req;
  const RunPlan& plan;
  const Baselines& base;
  std::string timer, renderer, date;
};

ResultRow runRow(const Measured& m, const RowContext& rows);

// "12.5 ms/frame, rmse 0.01, psnr 40 dB", or the status and why.
std::string jobSummary(const Measured& m);

}  // namespace vs::shootout
