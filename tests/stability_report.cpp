#include "stability_report.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "bad_inputs.hpp"
#include "gl_test.hpp"
#include "hard_cases.hpp"
#include "stress.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/io/results.hpp"

namespace vs::testing {

namespace {
using json = nlohmann::json;

std::string hardCaseCell(const HardCase& hard, const std::string& methodName, const std::string& referenceCache) {
  Scene scene = sceneFromJson(hard.json);
  auto method = createMethod(methodName);
  std::string spec = methodName + ":sm=512";
  ResolvedSpec resolved = resolveSpec(spec, glLimits());
  if (!method->unsupportedReason(scene, resolved.params).empty()) {
    // A point-light method meets the area-light cases behind the per-VPL wrapper (as the tests do).
    std::string wrapped = spec + ":vpls=" + std::to_string(kHardCaseVpls);
    if (!isAreaLight(scene.light.type) ||
        !unsupportedReason(scene, *method, resolveSpec(wrapped, glLimits()).params).empty())
      return "unsupported";
    spec = wrapped;
  }
  RunOptions options = RunOptions::singleFrame(64, 48);
  MethodRun run = renderScene(scene, spec, options);
  if (run.status != RunStatus::Success) return "**Failure**: " + run.reason;
  size_t bad = 0;
  for (float v : run.inscatter.rgb) bad += !(std::isfinite(v) && v >= 0.0f);
  for (float v : run.final.rgb) bad += !(std::isfinite(v) && v >= 0.0f);
  if (bad) return "**" + std::to_string(bad) + " bad values**";
  if (hard.singular) return "finite (singular)";
  // The case's reference is rendered once for every method (the cache), not once per method.
  Reference ref = obtainReference(scene, glLimits(), options, 512, referenceCache);
  return num(compareImages(run.inscatter, ref.inscatter).relmse);
}

std::string firstLine(const std::string& s) { return s.substr(0, s.find('\n')); }

std::string escapeCell(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::vector<size_t> allIndices(size_t n) {
  std::vector<size_t> v(n);
  std::iota(v.begin(), v.end(), size_t(0));
  return v;
}

template <class Row>
void mergeRows(std::vector<Row>& into, const std::vector<Row>& from, const char* what) {
  for (const Row& row : from) {
    if (std::any_of(into.begin(), into.end(), [&](const Row& r) { return r.index == row.index; }))
      throw std::runtime_error(std::string(what) + " " + std::to_string(row.index) + " is in two shards");
    into.push_back(row);
  }
  std::sort(into.begin(), into.end(), [](const Row& a, const Row& b) { return a.index < b.index; });
}
}  // namespace

void ReportRows::merge(const ReportRows& other) {
  mergeRows(hardCases, other.hardCases, "hard case");
  mergeRows(badInputs, other.badInputs, "bad input");
}

void ReportRows::checkComplete() const {
  const auto& cases = testing::hardCases();
  const auto& inputs = testing::badInputs();
  for (size_t i = 0; i < cases.size(); ++i)
    if (std::none_of(hardCases.begin(), hardCases.end(), [&](const HardCaseRow& r) { return r.index == i; }))
      throw std::runtime_error("no shard has the row of hard case '" + cases[i].name + "'");
  for (size_t i = 0; i < inputs.size(); ++i)
    if (std::none_of(badInputs.begin(), badInputs.end(), [&](const BadInputRow& r) { return r.index == i; }))
      throw std::runtime_error("no shard has the row of bad input '" + inputs[i].name + "'");
}

ReportRows computeReportRows(const std::vector<std::string>& methods, int shard, int shards,
                             const std::function<void(int, int)>& progress) {
  return computeReportRows(methods, shard, shards, allIndices(hardCases().size()), allIndices(badInputs().size()),
                           progress);
}

ReportRows computeReportRows(const std::vector<std::string>& methods, int shard, int shards,
                             const std::vector<size_t>& hardCaseIndices, const std::vector<size_t>& badInputIndices,
                             const std::function<void(int, int)>& progress) {
  shards = std::max(shards, 1);
  auto mine = [&](size_t index) { return int(index % size_t(shards)) == shard; };
  int total = 0, done = 0;
  for (size_t index : hardCaseIndices) total += mine(index);
  for (size_t index : badInputIndices) total += mine(index);
  auto step = [&] {
    if (progress) progress(++done, total);
  };
  ReportRows rows;
  const std::string referenceCache = makeTempDir("report-ref");
  for (size_t index : hardCaseIndices) {
    if (!mine(index)) continue;
    HardCaseRow row{index, {}};
    for (const auto& m : methods) row.cells.push_back(hardCaseCell(hardCases().at(index), m, referenceCache));
    rows.hardCases.push_back(std::move(row));
    step();
  }
  const std::string dir = makeTempDir("report-bad");
  writeBadInputFixtures(dir);
  for (size_t index : badInputIndices) {
    if (!mine(index)) continue;
    std::vector<std::string> args = badInputArgs(badInputs().at(index), dir);
    if (std::find(args.begin(), args.end(), "--out") == args.end()) args.insert(args.end(), {"--out", dir + "/out"});
    CommandResult r = runVshadow(args);
    std::string message = firstLine(r.err);
    for (auto pos = message.find(dir); pos != std::string::npos; pos = message.find(dir)) message.replace(pos, dir.size(), "DIR");
    rows.badInputs.push_back({index, r.exitCode, message});
    step();
  }
  return rows;
}

json reportRowsJson(const ReportRows& rows) {
  json j = {{"hard_cases", json::array()}, {"bad_inputs", json::array()}};
  for (const auto& r : rows.hardCases)
    j["hard_cases"].push_back({{"index", r.index}, {"case", hardCases().at(r.index).name}, {"cells", r.cells}});
  for (const auto& r : rows.badInputs)
    j["bad_inputs"].push_back(
        {{"index", r.index}, {"input", badInputs().at(r.index).name}, {"exit", r.exitCode}, {"message", r.message}});
  return j;
}

ReportRows reportRowsFromJson(const json& j, size_t methodCount) {
  ReportRows rows;
  for (const auto& h : j.at("hard_cases")) {
    HardCaseRow row{h.at("index").get<size_t>(), h.at("cells").get<std::vector<std::string>>()};
    std::string name = h.at("case").get<std::string>();
    if (row.index >= hardCases().size() || hardCases()[row.index].name != name)
      throw std::runtime_error("hard case '" + name + "' is not this build's case " + std::to_string(row.index));
    if (row.cells.size() != methodCount)
      throw std::runtime_error("hard case '" + name + "' has " + std::to_string(row.cells.size()) + " cells for " +
                               std::to_string(methodCount) + " methods");
    rows.hardCases.push_back(std::move(row));
  }
  for (const auto& b : j.at("bad_inputs")) {
    BadInputRow row{b.at("index").get<size_t>(), b.at("exit").get<int>(), b.at("message").get<std::string>()};
    std::string name = b.at("input").get<std::string>();
    if (row.index >= badInputs().size() || badInputs()[row.index].name != name)
      throw std::runtime_error("bad input '" + name + "' is not this build's input " + std::to_string(row.index));
    rows.badInputs.push_back(std::move(row));
  }
  return rows;
}

std::string reportRowsMarkdown(const std::vector<std::string>& methods, const ReportRows& rows) {
  std::ostringstream md;
  md << "## Hard cases\n\nL_s relMSE against the reference at 64x48 (each method at its defaults, shadow map "
        "512); \"singular\": the light sits on the camera ray origin, where the integral diverges, so only "
        "finiteness is checked.\n\n| case |";
  for (const auto& m : methods) md << " " << m << " |";
  md << "\n|---|";
  for (size_t i = 0; i < methods.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& row : rows.hardCases) {
    md << "| " << hardCases().at(row.index).name << " |";
    for (const auto& cell : row.cells) md << " " << escapeCell(cell) << " |";
    md << "\n";
  }
  md << "\n## Bad inputs\n\nWhat the user sees (`vshadow` exit status and its one line on stderr; nothing is written).\n\n"
     << "| input | exit | message |\n|---|---|---|\n";
  for (const auto& row : rows.badInputs)
    md << "| " << badInputs().at(row.index).what << " | " << row.exitCode << " | `" << escapeCell(row.message) << "` |\n";
  return md.str();
}

}  // namespace vs::testing
