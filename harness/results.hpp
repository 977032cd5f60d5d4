// Result files: tidy CSV tables and a JSON sidecar, always written atomically (temp + rename),
// so an interrupted sweep keeps every row finished before the interruption.
#pragma once
#include <string>
#include <vector>

namespace vs {

// Writes `text` to `path` through a temporary file in the same folder and a rename.
void writeFileAtomic(const std::string& path, const std::string& text);

class CsvTable {
 public:
  // keyColumns: how many leading columns identify a row; a new row with an existing key replaces it.
  CsvTable(std::vector<std::string> header, size_t keyColumns);
  // Loads rows already in `path` so a new run adds to them. A file with another header is an error
  // (std::runtime_error, one line) rather than something to overwrite.
  void loadExisting(const std::string& path);
  void upsert(const std::vector<std::string>& row);
  // Removes every row whose first `n` columns equal those of `prefix`.
  void removeMatching(const std::vector<std::string>& prefix, size_t n);
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

std::vector<std::string> runsCsvHeader();
std::vector<std::string> passesCsvHeader();

// Number formatting for result files: up to 6 significant digits, "inf"/"nan" spelled out.
std::string num(double v);

}  // namespace vs
