// vshadow_stress: randomized stress of every method, and the stability report.
//   vshadow_stress [--configs 10000] [--seed 1] [--method NAME ...] [--report FILE.md]
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>

#include "bad_inputs.hpp"
#include "gl_test.hpp"
#include "hard_cases.hpp"
#include "harness/metrics.hpp"
#include "harness/progress.hpp"
#include "harness/results.hpp"
#include "stress.hpp"

namespace vs {
const char* buildGitSha();
}

using namespace vs;
using namespace vs::testing;

namespace {

std::string hardCaseCell(const HardCase& hard, const std::string& methodName) {
  Scene scene = sceneFromJson(hard.json);
  auto method = createMethod(methodName);
  std::string spec = methodName + ":sm=512";
  ResolvedSpec resolved = resolveSpec(spec, glLimits());
  if (!method->unsupportedReason(scene, resolved.params).empty()) return "unsupported";
  RunOptions options;
  options.width = 64;
  options.height = 48;
  options.frames = 1;
  options.warmup = 0;
  MethodRun run = renderScene(scene, spec, options);
  if (run.status != RunStatus::Success) return "**Failure**: " + run.reason;
  size_t bad = 0;
  for (float v : run.inscatter.rgb) bad += !(std::isfinite(v) && v >= 0.0f);
  for (float v : run.final.rgb) bad += !(std::isfinite(v) && v >= 0.0f);
  if (bad) return "**" + std::to_string(bad) + " bad values**";
  if (hard.singular) return "finite (singular)";
  Reference ref = obtainReference(scene, glLimits(), options, 512, makeTempDir("report-ref"));
  return num(compareImages(run.inscatter, ref.inscatter).relmse);
}

std::string firstLine(const std::string& s) {
  auto end = s.find('\n');
  return s.substr(0, end);
}

std::string escapeCell(std::string s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vshadow_stress: randomized stress of every registered method, and the stability report"};
  StressOptions options;
  options.configs = 10000;
  std::vector<std::string> methods;
  std::string report;
  app.add_option("--configs", options.configs, "random configurations per method")->capture_default_str()->check(CLI::Range(1, 10000000));
  app.add_option("--seed", options.seed, "seed of the configuration sequence")->capture_default_str();
  app.add_option("--method", methods, "only these methods (default: all registered)");
  app.add_option("--report", report, "write the stability report (Markdown) to this file");
  CLI11_PARSE(app, argc, argv);
  if (methods.empty())
    for (const auto& info : registeredMethods()) methods.push_back(info.name);
  try {
    for (const auto& m : methods) createMethod(m);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vshadow_stress: error: %s\n", e.what());
    return 2;
  }

  std::ostringstream md;
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::string command;
  // The command as given, with the report named by its file name only (no machine paths).
  for (int i = 0; i < argc; ++i) {
    std::string arg = i ? argv[i] : "vshadow_stress";
    if (i > 0 && std::string(argv[i - 1]) == "--report") arg = arg.substr(arg.rfind('/') + 1);
    command += (i ? " " : "") + arg;
  }
  md << "# Stability report\n\nWritten by `" << command << "` on " << date << " at revision " << buildGitSha()
     << ".  \nRenderer: "
     << contextInfo().glRenderer << " (" << contextInfo().glVersion << ").\n\n";

  md << "## Randomized stress\n\nSeed " << options.seed << ", " << options.configs << " configurations per method at "
     << options.width << "x" << options.height
     << " (random camera, light type and placement, medium, phase; the light sits on the eye in ~3 % of them).\n"
     << "Worst error: L_s relMSE against the ray-marched reference, singular configurations excluded.\n\n"
     << "| method | configurations | tried | unsupported | failures | NaN | negative | worst L_s relMSE (config) |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  int problems = 0;
  for (const auto& m : methods) {
    Progress progress(1);
    progress.item(0, m + " stress");
    StressSummary s = runStress(m, options, glLimits(), [&](int done, int total) { progress.frames(done, total); });
    char line[256];
    std::snprintf(line, sizeof line, "%d configurations, %d tried, %d unsupported, %d failures, %d with NaN, %d negative, worst L_s relMSE %s (config %u)",
                  options.configs, s.tried, s.unsupported, s.failures, s.nonFinite, s.negative, num(s.worstRelmse).c_str(),
                  s.worstIndex);
    progress.finished(line);
    std::printf("%s: %s\n", m.c_str(), line);
    if (!s.firstFailure.empty()) std::printf("  first failure: %s\n", s.firstFailure.c_str());
    problems += s.failures + s.negative;
    md << "| " << m << " | " << options.configs << " | " << s.tried << " | " << s.unsupported << " | " << s.failures
       << " | " << s.nonFinite << " | " << s.negative << " | " << num(s.worstRelmse) << " (" << s.worstIndex << ") |\n";
  }

  if (!report.empty()) {
    md << "\n## Hard cases\n\nL_s relMSE against the reference at 64x48 (each method at its defaults, shadow map "
          "512); \"singular\": the light sits on the camera ray origin, where the integral diverges, so only "
          "finiteness is checked.\n\n| case |";
    for (const auto& m : methods) md << " " << m << " |";
    md << "\n|---|";
    for (size_t i = 0; i < methods.size(); ++i) md << "---|";
    md << "\n";
    for (const auto& hard : hardCases()) {
      md << "| " << hard.name << " |";
      for (const auto& m : methods) md << " " << escapeCell(hardCaseCell(hard, m)) << " |";
      md << "\n";
    }
    md << "\n## Bad inputs\n\nWhat the user sees (`vshadow` exit status and its one line on stderr; nothing is written).\n\n"
       << "| input | exit | message |\n|---|---|---|\n";
    std::string dir = makeTempDir("report-bad");
    writeBadInputFixtures(dir);
    for (const auto& bad : badInputs()) {
      std::vector<std::string> args = badInputArgs(bad, dir);
      if (std::find(args.begin(), args.end(), "--out") == args.end()) args.insert(args.end(), {"--out", dir + "/out"});
      CommandResult r = runVshadow(args);
      std::string message = firstLine(r.err);
      auto pos = message.find(dir);
      while (pos != std::string::npos) {
        message.replace(pos, dir.size(), "DIR");
        pos = message.find(dir);
      }
      md << "| " << bad.what << " | " << r.exitCode << " | `" << escapeCell(message) << "` |\n";
    }
    writeFileAtomic(report, md.str());
    std::printf("report: %s\n", report.c_str());
  }
  return problems > 0 ? 1 : 0;
}
