// vshadow: benchmark suite for real-time volumetric shadows.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "harness/cli/app.hpp"
#include "harness/cli/merge.hpp"
#include "harness/cli/sweep.hpp"
#include "harness/report/report.hpp"
#include "harness/viewer/viewer.hpp"
#include "methods/registry.hpp"

namespace {

// Every subcommand's request and, where dispatch needs it, its parsed state.
struct Commands {
  vs::RunRequest run, shootout;
  std::string sweepFile;
  vs::SweepOptions sweepOptions;
  vs::MergeRequest mergeRequest;
  vs::ReportRequest reportRequest;
  vs::ViewRequest viewRequest;
  CLI::App *plan = nullptr, *sweepRun = nullptr, *sweepReference = nullptr, *merge = nullptr, *report = nullptr,
           *view = nullptr;
};

// The options `run` and `shootout` share.
void addCommonOptions(CLI::App* cmd, vs::RunRequest& r) {
  cmd->add_option("--scene", r.scene, "built-in scene name or path to a scene .json")->required();
  cmd->add_option("--size", r.size, "image size WxH")->capture_default_str();
  cmd->add_option("--out", r.out, "output folder (rows already there are kept)")->capture_default_str();
  cmd->add_option("--frames", r.frames, "measured frames per method")->capture_default_str()->check(CLI::Range(1, 100000));
  cmd->add_option("--warmup", r.warmup, "warm-up frames per method")->capture_default_str()->check(CLI::Range(0, 100000));
  cmd->add_option("--min-time", r.minTimeMs,
                  "measure only as many of --frames as fill this many ms at the last warm-up frame's time (at "
                  "least one; 0: all of them; needs --warmup of at least 1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e7));
  cmd->add_option("--rounds", r.rounds,
                  "interleaved rounds: every row runs once per round, in turn, and its timings are the medians "
                  "over the rounds (their range in the *_round_min/max columns)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--drift-threshold", r.driftThresholdPct,
                  "a calibration workload is timed before the first and after every round of a row; a round "
                  "during which it moved more than this many percent is disturbed and run again (0: no check)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--drift-retries", r.driftRetries, "most repeats of a disturbed round")
      ->capture_default_str()
      ->check(CLI::Range(0, 10));
  cmd->add_option("--seed", r.seed, "seed for jitter and random scenes")->capture_default_str()->check(CLI::Range(0LL, 4294967295LL));
  cmd->add_option("--timer", r.timer, "timing strategy")->capture_default_str()->check(CLI::IsMember({"auto", "gpu", "wall"}));
  cmd->add_option("--pin-threads", r.pinThreads,
                  "pin the GL driver's worker threads one per CPU (auto: when passes are timed by the wall clock, "
                  "i.e. the driver is a CPU rasterizer whose idle workers the scheduler would otherwise place anew "
                  "for every pass)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd->add_option("--cache", r.cacheDir, "reference cache folder (default $VSHADOW_CACHE or ~/.cache/vshadow)");
  cmd->add_option("--reference", r.referenceSpec,
                  "method spec of the reference (default: the ray-marched reference), or 'exact' for the "
                  "exact-visibility ground truth (small images)");
  cmd->add_flag("--exact", r.exact, "also report errors against the exact-visibility ground truth (small images)");
  cmd->add_option("--exact-steps", r.exactSteps, "ground-truth samples per camera ray")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_flag("--no-reference", r.noReference, "skip the reference and the error metrics");
  cmd->add_flag("--no-images", r.noImages, "write no images");
  cmd->add_flag("--equal-quality", r.equalQuality,
                "add the equal-quality columns: brute-force ray marching (uniform and equiangular) bisected on its "
                "step count to each row's L_s error, and its error at each row's scattering time; errors are "
                "taken against the exact-visibility ground truth (computed on the CPU, cached) where it models "
                "the scene");
  cmd->add_flag("--strict-gl", r.strictGl, "treat any GL debug error as fatal");
}

void addRunAndShootout(CLI::App& app, Commands& c) {
  auto* runCmd = app.add_subcommand("run", "run the given methods on one scene");
  addCommonOptions(runCmd, c.run);
  runCmd->add_option("--method", c.run.methods, "method spec name:key=value:... (repeatable)")->required();
  auto* shootCmd = app.add_subcommand(
      "shootout", "run every method that supports the scene at its ladder of quality settings against the reference");
  addCommonOptions(shootCmd, c.shootout);
  shootCmd->add_option("--method", c.shootout.methods, "only these methods (by name; repeatable)");
  shootCmd->add_option("--rungs", c.shootout.rungs,
                       "only these rungs of each ladder: all, first, middle (index size/2), last or a 0-based index "
                       "(comma-separated or repeatable; default all)")
      ->delimiter(',');

}

void addSweepCommands(CLI::App& app, Commands& c) {
  // Sweeps (harness/cli/sweep.hpp) and merging their shards (harness/cli/merge.hpp).
  auto* sweepCmd = app.add_subcommand("sweep", "plan or run a sweep file shard by shard (README \"Sweeps\")");
  sweepCmd->require_subcommand(1);
  c.plan = sweepCmd->add_subcommand("plan", "print the shards of a sweep file: index, stable id, methods");
  c.plan->add_option("FILE", c.sweepFile, "sweep file (.json)")->required();
  c.plan->add_option("--out", c.sweepOptions.out, "also write OUT/sweep.json, the normalized sweep the shards run from");
  c.plan->add_flag("--pending", c.sweepOptions.pendingOnly, "only the shards not finished in --out");
  c.sweepRun = sweepCmd->add_subcommand("run", "run the shards into OUT/<id>/ in order, skipping finished ones");
  c.sweepRun->add_option("FILE", c.sweepFile, "sweep file (.json)")->required();
  c.sweepRun->add_option("OUT", c.sweepOptions.out, "the sweep's folder")->required();
  c.sweepRun->add_option("--shard", c.sweepOptions.only, "only this shard (id or index; repeatable)");
  c.sweepRun->add_option("--cache", c.sweepOptions.cacheDir, "reference cache folder (default $VSHADOW_CACHE or ~/.cache/vshadow)");
  c.sweepReference = sweepCmd->add_subcommand("reference", "fill the reference cache for one scene of a sweep");
  c.sweepReference->add_option("FILE", c.sweepFile, "sweep file (.json)")->required();
  c.sweepReference->add_option("--scene", c.sweepOptions.scene, "the scene (as named in the sweep file)")->required();
  c.sweepReference->add_option("--cache", c.sweepOptions.cacheDir, "reference cache folder (default $VSHADOW_CACHE or ~/.cache/vshadow)");
}

void addMergeAndReport(CLI::App& app, Commands& c) {
  c.mergeRequest.commandLine = c.run.commandLine;
  c.merge = app.add_subcommand("merge", "merge result folders (a sweep's shards) into one runs.csv, passes.csv, meta.json");
  c.merge->add_option("INPUT", c.mergeRequest.inputs, "shard or result folders; a sweep.json among them names the shards expected")
      ->required();
  c.merge->add_option("--out", c.mergeRequest.out, "folder for the merged tables")->required();
  c.merge->add_flag("--allow-mixed-renderers", c.mergeRequest.allowMixedRenderers,
                     "merge rows of one scene, size and seed that come from different renderers");
  c.report = app.add_subcommand("report", "one HTML page over a results folder: error against time, the rows, "
                                                 "images, passes, provenance (README \"Reports\")");
  c.report->add_option("DIR", c.reportRequest.dir, "a results folder, or a folder of them (one per scene)")->required();
  c.report->add_option("-o,--out", c.reportRequest.out, "the page (default DIR/report.html)");
  c.report->add_option("--embed-images", c.reportRequest.embedImagesMb,
                        "embed the images in the page while their total stays within this many MB (a single file to "
                        "send; the rest are referenced by relative path)")
      ->check(CLI::Range(0.0, 4096.0));

}

void addViewCommand(CLI::App& app, Commands& c) {
  // The interactive viewer (harness/viewer/viewer.hpp; README "Viewer").
  c.view = app.add_subcommand("view", "interactive window over one scene: the same frame pipeline and timer as "
                                             "run, keys and a panel (README \"Viewer\"); needs an X server");
  c.view->add_option("--scene", c.viewRequest.scene, "built-in scene name or path to a scene .json")->required();
  c.view->add_option("--method", c.viewRequest.methods, "method spec (repeatable, at most 9: keys 1-9; default every method)");
  c.view->add_option("--size", c.viewRequest.size, "image size WxH")->capture_default_str();
  c.view->add_option("--seed", c.viewRequest.seed, "seed for jitter")->capture_default_str()->check(CLI::Range(0LL, 4294967295LL));
  c.view->add_option("--timer", c.viewRequest.timer, "timing strategy")->capture_default_str()->check(CLI::IsMember({"auto", "gpu", "wall"}));
  c.view->add_option("--cache", c.viewRequest.cacheDir, "reference cache folder (default $VSHADOW_CACHE or ~/.cache/vshadow)");
  c.view->add_option("--out", c.viewRequest.out, "folder for screenshots and scene files saved by key")->capture_default_str();
  c.view->add_option("--frames", c.viewRequest.frames, "render N frames (after --script), then exit")->check(CLI::Range(1, 1000000));
  c.view->add_option("--screenshot", c.viewRequest.screenshot, "after the frames, write FILE.png and FILE.exr of the view");
  c.view->add_option("--script", c.viewRequest.script, "scripted input, one command per line (README \"Viewer\"), then exit");
  c.view->add_flag("--strict-gl", c.viewRequest.strictGl, "treat any GL debug error as fatal");

}

int dispatch(CLI::App& app, Commands& c) {
  if (app.got_subcommand("list")) return vs::listCommand(vs::registeredMethods());
  if (c.plan->parsed()) return vs::sweepPlanCommand(c.sweepFile, c.sweepOptions, vs::registeredMethods());
  if (c.sweepRun->parsed()) return vs::sweepRunCommand(c.sweepFile, c.sweepOptions, vs::registeredMethods());
  if (c.sweepReference->parsed()) return vs::sweepReferenceCommand(c.sweepFile, c.sweepOptions, vs::registeredMethods());
  if (c.view->parsed()) return vs::viewCommand(c.viewRequest, vs::registeredMethods());
  if (c.merge->parsed()) return vs::mergeCommand(c.mergeRequest, vs::registeredMethods());
  if (c.report->parsed()) return vs::reportCommand(c.reportRequest);
  if (app.got_subcommand("run")) return vs::runCommand(c.run, false, vs::registeredMethods());
  return vs::runCommand(c.shootout, true, vs::registeredMethods());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vshadow: time volumetric-shadow methods pass by pass and measure their error against a "
               "ray-marched reference"};
  app.require_subcommand(1);
  Commands c;
  for (int i = 0; i < argc; ++i) c.run.commandLine += (i ? " " : "") + std::string(argv[i]);
  c.shootout.commandLine = c.run.commandLine;
  app.add_subcommand("list", "list built-in scenes and every method with its parameters");
  addRunAndShootout(app, c);
  addSweepCommands(app, c);
  addMergeAndReport(app, c);
  addViewCommand(app, c);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "vshadow: error: %s (see vshadow --help)\n", e.what());
    return 2;
  }
  return dispatch(app, c);
}
