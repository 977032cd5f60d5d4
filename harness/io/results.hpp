// Result files: tidy CSV tables and a JSON sidecar, always written atomically (temp + rename),
// so an interrupted sweep keeps every row finished before the interruption.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace vs {

// Writes `text` to `path` through a temporary file in the same folder and a rename.
void writeFileAtomic(const std::string& path, const std::string& text);

// One row of a result table, filled by column name; the table's column list defines both the CSV
// header and the order of the fields, so no code matches values by position.
class ResultRow {
 public:
  explicit ResultRow(const std::vector<std::string>& columns) : columns_(&columns), values_(columns.size()) {}
  ResultRow& set(const std::string& column, const std::string& value);  // std::logic_error for unknown names
  ResultRow& set(const std::string& column, const char* value) { return set(column, std::string(value)); }
  ResultRow& set(const std::string& column, double value);              // formatted with num()
  ResultRow& set(const std::string& column, int value) { return set(column, std::to_string(value)); }
  ResultRow& set(const std::string& column, size_t value) { return set(column, std::to_string(value)); }
  const std::string& get(const std::string& column) const;
  const std::vector<std::string>& fields() const { return values_; }

 private:
  size_t index(const std::string& column) const;
  const std::vector<std::string>* columns_;
  std::vector<std::string> values_;
};

class CsvTable {
 public:
  // keyColumns: how many leading columns identify a row; a new row with an existing key replaces it.
  CsvTable(std::vector<std::string> header, size_t keyColumns);
  // Loads rows already in `path` so a new run adds to them. Columns are matched by name: a file
  // written before a column existed gets it empty; a file with a column this table does not know is
  // an error (std::runtime_error, one line) rather than something to overwrite.
  void loadExisting(const std::string& path);
  void upsert(const ResultRow& row);
  // Removes every row whose named columns hold the given values.
  void removeWhere(const std::vector<std::pair<std::string, std::string>>& match);
  void save(const std::string& path) const;
  const std::vector<std::vector<std::string>>& rows() const { return rows_; }
  const std::vector<std::string>& header() const { return header_; }
  static std::string format(const std::vector<std::string>& fields);
  static std::vector<std::vector<std::string>> parse(const std::string& text);

 private:
  std::vector<std::string> header_;
  size_t keyColumns_;
  std::vector<std::vector<std::string>> rows_;
};

// The columns of runs.csv and passes.csv (README "Results" describes each).
const std::vector<std::string>& runsColumns();
const std::vector<std::string>& passesColumns();
constexpr size_t kRunsKeyColumns = 3;    // scene, method, params
constexpr size_t kPassesKeyColumns = 4;  // scene, method, params, pass
// frames.csv (moving scenes): one row per measured frame of a row.
const std::vector<std::string>& framesColumns();
constexpr size_t kFramesKeyColumns = 4;  // scene, method, params, frame

// Number formatting for result files: up to 6 significant digits, "inf"/"nan" spelled out.
std::string num(double v);
// The current UTC time as ISO 8601 (2026-12-07T17:20:00Z), for meta.json and sweep state.
std::string isoDateUtc();

}  // namespace vs
