#include "harness/shootout/rows.hpp"

namespace vs::shootout {

namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : ";") + i;
  return s;
}

void setErrors(ResultRow& row, const Measured& m) {
  if (m.measured) {
    row.set("rmse", m.finalErr.rmse).set("relmse", m.finalErr.relmse).set("psnr", m.finalErr.psnr);
    row.set("ssim", m.finalErr.ssim).set("max_abs", m.finalErr.maxAbs);
    row.set("max_abs_x", m.finalErr.maxX).set("max_abs_y", m.finalErr.maxY);
    row.set("ls_rmse", m.lsErr.rmse).set("ls_relmse", m.lsErr.relmse).set("ls_psnr", m.lsErr.psnr);
    row.set("ls_ssim", m.lsErr.ssim).set("ls_max_abs", m.lsErr.maxAbs);
  }
  if (m.exactMeasured) {
    row.set("exact_rmse", m.exactErr.rmse).set("exact_relmse", m.exactErr.relmse).set("exact_psnr", m.exactErr.psnr);
    row.set("exact_ssim", m.exactErr.ssim).set("exact_ls_rmse", m.exactLsErr.rmse);
    row.set("exact_ls_relmse", m.exactLsErr.relmse);
  }
}

}  // namespace

ResultRow runRow(const Measured& m, const RowContext& rows) {
  const MethodRun& r = m.run;
  const RunPlan& plan = rows.plan;
  std::string statsText;
  for (const auto& [k, v] : r.stats) statsText += (statsText.empty() ? "" : ";") + k + "=" + num(v);
  ResultRow row(runsColumns());
  row.set("scene", plan.scene.name).set("method", r.method).set("params", r.params);
  row.set("status", runStatusName(r.status)).set("reason", r.reason).set("effects", plan.effects.describe());
  row.set("passes", joined(r.passes)).set("approximations", joined(r.approximations));
  row.set("nonfinite_pixels", r.nonFinitePixels).set("method_stats", statsText);
  if (r.status == RunStatus::Success) {
    row.set("setup_ms", r.setupMs);
    row.set("frame_median_ms", r.frame.medianMs).set("frame_min_ms", r.frame.minMs).set("frame_max_ms", r.frame.maxMs);
    row.set("frame_p95_ms", r.frame.p95Ms).set("frame_p99_ms", r.frame.p99Ms);
    row.set("frame_mdape_pct", r.frame.mdapePct).set("unstable", r.frame.mdapePct > 5.0 ? "1" : "0");
  }
  setErrors(row, m);
  row.set("width", plan.width).set("height", plan.height).set("shadow_map", r.shadowMapSize).set("frames", rows.req.frames);
  row.set("reference", rows.base.referenceLabel).set("timer", rows.timer).set("renderer", rows.renderer);
  row.set("date", rows.date);
  return row;
}

std::string jobSummary(const Measured& m) {
  const MethodRun& r = m.run;
  if (r.status != RunStatus::Success) return std::string(runStatusName(r.status)) + ": " + r.reason;
  std::string s = num(r.frame.medianMs) + " ms/frame";
  if (m.measured) s += ", rmse " + num(m.finalErr.rmse) + ", psnr " + num(m.finalErr.psnr) + " dB";
  if (r.frame.mdapePct > 5.0) s += " (unstable timing)";
  return s;
}

}  // namespace vs::shootout
