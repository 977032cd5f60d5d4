// vshadow_stress: randomized stress of every method, and the stability report.
//   vshadow_stress [--configs 10000] [--seed 1] [--method NAME ...] [--report FILE.md]
//   On a cluster: vshadow_stress --shard K/N --partial K.json on every node, then
//   vshadow_stress --merge 0.json ... --report FILE.md (each shard also computes its share of the
//   report's hard-case and bad-input rows; the merge assembles them)
//   vshadow_stress --print-config N [--seed S] > config.json: configuration N as a scene file
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gl_test.hpp"
#include "harness/cli/progress.hpp"
#include "harness/io/results.hpp"
#include "stability_report.hpp"
#include "stress.hpp"

namespace vs {
const char* buildGitSha();
}

using namespace vs;
using namespace vs::testing;
using json = nlohmann::json;

namespace {

std::string secondsText(double s) {
  char text[32];
  std::snprintf(text, sizeof text, s < 100 ? "%.1f" : "%.0f", s);
  return text;
}

// Wall-clock seconds of a stress run (shards: summed): all of it, and the reference's renders.
struct StressTimes {
  double total = 0, reference = 0;
  double rows = 0;  // the hard-case and bad-input rows
};

json summaryJson(const StressSummary& s) {
  return {{"method", s.method},         {"tried", s.tried},           {"unsupported", s.unsupported}, {"through_vpls", s.throughVpls},
          {"failures", s.failures},     {"nonfinite", s.nonFinite},   {"negative", s.negative},
          {"worst_relmse", s.worstRelmse}, {"worst_index", s.worstIndex}, {"first_failure", s.firstFailure},
          {"first_failure_index", s.firstFailureIndex}, {"most_negative", s.mostNegative},
          {"most_negative_index", s.mostNegativeIndex}, {"seconds", s.seconds}};
}

StressSummary summaryFromJson(const json& j) {
  StressSummary s;
  s.method = j.at("method").get<std::string>();
  s.tried = j.at("tried").get<int>();
  s.unsupported = j.at("unsupported").get<int>();
  s.throughVpls = j.value("through_vpls", 0);
  s.failures = j.at("failures").get<int>();
  s.nonFinite = j.at("nonfinite").get<int>();
  s.negative = j.at("negative").get<int>();
  s.worstRelmse = j.at("worst_relmse").get<double>();
  s.worstIndex = j.at("worst_index").get<uint32_t>();
  s.firstFailure = j.at("first_failure").get<std::string>();
  s.firstFailureIndex = j.at("first_failure_index").get<uint32_t>();
  s.mostNegative = j.at("most_negative").get<double>();
  s.mostNegativeIndex = j.at("most_negative_index").get<uint32_t>();
  s.seconds = j.at("seconds").get<double>();
  return s;
}

// Merges shard files written with --partial: the same seed, configurations, size, shard count and
// methods, every shard exactly once. Throws std::runtime_error naming the file at fault.
std::vector<StressSummary> mergePartials(const std::vector<std::string>& files, StressOptions& options,
                                         std::vector<std::string>& methods, std::string& revision,
                                         StressTimes& times, ReportRows& rows) {
  std::vector<StressSummary> merged;
  std::vector<bool> seen;
  for (const std::string& file : files) {
    std::ifstream in(file);
    if (!in) throw std::runtime_error(file + ": cannot read");
    json j;
    try {
      j = json::parse(in);
      int shards = j.at("shards").get<int>(), shard = j.at("shard").get<int>();
      std::vector<std::string> names;
      for (const auto& m : j.at("methods")) names.push_back(m.at("method").get<std::string>());
      if (merged.empty()) {
        options.seed = j.at("seed").get<uint32_t>();
        options.configs = j.at("configs").get<int>();
        options.width = j.at("width").get<int>();
        options.height = j.at("height").get<int>();
        options.shards = shards;
        methods = names;
        revision = j.at("revision").get<std::string>();
        seen.assign(size_t(std::max(shards, 1)), false);
        for (const auto& m : j.at("methods")) merged.push_back(summaryFromJson(m));
      } else {
        if (j.at("seed").get<uint32_t>() != options.seed || j.at("configs").get<int>() != options.configs ||
            j.at("width").get<int>() != options.width || j.at("height").get<int>() != options.height ||
            shards != options.shards || names != methods)
          throw std::runtime_error("its seed, configurations, size, shard count or methods differ from " + files[0] + "'s");
        if (j.at("revision").get<std::string>() != revision)
          throw std::runtime_error("written at revision " + j.at("revision").get<std::string>() + ", " + files[0] +
                                   " at " + revision);
        for (size_t m = 0; m < merged.size(); ++m) merged[m].merge(summaryFromJson(j.at("methods")[m]));
      }
      times.reference += j.at("reference_seconds").get<double>();
      times.total += j.at("seconds").get<double>();
      times.rows += j.at("rows_seconds").get<double>();
      rows.merge(reportRowsFromJson(j.at("rows"), methods.size()));
      if (shard < 0 || shard >= options.shards) throw std::runtime_error("shard " + std::to_string(shard) + " out of range");
      if (seen[size_t(shard)]) throw std::runtime_error("shard " + std::to_string(shard) + " given twice");
      seen[size_t(shard)] = true;
    } catch (const json::exception& e) {
      throw std::runtime_error(file + ": not a stress shard file (" + std::string(e.what()) + ")");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(file + ": " + e.what());
    }
  }
  for (size_t k = 0; k < seen.size(); ++k)
    if (!seen[k]) throw std::runtime_error("shard " + std::to_string(k) + "/" + std::to_string(options.shards) + " is missing");
  return merged;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vshadow_stress: randomized stress of every registered method, and the stability report"};
  StressOptions options;
  options.configs = 10000;
  std::vector<std::string> methods, mergeFiles;
  std::string report, partial, shardText;
  app.add_option("--configs", options.configs, "random configurations per method")->capture_default_str()->check(CLI::Range(1, 10000000));
  app.add_option("--seed", options.seed, "seed of the configuration sequence")->capture_default_str();
  app.add_option("--method", methods, "only these methods (default: all registered)");
  app.add_option("--report", report, "write the stability report (Markdown) to this file");
  app.add_option("--shard", shardText, "K/N: run only the configurations whose index modulo N is K (write it with --partial)");
  app.add_option("--partial", partial, "write this run's summaries to FILE.json, to be merged with --merge");
  int64_t printConfig = -1;
  app.add_option("--print-config", printConfig, "print configuration N of the seed's sequence as a scene file and exit")
      ->check(CLI::Range(int64_t(0), int64_t(UINT32_MAX)));
  app.add_option("--merge", mergeFiles, "merge the --partial files of every shard instead of running (then --report)")
      ->expected(1, -1);
  CLI11_PARSE(app, argc, argv);
  if (printConfig >= 0) {
    std::printf("%s\n", randomStressSceneJson(options.seed, uint32_t(printConfig)).c_str());
    return 0;
  }
  try {
    if (!shardText.empty()) {
      size_t slash = shardText.find('/');
      size_t used = 0, usedN = 0;
      if (slash == std::string::npos) throw std::runtime_error("--shard " + shardText + ": expected K/N");
      options.shard = std::stoi(shardText.substr(0, slash), &used);
      options.shards = std::stoi(shardText.substr(slash + 1), &usedN);
      if (used != slash || usedN != shardText.size() - slash - 1 || options.shards < 1 || options.shard < 0 ||
          options.shard >= options.shards)
        throw std::runtime_error("--shard " + shardText + ": expected K/N with 0 <= K < N");
    }
    if (options.shards > 1 && !report.empty())
      throw std::runtime_error("--report with --shard would cover part of the configurations: write --partial, then --merge");
    if (!mergeFiles.empty() && (!shardText.empty() || !methods.empty()))
      throw std::runtime_error("--merge takes its methods and shards from the files: no --shard or --method");
    if (methods.empty() && mergeFiles.empty())
      for (const auto& info : registeredMethods()) methods.push_back(info.name);
    for (const auto& m : methods) createMethod(m);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vshadow_stress: error: %s\n", e.what());
    return 2;
  }

  std::vector<StressSummary> summaries;
  std::string revision = buildGitSha();
  StressTimes times;
  ReportRows rows;
  if (!mergeFiles.empty()) {
    try {
      summaries = mergePartials(mergeFiles, options, methods, revision, times, rows);
      if (!report.empty()) rows.checkComplete();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "vshadow_stress: error: %s\n", e.what());
      return 2;
    }
  } else {
    Progress progress(1);
    progress.item(0, "stress, " + std::to_string(methods.size()) + " methods" +
                         (options.shards > 1 ? ", shard " + shardText : ""));
    auto start = std::chrono::steady_clock::now();
    summaries = runStress(methods, options, glLimits(), [&](int done, int total) { progress.frames(done, total); },
                          &times.reference);
    times.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.finished("done");
    // The report's other rows: this shard's share when it is to be merged, all of them for a report.
    if (!partial.empty() || !report.empty()) {
      Progress rowsProgress(1);
      rowsProgress.item(0, "hard cases and bad inputs" + (options.shards > 1 ? ", shard " + shardText : std::string()));
      start = std::chrono::steady_clock::now();
      rows = computeReportRows(methods, options.shard, options.shards,
                               [&](int done, int total) { rowsProgress.frames(done, total); });
      times.rows = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      rowsProgress.finished("done");
    }
  }
  int problems = 0;
  for (const auto& s : summaries) {
    std::printf("%s: %d tried (%d through VPLs), %d unsupported, %d failures, %d with NaN, %d negative, worst L_s relMSE %s (config %u)\n",
                s.method.c_str(), s.tried, s.throughVpls, s.unsupported, s.failures, s.nonFinite, s.negative,
                num(s.worstRelmse).c_str(), s.worstIndex);
    if (!s.firstFailure.empty()) std::printf("  first failure: %s\n", s.firstFailure.c_str());
    if (s.negative > 0) std::printf("  most negative value: %s (config %u)\n", num(s.mostNegative).c_str(), s.mostNegativeIndex);
    problems += s.failures + s.negative;
  }
  if (!partial.empty()) {
    json j = {{"seed", options.seed},     {"configs", options.configs}, {"width", options.width},
              {"height", options.height}, {"shard", options.shard},     {"shards", options.shards},
              {"revision", revision},     {"renderer", contextInfo().glRenderer},
              {"seconds", times.total},   {"reference_seconds", times.reference},
              {"rows_seconds", times.rows}, {"rows", reportRowsJson(rows)},
              {"methods", json::array()}};
    for (const auto& s : summaries) j["methods"].push_back(summaryJson(s));
    writeFileAtomic(partial, j.dump(1) + "\n");
    std::printf("partial: %s\n", partial.c_str());
  }

