// vshadow report: one self-contained HTML page over a results folder (a shootout, a merged sweep,
// an equal-quality or animated run, or a folder of such folders): the error-against-time chart,
// the rows as a table, image comparisons, pass breakdowns, work counters and provenance.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace vs {

struct ReportRequest {
  std::string dir;  // a result folder, or a folder holding result folders (one per scene)
  std::string out;  // the page; empty: DIR/report.html
  // Images are embedded in the page (data: URIs) while their total stays within this many
  // megabytes, the rest referenced by relative path; 0: every image referenced.
  double embedImagesMb = 0;
};

// Where the page goes by default.
std::string defaultReportPath(const std::string& dir);

// The data the page embeds: every result folder found in `dir` (itself when it holds runs.csv,
// else its sub-folders that do, searched a few levels deep), grouped by scene. Every field keeps
// its text from the CSV. Image, video and folder paths are relative to `pageDir`, the folder the
// page is written to. Missing or malformed input is a UsageError (one line).
nlohmann::json collectReportData(const std::string& dir, const std::string& pageDir);

// Replaces image paths in `data` (relative to `pageDir`) by data: URIs, in the page's order,
// while their total size stays within `budgetBytes`; returns how many were embedded.
size_t embedImages(nlohmann::json& data, const std::string& pageDir, size_t budgetBytes);

// The HTML page: the template with the page's CSS and JavaScript and `data` embedded.
std::string renderReportPage(const nlohmann::json& data);

// Exit status: 0 written; 2 bad input (one line on stderr, nothing written); 1 other failures.
int reportCommand(const ReportRequest& request);

}  // namespace vs
