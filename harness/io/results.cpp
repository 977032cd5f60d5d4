#include "harness/io/results.hpp"

#include <ctime>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace vs {

void writeFileAtomic(const std::string& path, const std::string& text) {
  auto slash = path.rfind('/');
  std::string dir = slash == std::string::npos ? "." : path.substr(0, slash);
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  std::string tmp = dir + "/." + base + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + path + " (cannot create a file in " + dir + ")");
    out << text;
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot write " + path + " (write failed)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write " + path + " (rename failed)");
  }
}

const std::vector<std::string>& runsColumns() {
  static const std::vector<std::string> columns = {
      "scene", "method", "params", "status", "reason", "effects", "passes", "approximations", "series", "setup_ms",
      "frame_median_ms", "frame_min_ms", "frame_max_ms", "frame_p95_ms", "frame_p99_ms", "frame_mdape_pct", "unstable", "rounds", "frame_round_min_ms",
      "frame_round_max_ms", "rmse", "relmse", "psnr",
      "ssim", "max_abs", "max_abs_x", "max_abs_y", "ls_rmse", "ls_relmse", "ls_psnr", "ls_ssim", "ls_max_abs",
      "nonfinite_pixels", "method_stats", "scatter_ms", "scatter_round_min_ms", "scatter_round_max_ms",
      "calibration_drift_pct", "calibration_shift_pct", "disturbed", "disturbed_retries",
      "eq_error_against", "eq_uniform_steps", "eq_uniform_ms", "eq_uniform_round_min_ms", "eq_uniform_round_max_ms",
      "speedup_eq_uniform", "speedup_eq_uniform_round_min", "speedup_eq_uniform_round_max",
      "equal_time_ls_rmse_uniform", "eq_equiangular_steps", "eq_equiangular_ms", "eq_equiangular_round_min_ms",
      "eq_equiangular_round_max_ms", "speedup_eq_equiangular", "speedup_eq_equiangular_round_min",
      "speedup_eq_equiangular_round_max", "equal_time_ls_rmse_equiangular", "exact_rmse", "exact_relmse", "exact_psnr",
      "exact_ssim", "exact_ls_rmse", "exact_ls_relmse", "seq_frames", "seq_ls_rmse_mean", "seq_ls_rmse_max",
      "seq_ls_relmse_mean", "seq_ls_relmse_max", "temporal_ls_rmse", "temporal_ls_rel", "width", "height", "shadow_map", "frames", "reference", "timer", "renderer", "date"};
  return columns;
}

const std::vector<std::string>& framesColumns() {
  static const std::vector<std::string> columns = {"scene", "method", "params", "frame", "time_s", "frame_ms",
                                                   "ls_rmse", "ls_relmse", "pass_ms", "timer", "renderer"};
  return columns;
}

const std::vector<std::string>& passesColumns() {
  static const std::vector<std::string> columns = {"scene",  "method",    "params", "pass",         "median_ms",
                                                   "min_ms", "max_ms",    "p95_ms", "p99_ms", "mdape_pct", "frames", "rounds",
                                                   "round_min_ms", "round_max_ms", "timer", "renderer"};
  return columns;
}

size_t ResultRow::index(const std::string& column) const {
  for (size_t i = 0; i < columns_->size(); ++i)
    if ((*columns_)[i] == column) return i;
  throw std::logic_error("result table has no column '" + column + "'");
}

ResultRow& ResultRow::set(const std::string& column, const std::string& value) {
  values_[index(column)] = value;
  return *this;
}

ResultRow& ResultRow::set(const std::string& column, double value) { return set(column, num(value)); }

const std::string& ResultRow::get(const std::string& column) const { return values_[index(column)]; }

std::string num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

CsvTable::CsvTable(std::vector<std::string> header, size_t keyColumns)
    : header_(std::move(header)), keyColumns_(keyColumns) {}

std::string CsvTable::format(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) {
    const std::string& f = fields[i];
    if (i) line += ',';
    if (f.find_first_of(",\"\n\r") != std::string::npos) {
      line += '"';
      for (char c : f) line += c == '"' ? std::string("\"\"") : std::string(1, c);
      line += '"';
    } else {
      line += f;
    }
  }
  return line + "\n";
}

std::vector<std::vector<std::string>> CsvTable::parse(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, any = false;
  for (size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
      continue;
    }
    if (c == '"') {
      quoted = true;
      any = true;
    } else if (c == ',') {
      row.push_back(field);
      field.clear();
      any = true;
    } else if (c == '\n') {
      row.push_back(field);
      rows.push_back(row);
      row.clear();
      field.clear();
      any = false;
    } else if (c != '\r') {
      field += c;
      any = true;
    }
  }
  if (any) {
    row.push_back(field);
    rows.push_back(row);
  }
  return rows;
}

void CsvTable::loadExisting(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;
  std::stringstream ss;
  ss << in.rdbuf();
  auto rows = parse(ss.str());
  if (rows.empty()) return;
  // Each column of the file, by name, to its place in this table.
  std::vector<size_t> place;
  for (const auto& name : rows[0]) {
    auto it = std::find(header_.begin(), header_.end(), name);
    if (it == header_.end())
      throw std::runtime_error(path + " has a column '" + name + "' this version does not write; write to another --out folder");
    place.push_back(size_t(it - header_.begin()));
  }
  for (size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].size() != place.size()) continue;
    std::vector<std::string> row(header_.size());
    for (size_t c = 0; c < place.size(); ++c) row[place[c]] = rows[i][c];
    rows_.push_back(std::move(row));
  }
}

void CsvTable::upsert(const ResultRow& result) {
  const std::vector<std::string>& row = result.fields();
  if (row.size() != header_.size()) throw std::logic_error("CSV row has the wrong number of fields");
  for (auto& existing : rows_) {
    bool same = true;
    for (size_t k = 0; k < keyColumns_ && same; ++k) same = existing[k] == row[k];
    if (same) {
      existing = row;
      return;
    }
  }
  rows_.push_back(row);
}

void CsvTable::removeWhere(const std::vector<std::pair<std::string, std::string>>& match) {
  std::vector<size_t> columns;
  for (const auto& m : match) {
    auto it = std::find(header_.begin(), header_.end(), m.first);
    if (it == header_.end()) throw std::logic_error("result table has no column '" + m.first + "'");
    columns.push_back(size_t(it - header_.begin()));
  }
  std::vector<std::vector<std::string>> kept;
  for (auto& r : rows_) {
    bool same = true;
    for (size_t k = 0; k < match.size() && same; ++k) same = r[columns[k]] == match[k].second;
    if (!same) kept.push_back(r);
  }
  rows_ = std::move(kept);
}

void CsvTable::save(const std::string& path) const {
  std::string text = format(header_);
  for (const auto& r : rows_) text += format(r);
  writeFileAtomic(path, text);
}

std::string isoDateUtc() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

}  // namespace vs
