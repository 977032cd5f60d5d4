// Tests for the result files: the rows a run writes, rows of earlier runs kept, and no partial
// file left behind when a write fails.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "gl_test.hpp"
#include "harness/pipeline/frame.hpp"
#include "harness/shootout/result_files.hpp"

namespace vs::shootout {
namespace {

namespace fs = std::filesystem;
using vs::testing::makeTempDir;
using vs::testing::readFile;

TimingStats stats(double median) {
  TimingStats s;
  s.medianMs = s.minMs = s.maxMs = median;
  s.samples = 2;
  return s;
}

MethodRun successfulRun(const std::string& params) {
  MethodRun r;
  r.method = "raymarch";
  r.params = params;
  r.passes = {kShadowMapPass, "March"};
  r.passStats[kShadowMapPass] = stats(1.0);
  r.passStats["March"] = stats(4.0);
  r.frame = stats(6.0);
  return r;
}

ResultRow runsRow(const MethodRun& r, const std::string& status) {
  ResultRow row(runsColumns());
  row.set("scene", "spheres").set("method", r.method).set("params", r.params).set("status", status);
  return row;
}

std::vector<std::vector<std::string>> csv(const std::string& path) { return CsvTable::parse(readFile(path)); }

std::vector<std::string> leftovers(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp") != std::string::npos) names.push_back(e.path().string());
  return names;
}

TEST(ResultFiles, RowsOfRunsAndPassesWithTheirRounds) {
  const std::string dir = makeTempDir("result-files");
  ResultFiles files(dir, "spheres", false);
  MethodRun r = successfulRun("steps=8");
  RoundTimings rounds;
  rounds.add(r);
  r.passStats["March"] = stats(6.0);
  rounds.add(r);
  files.addRows(runsRow(r, "Success"), r, "spheres", "wall", "llvmpipe", rounds);

  auto runs = csv(dir + "/runs.csv");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0], runsColumns());
  EXPECT_EQ(runs[1][3], "Success");
  auto passes = csv(dir + "/passes.csv");
  ASSERT_EQ(passes.size(), 4u);  // header, two passes and the frame
  EXPECT_EQ(passes[0], passesColumns());
  auto column = [&](const std::string& name) {
    return size_t(std::find(passes[0].begin(), passes[0].end(), name) - passes[0].begin());
  };
  EXPECT_EQ(passes[2][column("pass")], "March");
  EXPECT_EQ(passes[2][column("median_ms")], "6");
  EXPECT_EQ(passes[2][column("rounds")], "2");
  EXPECT_EQ(passes[2][column("round_min_ms")], "4");
  EXPECT_EQ(passes[2][column("round_max_ms")], "6");
  EXPECT_EQ(passes[3][column("pass")], PassTimer::kFrame);
  EXPECT_EQ(passes[3][column("timer")], "wall");
  EXPECT_FALSE(fs::exists(dir + "/frames.csv"));
  EXPECT_EQ(files.summary(), "results: " + dir + "/runs.csv  " + dir + "/passes.csv  " + dir + "/meta.json");
  EXPECT_FALSE(fs::exists(dir + "/images"));  // without images
}

TEST(ResultFiles, EarlierRowsAreKeptAndTheSameKeyReplaced) {
  const std::string dir = makeTempDir("result-files-again");
  MethodRun a = successfulRun("steps=8"), b = successfulRun("steps=16");
  ResultFiles(dir, "spheres", false).addRows(runsRow(a, "Failure"), a, "spheres", "wall", "llvmpipe", {});
  ResultFiles files(dir, "spheres", false);
  files.addRows(runsRow(b, "Success"), b, "spheres", "wall", "llvmpipe", {});
  files.addRows(runsRow(a, "Success"), a, "spheres", "wall", "llvmpipe", {});
  auto runs = csv(dir + "/runs.csv");
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[1][2], "steps=8");
  EXPECT_EQ(runs[1][3], "Success");
  EXPECT_EQ(runs[2][2], "steps=16");
}

TEST(ResultFiles, AFolderThatCannotHoldResultsIsAnErrorBeforeAnyFile) {
  const std::string dir = makeTempDir("result-files-blocked");
  const std::string blocked = dir + "/a-file";
  std::ofstream(blocked) << "not a folder";
  EXPECT_THROW(ResultFiles(blocked, "spheres", true), std::runtime_error);
  EXPECT_THROW(ResultFiles(blocked + "/below", "spheres", true), std::runtime_error);
  EXPECT_EQ(readFile(blocked), "not a folder");
}

TEST(ResultFiles, AFailedWriteLeavesTheEarlierFileWhole) {
  const std::string dir = makeTempDir("result-files-failing");
  ResultFiles files(dir, "spheres", false);
  files.writeMeta({{"status", "running"}});
  const std::string before = readFile(dir + "/meta.json");
  fs::rename(dir + "/meta.json", dir + "/meta.keep");
  fs::create_directory(dir + "/meta.json");  // the rename over it fails
  EXPECT_THROW(files.writeMeta({{"status", "finished"}}), std::runtime_error);
  EXPECT_TRUE(leftovers(dir).empty());
  EXPECT_EQ(readFile(dir + "/meta.keep"), before);

  MethodRun r = successfulRun("steps=8");
  fs::create_directory(dir + "/passes.csv");
  EXPECT_THROW(files.addRows(runsRow(r, "Success"), r, "spheres", "wall", "llvmpipe", {}), std::runtime_error);
  EXPECT_TRUE(leftovers(dir).empty());
  EXPECT_EQ(csv(dir + "/runs.csv").size(), 2u);  // written before passes.csv failed, and whole
}

TEST(ResultFiles, ImagesOfASuccessfulRunOnly) {
  const std::string dir = makeTempDir("result-files-images");
  ResultFiles files(dir, "my scene", true);
  MethodRun r = successfulRun("steps=8:sm=64");
  r.final = r.inscatter = Image(4, 3);
  Baselines base;
  files.writeImages(r, base, false);
  const std::string stem = dir + "/images/my_scene/raymarch_steps_8_sm_64";
  EXPECT_TRUE(fs::exists(stem + ".final.exr"));
  EXPECT_TRUE(fs::exists(stem + ".ls.exr"));
  EXPECT_TRUE(fs::exists(stem + ".png"));
  EXPECT_FALSE(fs::exists(stem + ".error.png"));  // no reference
  r.params = "steps=16";
  r.status = RunStatus::Failure;
  files.writeImages(r, base, false);
  EXPECT_FALSE(fs::exists(dir + "/images/my_scene/raymarch_steps_16.png"));
}

}  // namespace
}  // namespace vs::shootout
