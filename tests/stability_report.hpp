// The stability report's hard-case and bad-input tables. A sharded stress run computes its share of
// their rows (every shards-th, from its own shard index) beside its configurations, so the shards of
// a cluster or of `scripts/reproduce` split them; --merge assembles the rows of every shard.
#pragma once
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace vs::testing {

struct HardCaseRow {
  size_t index = 0;                // into hardCases()
  std::vector<std::string> cells;  // one per method: its L_s relMSE, "unsupported", "finite (singular)" or the failure
};

struct BadInputRow {
  size_t index = 0;  // into badInputs()
  int exitCode = 0;
  std::string message;  // vshadow's first line on stderr, the fixture folder written DIR
};

struct ReportRows {
  std::vector<HardCaseRow> hardCases;
  std::vector<BadInputRow> badInputs;

  // Adds another shard's rows; throws std::runtime_error if a row is given twice.
  void merge(const ReportRows& other);
  // Throws std::runtime_error naming the first hard case or bad input without a row.
  void checkComplete() const;
};

// The rows whose index modulo `shards` is `shard`, among the given hard cases and bad inputs (default:
// all of them), each method at its defaults with a 512² shadow map at 64x48. progress(done, total)
// counts rows.
ReportRows computeReportRows(const std::vector<std::string>& methods, int shard, int shards,
                             const std::function<void(int, int)>& progress = {});
ReportRows computeReportRows(const std::vector<std::string>& methods, int shard, int shards,
                             const std::vector<size_t>& hardCaseIndices, const std::vector<size_t>& badInputIndices,
                             const std::function<void(int, int)>& progress = {});

nlohmann::json reportRowsJson(const ReportRows& rows);
// Throws std::runtime_error if the JSON is not what reportRowsJson writes for this build's cases.
ReportRows reportRowsFromJson(const nlohmann::json& j, size_t methodCount);

// The two Markdown sections ("## Hard cases", "## Bad inputs"), rows in the order of the lists.
std::string reportRowsMarkdown(const std::vector<std::string>& methods, const ReportRows& rows);

}  // namespace vs::testing