  std::ostringstream md;
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::string command;
  // The command as given, with files named by their file names only (no machine paths).
  bool fileArgs = false;
  for (int i = 0; i < argc; ++i) {
    std::string arg = i ? argv[i] : "vshadow_stress";
    if (arg.rfind("--", 0) == 0) fileArgs = arg == "--report" || arg == "--merge" || arg == "--partial";
    else if (i > 0 && fileArgs) arg = arg.substr(arg.rfind('/') + 1);
    command += (i ? " " : "") + arg;
  }
  md << "# Stability report\n\nWritten by `" << command << "` on " << date << " at revision " << revision
     << ".  \nRenderer: "
     << contextInfo().glRenderer << " (" << contextInfo().glVersion << ").\n\n";

  md << "## Randomized stress\n\nSeed " << options.seed << ", " << options.configs << " configurations per method at "
     << options.width << "x" << options.height
     << " (random camera, light type and placement, medium, phase, volume data in ~30 %; the light sits on the eye in ~3 % of them)"
     << (options.shards > 1 ? ", run in " + std::to_string(options.shards) + " shards" : std::string()) << ".\n"
     << "Worst error: L_s relMSE against the ray-marched reference (its parameters for the configuration's effects, "
        "at most "
     << kStressReferenceSteps << " steps, " << kStressAreaReferenceSteps << " for area lights, shadow maps " << kStressShadowMap << "² like the methods', whose own maps (`res`) are at most "
     << kStressShadowMap << "² too), singular configurations excluded; "
        "`vshadow_stress --print-config N --seed "
     << options.seed << " > config.json` writes configuration N as a scene for `vshadow run --scene config.json`.\n\n"
     << "| method | configurations | tried | of which through VPLs | unsupported | failures | NaN | negative | worst L_s relMSE (config) | time (s) |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  double methodSeconds = 0;
  for (const auto& s : summaries) {
    md << "| " << s.method << " | " << options.configs << " | " << s.tried << " | " << s.throughVpls << " | "
       << s.unsupported << " | " << s.failures
       << " | " << s.nonFinite << " | " << s.negative << " | " << num(s.worstRelmse) << " (" << s.worstIndex << ") | "
       << secondsText(s.seconds) << " |\n";
    methodSeconds += s.seconds;
  }
  md << "\nWall-clock time" << (options.shards > 1 ? " summed over the shards" : "") << ": " << secondsText(times.total)
     << " s, of which the methods' runs " << secondsText(methodSeconds) << " s (the table's last column), the reference's "
     << secondsText(times.reference) << " s, and the scenes' set-up the rest.\n";

  if (!report.empty()) {
    md << "Hard cases and bad inputs: " << secondsText(times.rows) << " s"
       << (options.shards > 1 ? " summed over the shards, each of which has its share of their rows" : "") << ".\n\n"
       << reportRowsMarkdown(methods, rows);
    writeFileAtomic(report, md.str());
    std::printf("report: %s\n", report.c_str());
  }
  return problems > 0 ? 1 : 0;
}
