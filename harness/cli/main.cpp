// vshadow: benchmark suite for real-time volumetric shadows.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "harness/cli/app.hpp"
#include "harness/cli/merge.hpp"
#include "harness/cli/sweep.hpp"
#include "harness/report/report.hpp"
#include "harness/viewer/viewer.hpp"
#include "methods/registry.hpp"

int main(int argc, char** argv) {
  CLI::App app{"vshadow: time volumetric-shadow methods pass by pass and measure their error against a "
               "ray-marched reference"};
  app.require_subcommand(1);
  vs::RunRequest run, shootout;
  for (int i = 0; i < argc; ++i) run.commandLine += (i ? " " : "") + std::string(argv[i]);
  shootout.commandLine = run.commandLine;

  app.add_subcommand("list", "list built-in scenes and every method with its parameters");

  auto addCommon = [](CLI::App* cmd, vs::RunRequest& r) {
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
  };
  auto* runCmd = app.add_subcommand("run", "run the given methods on one scene");
  addCommon(runCmd, run);
  runCmd->add_option("--method", run.methods, "method spec name:key=value:... (repeatable)")->required();
  auto* shootCmd = app.add_subcommand(
      "shootout", "run every method that supports the scene at its ladder of quality settings against the reference");
  addCommon(shootCmd, shootout);
  shootCmd->add_option("--method", shootout.methods, "only these methods (by name; repeatable)");
  shootCmd->add_option("--rungs", shootout.rungs,
                       "only these rungs of each ladder: all, first, middle (index size/2), last or a 0-based index "
                       "(comma-separated or repeatable; default all)")
      ->delimiter(',');

  // Sweeps (harness/cli/sweep.hpp) and merging their shards (harness/cli/merge.hpp).
  std::string sweepFile;
  vs::SweepOptions sweepOptions;
  auto* sweepCmd = app.add_subcommand("sweep", "plan or run a sweep file shard by shard (README \"Sweeps\")");
  sweepCmd->require_subcommand(1);
  auto* planCmd = sweepCmd->add_subcommand("plan", "print the shards of a sweep file: index, stable id, methods");
  planCmd->add_option("FILE", sweepFile, "sweep file (.json)")->required();
  planCmd->add_option("--out", sweepOptions.out, "also write OUT/sweep.json, the normalized sweep the shards run from");
  planCmd->add_flag("--pending", sweepOptions.pendingOnly, "only the shards not finished in --out");
  auto* sweepRunCmd = sweepCmd->add_subcommand("run", "run the shards into OUT/<id>/ in order, skipping finished ones");
  sweepRunCmd->add_option("FILE", sweepFile, "sweep file (.json)")->required();
  sweepRunCmd->add_option("OUT", sweepOptions.out, "the sweep's folder")->required();
  sweepRunCmd->add_option("--shard", sweepOptions.only, "only this shard (id or index; repeatable)");
  sweepRunCmd->add_option("--cache", sweepOptions.cacheDir, "reference cache folder (default $VSHADOW_CACHE or ~/.cache/vshadow)");
  auto* sweepRefCmd = sweepCmd->add_subcommand("reference", "fill the reference cache for one scene of a sweep");
  sweepRefCmd->add_option("FILE", sweepFile, "sweep file (.json)")->required();
  sweepRefCmd->add_option("--scene", sweepOptions.scene, "the scene (as named in the sweep file)")->required();
  sweepRefCmd->add_option("--cache", sweepOptions.cacheDir, "reference cache folder (default $VSHADOW_CACHE or ~/.cache/vshadow)");
  vs::MergeRequest merge;
  merge.commandLine = run.commandLine;
  auto* mergeCmd = app.add_subcommand("merge", "merge result folders (a sweep's shards) into one runs.csv, passes.csv, meta.json");
  mergeCmd->add_option("INPUT", merge.inputs, "shard or result folders; a sweep.json among them names the shards expected")
      ->required();
  mergeCmd->add_option("--out", merge.out, "folder for the merged tables")->required();
  mergeCmd->add_flag("--allow-mixed-renderers", merge.allowMixedRenderers,
                     "merge rows of one scene, size and seed that come from different renderers");
  vs::ReportRequest report;
  auto* reportCmd = app.add_subcommand("report", "one HTML page over a results folder: error against time, the rows, "
                                                 "images, passes, provenance (README \"Reports\")");
  reportCmd->add_option("DIR", report.dir, "a results folder, or a folder of them (one per scene)")->required();
  reportCmd->add_option("-o,--out", report.out, "the page (default DIR/report.html)");
  reportCmd->add_option("--embed-images", report.embedImagesMb,
                        "embed the images in the page while their total stays within this many MB (a single file to "
                        "send; the rest are referenced by relative path)")
      ->check(CLI::Range(0.0, 4096.0));

  // The interactive viewer (harness/viewer/viewer.hpp; README "Viewer").
  vs::ViewRequest view;
  auto* viewCmd = app.add_subcommand("view", "interactive window over one scene: the same frame pipeline and timer as "
                                             "run, keys and a panel (README \"Viewer\"); needs an X server");
  viewCmd->add_option("--scene", view.scene, "built-in scene name or path to a scene .json")->required();
  viewCmd->add_option("--method", view.methods, "method spec (repeatable, at most 9: keys 1-9; default every method)");
  viewCmd->add_option("--size", view.size, "image size WxH")->capture_default_str();
  viewCmd->add_option("--seed", view.seed, "seed for jitter")->capture_default_str()->check(CLI::Range(0LL, 4294967295LL));
  viewCmd->add_option("--timer", view.timer, "timing strategy")->capture_default_str()->check(CLI::IsMember({"auto", "gpu", "wall"}));
  viewCmd->add_option("--cache", view.cacheDir, "reference cache folder (default $VSHADOW_CACHE or ~/.cache/vshadow)");
  viewCmd->add_option("--out", view.out, "folder for screenshots and scene files saved by key")->capture_default_str();
  viewCmd->add_option("--frames", view.frames, "render N frames (after --script), then exit")->check(CLI::Range(1, 1000000));
  viewCmd->add_option("--screenshot", view.screenshot, "after the frames, write FILE.png and FILE.exr of the view");
  viewCmd->add_option("--script", view.script, "scripted input, one command per line (README \"Viewer\"), then exit");
  viewCmd->add_flag("--strict-gl", view.strictGl, "treat any GL debug error as fatal");

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
  if (app.got_subcommand("list")) return vs::listCommand(vs::registeredMethods());
  if (planCmd->parsed()) return vs::sweepPlanCommand(sweepFile, sweepOptions, vs::registeredMethods());
  if (sweepRunCmd->parsed()) return vs::sweepRunCommand(sweepFile, sweepOptions, vs::registeredMethods());
  if (sweepRefCmd->parsed()) return vs::sweepReferenceCommand(sweepFile, sweepOptions, vs::registeredMethods());
  if (viewCmd->parsed()) return vs::viewCommand(view, vs::registeredMethods());
  if (mergeCmd->parsed()) return vs::mergeCommand(merge, vs::registeredMethods());
  if (reportCmd->parsed()) return vs::reportCommand(report);
  if (app.got_subcommand("run")) return vs::runCommand(run, false, vs::registeredMethods());
  return vs::runCommand(shootout, true, vs::registeredMethods());
}
