// End to end through the vshadow binary: listing, bad input, a shootout, killed runs, the cache.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "bad_inputs.hpp"
#include "gl_test.hpp"
#include "harness/io/results.hpp"

namespace vs::testing {
namespace {

namespace fs = std::filesystem;

int nonEmptyLines(const std::string& s) {
  int n = 0;
  std::istringstream in(s);
  std::string line;
  while (std::getline(in, line)) n += line.find_first_not_of(" \t\r") != std::string::npos;
  return n;
}

TEST(CliTest, ListShowsScenesMethodsAndParameters) {
  CommandResult r = runVshadow({"list"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (const char* s : {"spheres", "room", "fence", "trees", "terrain", "volumes", "cloud", "foliage", "arealight",
                        "raymarch", "steps", "jitter", "sm", "light_samples", "volume-data", "semi-transparent",
                        "colored-shadows", "area-light", "sunsweep"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
  // Which scenes move, and how.
  EXPECT_NE(r.out.find("moves: 2 s at 12 fps (25 frames): light direction"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("moves: 2 s at 12 fps (25 frames): geometry 'torus_tilted', geometry 'knot_left'"),
            std::string::npos) << r.out;
  // Per method, the effects it models and those it runs under a declared approximation.
  EXPECT_NE(r.out.find("effects approximated: area light (vpls=N virtual point lights, the per-VPL wrapper); "
                       "semi-transparent occluders (alpha-tested into the shadow map at alpha_test)"),
            std::string::npos) << r.out;
  EXPECT_NE(r.out.find("effects not run: volume data"), std::string::npos) << r.out;
  // raymarch's two brute-force series on point and spot lights.
  EXPECT_NE(r.out.find("shootout ladder (equiangular, point and spot lights): steps=8:sampling=equiangular"),
            std::string::npos);
}

TEST(CliTest, HelpExitsCleanly) {
  CommandResult r = runVshadow({"--help"});
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("shootout"), std::string::npos);
}

class BadInputTest : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputTest, OneClearLineNonZeroExitNothingWritten) {
  const BadInput& bad = GetParam();
  std::string dir = makeTempDir("bad");
  writeBadInputFixtures(dir);
  // An output folder that already holds results: bad input must leave it untouched.
  std::string out = dir + "/out";
  fs::create_directories(out);
  writeFile(out + "/runs.csv", "sentinel\n");
  std::vector<std::string> args = badInputArgs(bad, dir);
  if (std::find(args.begin(), args.end(), "--out") == args.end()) args.insert(args.end(), {"--out", out});
  args.insert(args.end(), {"--cache", dir + "/cache"});
  CommandResult r = runVshadow(args);
  EXPECT_NE(r.exitCode, 0) << bad.name;
  EXPECT_EQ(nonEmptyLines(r.err), 1) << bad.name << ": " << r.err;
  EXPECT_NE(r.err.find(bad.expectInError), std::string::npos) << bad.name << ": " << r.err;
  EXPECT_EQ(readFile(out + "/runs.csv"), "sentinel\n");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(out)) files.push_back(e.path().filename().string());
  EXPECT_EQ(files, std::vector<std::string>{"runs.csv"}) << bad.name;
  EXPECT_FALSE(fs::exists(dir + "/cache")) << bad.name;
}

INSTANTIATE_TEST_SUITE_P(Cases, BadInputTest, ::testing::ValuesIn(badInputs()),
                         [](const ::testing::TestParamInfo<BadInput>& info) { return info.param.name; });

TEST(CliTest, ShaderThatFailsToCompileIsAFailureRowAndTheSweepGoesOn) {
  std::string dir = makeTempDir("shader");
  std::string shaders = dir + "/shaders";
  fs::create_directories(shaders + "/methods/raymarch/shaders");
  writeFile(shaders + "/methods/raymarch/shaders/raymarch.frag",
            "#version 450 core\n#include \"common.glsl\"\nout vec4 color;\nvoid main() {\n  color = undefinedThing;\n}\n");
  std::string out = dir + "/out";
  CommandResult r = runVshadow({"run", "--scene", "spheres", "--method", "raymarch:steps=4", "--method",
                                "raymarch:steps=8", "--size", "16x16", "--frames", "1", "--warmup", "0",
                                "--no-reference", "--out", out},
                               {"VSHADOW_SHADER_DIR=" + shaders});
  EXPECT_EQ(r.exitCode, 3) << r.err;
  auto rows = CsvTable::parse(readFile(out + "/runs.csv"));
  ASSERT_EQ(rows.size(), 3u) << "both rows of the sweep are written";
  for (size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i][3], "Failure");
    EXPECT_NE(rows[i][4].find("methods/raymarch/shaders/raymarch.frag:5"), std::string::npos) << rows[i][4];
  }
}

CsvTable loadCsv(const std::string& path, std::vector<std::string> header, size_t keys) {
  CsvTable t(std::move(header), keys);
  t.loadExisting(path);
  return t;
}

const std::string& field(const CsvTable& table, const std::vector<std::string>& row, const std::string& column) {
  auto it = std::find(table.header().begin(), table.header().end(), column);
  EXPECT_NE(it, table.header().end()) << column;
  static const std::string none;
  return it == table.header().end() ? none : row[size_t(it - table.header().begin())];
}

TEST(CliTest, ShootoutRunsPointLightMethodsPerVplOnAnAreaLight) {
  std::string dir = makeTempDir("shootout-area");
  std::string out = dir + "/out";
  CommandResult r = runVshadow({"shootout", "--scene", "arealight", "--size", "24x18", "--frames", "1", "--warmup", "0",
                                "--rungs", "first", "--method", "vsv", "--method", "ivsv", "--method", "slicemap",
                                "--out", out, "--cache", dir + "/cache", "--strict-gl", "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  CsvTable runs = loadCsv(out + "/runs.csv", runsColumns(), kRunsKeyColumns);
  std::map<std::string, std::string> status, params, stats;
  for (const auto& row : runs.rows()) {
    status[field(runs, row, "method")] = field(runs, row, "status");
    params[field(runs, row, "method")] = field(runs, row, "params");
    stats[field(runs, row, "method")] = field(runs, row, "method_stats");
  }
  EXPECT_EQ(status["vsv"], "Success");
  EXPECT_NE(params["vsv"].find("vpls=16"), std::string::npos) << params["vsv"];
  // Work counters, from one untimed frame over every VPL.
  EXPECT_NE(stats["vsv"].find("vsv_bins_mean="), std::string::npos) << stats["vsv"];
  EXPECT_NE(stats["vsv"].find("vsv_shadowed_voxels="), std::string::npos) << stats["vsv"];
  EXPECT_EQ(status["ivsv"], "Success");
  EXPECT_NE(params["ivsv"].find("vpls=0"), std::string::npos) << params["ivsv"];  // area lights natively
  EXPECT_EQ(status["slicemap"], "Unsupported");  // its setup fits one light position
}

// An OBJ downloaded without its MTL: the run goes on, says so once per problem on stderr and keeps
// the warnings in meta.json.
TEST(CliTest, SceneWarningsArePrintedAndRecorded) {
  std::string dir = makeTempDir("scene-warnings");
  writeFile(dir + "/nave.obj", "mtllib untitled.mtl\nv -2 1 -2\nv 2 1 -2\nv 2 1 2\nv -2 1 2\nusemtl stone\nf 1 2 3 4\n");
  writeFile(dir + "/scene.json", R"({"geometry": [{"obj": "nave.obj"}], "camera": {"position": [0, 0.5, 6], "target": [0, 1, 0]},
    "light": {"type": "point", "position": [0, 3, 0], "intensity": 50}, "medium": {"sigma_s": 0.05, "sigma_a": 0.01}})");
  CommandResult r = runVshadow({"run", "--scene", dir + "/scene.json", "--method", "raymarch:steps=4", "--size", "16x12",
                                "--frames", "1", "--warmup", "0", "--no-reference", "--no-images", "--out", dir + "/out"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + dir + "/nave.obj:1: material library"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nave.obj:6: material 'stone'"), std::string::npos) << r.err;
  auto meta = nlohmann::json::parse(readFile(dir + "/out/meta.json"));
  ASSERT_EQ(meta["scene_warnings"].size(), 2u);
  EXPECT_NE(meta["scene_warnings"][0].get<std::string>().find("untitled.mtl"), std::string::npos);
}

// A moving scene through the binary: the compared frame's time is recorded, the reference is the
// scene at that time, and the light-fitted methods pay for their refits in the frame.
TEST(CliTest, MovingSceneRecordsItsComparedFrameAndRefitsInTheFrame) {
  std::string dir = makeTempDir("moving");
  CommandResult r = runVshadow({"shootout", "--scene", "sunsweep", "--size", "32x24", "--frames", "2", "--warmup", "2",
                                "--rungs", "first", "--method", "raymarch", "--method", "slicemap", "--no-images",
                                "--out", dir + "/out", "--cache", dir + "/cache"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto meta = nlohmann::json::parse(readFile(dir + "/out/meta.json"));
  const auto& animation = meta["scene"]["animation"];
  ASSERT_TRUE(animation.is_object()) << meta["scene"].dump();
  EXPECT_EQ(animation["compared_frame"], 3);
  EXPECT_DOUBLE_EQ(animation["compared_time_s"].get<double>(), 0.25);
  EXPECT_EQ(animation["sequence_frames"], 25);
  CsvTable runs = loadCsv(dir + "/out/runs.csv", runsColumns(), kRunsKeyColumns);
  int slicemapRows = 0;
  for (const auto& row : runs.rows()) {
    ASSERT_EQ(field(runs, row, "status"), "Success") << field(runs, row, "reason");
    const std::string passes = field(runs, row, "passes");
    const bool refits = passes.find(kLightRefitPass) != std::string::npos;
    if (field(runs, row, "method") == "slicemap") {
      ++slicemapRows;
      EXPECT_TRUE(refits) << passes;  // its slices are fitted to the light, which moves every frame
    } else {
      EXPECT_FALSE(refits) << passes;
    }
    EXPECT_FALSE(field(runs, row, "frame_p95_ms").empty());
    // Errors over the sequence: both measured frames, each against the reference of its time.
    EXPECT_EQ(field(runs, row, "seq_frames"), "2");
    const double temporal = std::stod(field(runs, row, "temporal_ls_rmse"));
    EXPECT_TRUE(std::isfinite(temporal) && temporal >= 0.0) << temporal;
    EXPECT_GE(std::stod(field(runs, row, "seq_ls_rmse_max")), std::stod(field(runs, row, "seq_ls_rmse_mean")));
  }
  EXPECT_EQ(slicemapRows, 1);
  CsvTable frames = loadCsv(dir + "/out/frames.csv", framesColumns(), kFramesKeyColumns);
  ASSERT_EQ(frames.rows().size(), 2 * runs.rows().size());
  for (const auto& f : frames.rows()) {
    const std::string frame = field(frames, f, "frame");
    ASSERT_TRUE(frame == "2" || frame == "3") << frame;
    EXPECT_NEAR(std::stod(field(frames, f, "time_s")), std::stod(frame) / 12.0, 1e-6);
    EXPECT_GT(std::stod(field(frames, f, "frame_ms")), 0.0);
    EXPECT_NE(field(frames, f, "pass_ms").find("G Buffer="), std::string::npos);
    // The last frame is the compared one: its error is the row's.
    if (frame != "3") continue;
    for (const auto& row : runs.rows()) {
      if (field(runs, row, "method") == field(frames, f, "method") && field(runs, row, "params") == field(frames, f, "params")) {
        EXPECT_EQ(field(frames, f, "ls_rmse"), field(runs, row, "ls_rmse"));
      }
    }
  }
  // Error and frame time over time, as a picture.
  std::string cmd = std::string(VS_SOURCE_DIR) + "/scripts/plot-sequence " + dir + "/out -o " + dir +
                    "/sequence.png > " + dir + "/plot.log 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/plot.log");

  // `vshadow merge` keeps the frames, tagged with where they come from.
  CommandResult merged = runVshadow({"merge", dir + "/out", "--out", dir + "/merged"});
  ASSERT_EQ(merged.exitCode, 0) << merged.err;
  std::vector<std::string> taggedFrames = framesColumns();
  for (const char* c : {"width", "height", "seed", "host", "shard"}) taggedFrames.push_back(c);
  CsvTable mergedFrames = loadCsv(dir + "/merged/frames.csv", taggedFrames, kFramesKeyColumns);
  EXPECT_EQ(mergedFrames.rows().size(), frames.rows().size());
  EXPECT_EQ(field(mergedFrames, mergedFrames.rows().front(), "width"), "32");

  // Against the exact ground truth, every measured frame is compared with the ground truth of its
  // own time; the last one's is the row's error.
  CommandResult exact = runVshadow({"run", "--scene", "sunsweep", "--size", "24x18", "--frames", "2", "--warmup", "1",
                                    "--method", "minmax", "--reference", "exact", "--exact-steps", "64", "--no-images",
                                    "--out", dir + "/exact", "--cache", dir + "/cache"});
  ASSERT_EQ(exact.exitCode, 0) << exact.err;
  CsvTable exactRuns = loadCsv(dir + "/exact/runs.csv", runsColumns(), kRunsKeyColumns);
  ASSERT_EQ(exactRuns.rows().size(), 1u);
  EXPECT_EQ(field(exactRuns, exactRuns.rows()[0], "seq_frames"), "2");
  CsvTable exactFrames = loadCsv(dir + "/exact/frames.csv", framesColumns(), kFramesKeyColumns);
  ASSERT_EQ(exactFrames.rows().size(), 2u);
  for (const auto& f : exactFrames.rows()) {
    if (field(exactFrames, f, "frame") == "2") {
      EXPECT_EQ(field(exactFrames, f, "ls_rmse"), field(exactRuns, exactRuns.rows()[0], "ls_rmse"));
    }
  }
  EXPECT_GT(fs::file_size(dir + "/sequence.png"), 1000u);
}

// A moving scene's video: every measured frame's images are written, and scripts/video makes an
// H.264 MP4 with one frame per measured frame, its PNG frames kept beside it. scripts/animation-table
// tabulates the same folder (results/animation).
TEST(CliTest, MovingSceneGivesAVideoAndAnAnimationTable) {
  std::string dir = makeTempDir("video");
  CommandResult r = runVshadow({"shootout", "--scene", "sunsweep", "--size", "32x24", "--frames", "3", "--warmup", "1",
                                "--rungs", "first", "--method", "minmax", "--method", "vsv", "--out", dir + "/out",
                                "--cache", dir + "/cache"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const fs::path frames = fs::path(dir) / "out/images/sunsweep/frames";
  for (const char* frame : {"0001", "0002", "0003"}) {
    EXPECT_TRUE(fs::exists(frames / "reference" / (std::string(frame) + ".png"))) << frame;
    int rows = 0;
    for (const auto& entry : fs::directory_iterator(frames)) {
      if (entry.path().filename() == "reference") continue;
      ++rows;
      EXPECT_TRUE(fs::exists(entry.path() / (std::string(frame) + ".png"))) << entry.path();
      EXPECT_TRUE(fs::exists(entry.path() / (std::string(frame) + ".error.png"))) << entry.path();
    }
    EXPECT_EQ(rows, 2);
  }
  const std::string video = std::string(VS_SOURCE_DIR) + "/scripts/video ";
  std::string cmd = video + dir + "/out -o " + dir + " > " + dir + "/video.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/video.log");
  EXPECT_TRUE(fs::exists(dir + "/video-sunsweep/0002.png"));
  cmd = "ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=codec_name,nb_read_frames -of csv=p=0 " +
        dir + "/video-sunsweep.mp4 > " + dir + "/probe.txt 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/probe.txt");
  EXPECT_EQ(readFile(dir + "/probe.txt"), "h264,3\n");

  // Without images (or without frames.csv) there is nothing to make a video of: one line, exit 1.
  cmd = video + dir + "/nowhere 2> " + dir + "/err.txt";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  const std::string err = readFile(dir + "/err.txt");
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("frames.csv"), std::string::npos) << err;

  // The animation table: a row per method with its errors over the sequence and frame percentiles,
  // what motion costs each, and vsv beside the paper's animations.
  cmd = std::string(VS_SOURCE_DIR) + "/scripts/animation-table " + dir + "/out > " + dir + "/table.md 2> " + dir +
        "/table.err";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/table.err");
  const std::string table = readFile(dir + "/table.md");
  EXPECT_NE(table.find("## sunsweep: 2 s at 12 fps (25 frames): light direction"), std::string::npos) << table;
  EXPECT_NE(table.find("Frames 1–3 of 25 measured"), std::string::npos) << table;
  EXPECT_NE(table.find("| minmax"), std::string::npos) << table;
  EXPECT_NE(table.find("| vsv | none |"), std::string::npos) << table;  // what motion costs it
  EXPECT_NE(table.find("| sunsweep (ours) |"), std::string::npos) << table;
  EXPECT_NE(table.find("| Fairy Forest Animation (paper) |"), std::string::npos) << table;
  EXPECT_NE(table.find("Motion adds no pass of its own to vsv"), std::string::npos) << table;
  // A still scene's folder is not a sequence: one line, exit 1.
  CommandResult still = runVshadow({"run", "--scene", "spheres", "--size", "16x12", "--frames", "1", "--warmup", "0",
                                    "--method", "raymarch", "--no-reference", "--no-images", "--out", dir + "/still"});
  ASSERT_EQ(still.exitCode, 0) << still.err;
  cmd = std::string(VS_SOURCE_DIR) + "/scripts/animation-table " + dir + "/still 2> " + dir + "/still.err";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  const std::string stillErr = readFile(dir + "/still.err");
  EXPECT_EQ(std::count(stillErr.begin(), stillErr.end(), '\n'), 1) << stillErr;
}

// scripts/froxel-verdict (results/froxel): from a shootout of whole ladders, per scene the fastest
// method at froxel's error and the most accurate in its time, against froxel's game setting.
TEST(CliTest, FroxelVerdictComparesEveryMethodAtFroxelsErrorAndTime) {
  std::string dir = makeTempDir("froxel-verdict");
  CommandResult r = runVshadow({"shootout", "--scene", "spheres", "--size", "32x24", "--frames", "1", "--warmup", "1",
                                "--rungs", "all", "--method", "froxel", "--method", "minmax", "--no-images", "--out",
                                dir + "/out", "--cache", dir + "/cache"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::string cmd = std::string(VS_SOURCE_DIR) + "/scripts/froxel-verdict " + dir + "/out > " + dir + "/verdict.md 2> " +
                    dir + "/verdict.err";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/verdict.err");
  const std::string verdict = readFile(dir + "/verdict.md");
  EXPECT_NE(verdict.find("| spheres |"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("- **spheres**: "), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("froxel wins at equal error on "), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("minmax"), std::string::npos) << verdict;
  // Across processes: the same runs twice name the same winners; a second process in which froxel
  // ran 1000x slower names another method at froxel's error, so that scene is too close to call.
  std::filesystem::create_directories(dir + "/p1");
  std::filesystem::create_directories(dir + "/p2");
  std::filesystem::copy(dir + "/out", dir + "/p1/spheres", std::filesystem::copy_options::recursive);
  std::filesystem::copy(dir + "/out", dir + "/p2/spheres", std::filesystem::copy_options::recursive);
  const std::string same = std::string(VS_SOURCE_DIR) + "/scripts/froxel-verdict --processes " + dir + "/p1 " + dir + "/p2";
  cmd = same + " > " + dir + "/same.md 2> " + dir + "/same.err";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/same.err");
  const std::string agreed = readFile(dir + "/same.md");
  EXPECT_NE(agreed.find("- **spheres**: "), std::string::npos) << agreed;
  EXPECT_EQ(agreed.find("too close to call at its error"), std::string::npos) << agreed;
  EXPECT_NE(agreed.find("too close to call on 0"), std::string::npos) << agreed;
  {
    std::vector<std::vector<std::string>> rows = CsvTable::parse(readFile(dir + "/p2/spheres/runs.csv"));
    ASSERT_FALSE(rows.empty());
    const std::vector<std::string>& header = rows[0];
    const size_t method = size_t(std::find(header.begin(), header.end(), "method") - header.begin());
    const size_t ms = size_t(std::find(header.begin(), header.end(), "scatter_ms") - header.begin());
    ASSERT_LT(ms, header.size());
    std::string text;
    for (auto& cells : rows) {
      if (&cells != &rows[0] && cells.size() == header.size() && cells[method] == "froxel" && !cells[ms].empty())
        cells[ms] = std::to_string(std::stod(cells[ms]) * 1000.0);
      text += CsvTable::format(cells) + "\n";
    }
    std::ofstream(dir + "/p2/spheres/runs.csv") << text;
  }
  cmd = same + " > " + dir + "/split.md 2> " + dir + "/split.err";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/split.err");
  const std::string split = readFile(dir + "/split.md");
  EXPECT_NE(split.find("too close to call at its error (the processes name "), std::string::npos) << split;
  EXPECT_NE(split.find("too close to call on 1 (spheres)"), std::string::npos) << split;
  // Without froxel rows there is no yardstick: one line, exit 1.
  CommandResult other = runVshadow({"shootout", "--scene", "spheres", "--size", "16x12", "--frames", "1", "--warmup", "0",
                                    "--rungs", "first", "--method", "minmax", "--no-images", "--out", dir + "/other",
                                    "--cache", dir + "/cache"});
  ASSERT_EQ(other.exitCode, 0) << other.err;
  cmd = std::string(VS_SOURCE_DIR) + "/scripts/froxel-verdict " + dir + "/other 2> " + dir + "/other.err";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  const std::string err = readFile(dir + "/other.err");
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

// The alpha-textured tree: every method that can model or approximate its leaves has a row (the
// binary ones alpha-tested, said in the row), and scripts/alpha-table reads them against the
// exact ground truth.
TEST(CliTest, AlphaTexturedTreeGivesEveryMethodARowAndTheAlphaTable) {
  std::string dir = makeTempDir("alpha-tree");
  CommandResult r = runVshadow({"shootout", "--scene", "foliage_alpha", "--size", "24x18", "--frames", "1", "--warmup",
                                "0", "--rungs", "first", "--exact", "--exact-steps", "64", "--no-images", "--out",
                                dir + "/out", "--cache", dir + "/cache"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  CsvTable runs = loadCsv(dir + "/out/runs.csv", runsColumns(), kRunsKeyColumns);
  std::map<std::string, std::string> status, approximations;
  for (const auto& row : runs.rows()) {
    status[field(runs, row, "method")] = field(runs, row, "status");
    approximations[field(runs, row, "method")] = field(runs, row, "approximations");
  }
  for (const char* method : {"raymarch", "minmax", "vsv", "slicemap", "froxel"})
    EXPECT_EQ(status[method], "Success") << method;
  for (const char* method : {"minmax", "vsv"})
    EXPECT_NE(approximations[method].find("alpha-tested into the shadow map"), std::string::npos) << method;
  EXPECT_NE(approximations["slicemap"].find("per-texel opacity quantised"), std::string::npos);
  std::string cmd = std::string(VS_SOURCE_DIR) + "/scripts/alpha-table " + dir + "/out > " + dir + "/table.md 2> " +
                    dir + "/table.err";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/table.err");
  const std::string table = readFile(dir + "/table.md");
  EXPECT_NE(table.find("| minmax | alpha_test=0.5 | alpha-tested (binary) |"), std::string::npos) << table;
  EXPECT_NE(table.find("- minmax (alpha_test=0.5), occluders alpha-tested: L_s RMSE "), std::string::npos) << table;
  // Without the exact ground truth the table has nothing to stand on: one line, exit 2.
  CommandResult plain = runVshadow({"run", "--scene", "foliage_alpha", "--size", "16x12", "--frames", "1", "--warmup",
                                    "0", "--method", "minmax", "--no-images", "--out", dir + "/plain", "--cache",
                                    dir + "/cache"});
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  cmd = std::string(VS_SOURCE_DIR) + "/scripts/alpha-table " + dir + "/plain 2> " + dir + "/plain.err";
  EXPECT_EQ(WEXITSTATUS(std::system(cmd.c_str())), 2);
  const std::string err = readFile(dir + "/plain.err");
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

TEST(CliTest, ShootoutWritesTablesImagesAndAPlot) {
  std::string dir = makeTempDir("shootout");
  std::string out = dir + "/out";
  // Two rungs of every ladder series keep it short (raymarch has two series on this point light).
  CommandResult r = runVshadow({"shootout", "--scene", "spheres", "--size", "64x48", "--frames", "3", "--warmup", "1",
                                "--rungs", "first,middle", "--out", out, "--cache", dir + "/cache", "--strict-gl"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  CsvTable runs = loadCsv(out + "/runs.csv", runsColumns(), kRunsKeyColumns);
  CsvTable passes = loadCsv(out + "/passes.csv", passesColumns(), kPassesKeyColumns);
  ASSERT_GE(runs.rows().size(), 3u);
  std::map<std::string, int> unsupported;
  for (const auto& row : runs.rows()) {
    if (field(runs, row, "status") == "Unsupported") {
      // Methods for effects the scene lacks (dsm: volume data): one row that says why.
      EXPECT_FALSE(field(runs, row, "reason").empty());
      EXPECT_EQ(++unsupported[field(runs, row, "method")], 1) << field(runs, row, "method");
      continue;
    }
    EXPECT_EQ(field(runs, row, "status"), "Success") << field(runs, row, "reason");
    EXPECT_FALSE(field(runs, row, "rmse").empty());
    EXPECT_FALSE(field(runs, row, "setup_ms").empty());
    EXPECT_EQ(field(runs, row, "effects"), "scattering+extinction+point");
    // Drift detection: the calibration around the row's rounds, and whether it moved.
    EXPECT_TRUE(field(runs, row, "disturbed") == "0" || field(runs, row, "disturbed") == "1");
    EXPECT_GE(std::stod(field(runs, row, "calibration_drift_pct")), 0.0);
    EXPECT_GE(std::stod(field(runs, row, "calibration_shift_pct")), 0.0);
    EXPECT_GE(std::stoi(field(runs, row, "disturbed_retries")), 0);
  }
  EXPECT_GE(passes.rows().size(), runs.rows().size() * 5);
  auto meta = nlohmann::json::parse(readFile(out + "/meta.json"));
  for (const char* key : {"command_line", "git_sha", "date", "build", "gl", "egl", "cpu", "timer", "width", "height"})
    EXPECT_TRUE(meta.contains(key)) << key;
  // How the binary was built: a sanitizer build's timings must not pass for a release build's.
  EXPECT_FALSE(meta["build"]["type"].get<std::string>().empty());
  EXPECT_FALSE(meta["build"]["compiler"].get<std::string>().empty());
#ifdef VS_SANITIZE
  EXPECT_EQ(meta["build"]["sanitizers"], "address,undefined");
#else
  EXPECT_EQ(meta["build"]["sanitizers"], "none");
#endif
  EXPECT_EQ(meta["status"], "finished");
  // The calibration workload was timed before the first row and after each (one round here).
  ASSERT_TRUE(meta.contains("drift"));
  EXPECT_EQ(meta["drift"]["threshold_pct"], 15.0);
  EXPECT_GT(meta["drift"]["workload"]["draw_iterations"].get<int>(), 0);
  size_t successes = 0;
  for (const auto& row : runs.rows()) successes += field(runs, row, "status") == "Success";
  EXPECT_GE(meta["drift"]["samples"].size(), successes + 1);
  for (const auto& sample : meta["drift"]["samples"]) {
    EXPECT_GT(sample["draw_ms"].get<double>(), 0.0);
    EXPECT_GT(sample["compute_ms"].get<double>(), 0.0);
  }
  EXPECT_FALSE(meta["gl"]["renderer"].get<std::string>().empty());
  EXPECT_TRUE(fs::exists(out + "/images/spheres/reference.final.exr"));
  int pngs = 0, errors = 0;
  for (const auto& e : fs::directory_iterator(out + "/images/spheres")) {
    std::string name = e.path().filename().string();
    pngs += name.size() > 4 && name.substr(name.size() - 4) == ".png";
    errors += name.find(".error.png") != std::string::npos;
  }
  EXPECT_GE(errors, 3);
  EXPECT_GT(pngs, errors);
  // The plot script turns runs.csv into an error-vs-time figure.
  std::string plot = std::string(VS_SOURCE_DIR) + "/scripts/plot";
  std::string cmd = plot + " " + out + "/runs.csv -o " + out + "/plot.png > " + dir + "/plot.log 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/plot.log");
  EXPECT_GT(fs::file_size(out + "/plot.png"), 1000u);

  // A second run reuses the cached reference.
  CommandResult again = runVshadow({"run", "--scene", "spheres", "--size", "64x48", "--frames", "2", "--warmup", "0",
                                    "--method", "raymarch:steps=8", "--out", out, "--cache", dir + "/cache",
                                    "--no-images"});
  ASSERT_EQ(again.exitCode, 0) << again.err;
  auto meta2 = nlohmann::json::parse(readFile(out + "/meta.json"));
  EXPECT_TRUE(meta2["reference"]["from_cache"].get<bool>());
  // Rows from the first run stay; the re-run row replaces its old self.
  EXPECT_EQ(loadCsv(out + "/runs.csv", runsColumns(), kRunsKeyColumns).rows().size(), runs.rows().size());
}

// scripts/shader-ab runs the built-in shaders (A) and a folder's (B) in turn on the same binary.
TEST(CliTest, ShaderAbRunsTheBuiltInShadersAndTheFolders) {
  std::string dir = makeTempDir("shader-ab");
  std::string script = std::string(VS_SOURCE_DIR) + "/scripts/shader-ab";
  std::string env = "BUILD_DIR=" + fs::path(vshadowPath()).parent_path().string() +
                    " SIZE=32x24 ROUNDS=1 FRAMES=1 PASSES='Compute L_s' ";
  std::string cmd = env + script + " " + VS_SOURCE_DIR + " room vsv:alpha=64:theta=128:phi=128 > " + dir +
                    "/ab.txt 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/ab.txt");
  std::string out = readFile(dir + "/ab.txt");
  EXPECT_NE(out.find("A | Compute L_s"), std::string::npos) << out;
  EXPECT_NE(out.find("B | Compute L_s"), std::string::npos) << out;
  // B really reads the folder: a shader that does not compile there fails the run, naming its file.
  fs::create_directories(dir + "/broken/methods/vsv/shaders");
  writeFile(dir + "/broken/methods/vsv/shaders/inscatter.frag", "#version 450 core\nvoid main() { nonsense; }\n");
  cmd = env + script + " " + dir + "/broken room vsv:alpha=64:theta=128:phi=128 > " + dir + "/broken.txt 2>&1";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  EXPECT_NE(readFile(dir + "/broken.txt").find("inscatter.frag"), std::string::npos) << readFile(dir + "/broken.txt");
}

// scripts/merge-processes: one benchmark's output from two processes becomes one document with the
// median, the rounds' and the processes' ranges, and a flag where the processes disagree.
TEST(CliTest, MergeProcessesGivesMediansRangesAndFlagsDisagreement) {
  std::string dir = makeTempDir("merge-processes");
  auto doc = [](const std::string& seed, const std::string& agreeing, const std::string& disagreeing,
                const std::string& extra) {
    return "# bench: measured\n\n- seed: " + seed + "\n\n## Equal\n\n| scene | steps | ms | speedup |\n"
           "|---|---|---|---|\n| a | steps=64 | " + agreeing + " | **2.00x** [1.90–2.10] |\n| b | steps=" + seed +
           " | 10.0 | " + disagreeing + " |\n" + extra + "\nVerdict: holds.\n";
  };
  writeFile(dir + "/1.md", doc("1", "93.8 [93.4–96.2]", "**3.25x** [3.17–3.25]", ""));
  writeFile(dir + "/2.md", doc("2", "95.0 [94.0–97.0]", "**4.25x** [4.20–4.30]", "| c | steps=8 | 1.0 | 1.00x |\n"));
  const std::string script = std::string(VS_SOURCE_DIR) + "/scripts/merge-processes";
  std::string cmd = script + " " + dir + "/1.md " + dir + "/2.md > " + dir + "/out.md 2> " + dir + "/err.txt";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readFile(dir + "/err.txt");
  std::string out = readFile(dir + "/out.md");
  // Agreeing processes: the median, the rounds' range over both, the processes' range; no flag.
  EXPECT_NE(out.find("| a | steps=64 | 94.4 [93.4–97.0] {93.8–95.0} | **2.00x** [1.90–2.10] |"), std::string::npos)
      << out;
  // Rounds that do not overlap even widened by 5 %: flagged in the cell, under the table and on stderr.
  EXPECT_NE(out.find("| b | steps=1 / steps=2 | 10.0 | **3.75x** [3.17–4.30] {3.25–4.25} ⚑ |"), std::string::npos)
      << out;
  EXPECT_NE(out.find("⚑ 1 of 2 figures in this table"), std::string::npos) << out;
  EXPECT_NE(readFile(dir + "/err.txt").find("1 figure(s) flagged"), std::string::npos);
  // Prose that differs is given per process; a row only one process printed stays in its table.
  EXPECT_NE(out.find("- process 1: seed: 1\n- process 2: seed: 2"), std::string::npos) << out;
  EXPECT_NE(out.find("| c | steps=8 | 1.0 | 1.00x |\n\n⚑"), std::string::npos) << out;
  EXPECT_NE(out.find("Merged from 2 processes"), std::string::npos) << out;
  EXPECT_EQ(out.find("Verdict: holds."), out.rfind("Verdict: holds."));
  // A missing input: one line, non-zero exit.
  cmd = script + " " + dir + "/1.md " + dir + "/missing.md > " + dir + "/out2.md 2> " + dir + "/err2.txt";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  std::string err = readFile(dir + "/err2.txt");
  EXPECT_NE(err.find("cannot read"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

// scripts/method-readmes: a method README's "Measured" section is written from results/ (its tables,
// verdict lines and flags), and --check fails once results/ says something else.
TEST(CliTest, MethodReadmesQuoteResultsAndGoStaleLoudly) {
  std::string dir = makeTempDir("method-readmes");
  std::filesystem::create_directories(dir + "/scripts");
  std::filesystem::create_directories(dir + "/methods/demo");
  std::filesystem::create_directories(dir + "/results/demo");
  std::filesystem::copy_file(std::string(VS_SOURCE_DIR) + "/scripts/method-readmes", dir + "/scripts/method-readmes");
  writeFile(dir + "/methods/demo/README.md", "# demo\n\n## Parameters\n\n`k`\n");
  writeFile(dir + "/results/demo/README.md",
            "# demo, measured\n\n## Table 1\n\n| a | 1.0 |\n\n⚑ 1 of 2 figures in this table: x\n\n"
            "- Faster than the paper's baseline: holds (3.0x).\n- thresholds: relative\n");
  const std::string script = "python3 " + dir + "/scripts/method-readmes";
  ASSERT_NE(std::system((script + " --check 2> " + dir + "/err.txt").c_str()), 0) << "a missing section passed";
  ASSERT_EQ(std::system((script + " 2> " + dir + "/err.txt").c_str()), 0) << readFile(dir + "/err.txt");
  std::string readme = readFile(dir + "/methods/demo/README.md");
  EXPECT_NE(readme.find("## Parameters\n\n`k`\n\n## Measured"), std::string::npos) << readme;
  EXPECT_NE(readme.find("- [Table 1](../../results/demo/README.md#table-1)"), std::string::npos) << readme;
  EXPECT_NE(readme.find("- Faster than the paper's baseline: holds (3.0x)."), std::string::npos) << readme;
  EXPECT_EQ(readme.find("thresholds"), std::string::npos) << "a line that is not a verdict was quoted";
  EXPECT_NE(readme.find("⚑ 1 of 2 figures"), std::string::npos) << readme;
  EXPECT_EQ(std::system((script + " --check").c_str()), 0);
  // New results: the section is stale until written again, and writing it again keeps one section.
  writeFile(dir + "/results/demo/README.md", "# demo\n\n## Table 1\n\n- Faster: does not hold (0.9x).\n");
  EXPECT_NE(std::system((script + " --check 2> " + dir + "/err.txt").c_str()), 0);
  EXPECT_NE(readFile(dir + "/err.txt").find("methods/demo/README.md"), std::string::npos);
  ASSERT_EQ(std::system((script + " 2> /dev/null").c_str()), 0);
  readme = readFile(dir + "/methods/demo/README.md");
  EXPECT_NE(readme.find("does not hold (0.9x)"), std::string::npos) << readme;
  EXPECT_EQ(readme.find("holds (3.0x)"), std::string::npos) << readme;
  EXPECT_EQ(readme.find("## Measured"), readme.rfind("## Measured")) << readme;
}

TEST(CliTest, KilledSweepKeepsEveryFinishedRow) {
  std::string dir = makeTempDir("killed");
  std::string out = dir + "/out";
  std::string bin = vshadowPath();
  pid_t pid = ::fork();
  if (pid == 0) {
    int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    std::string cache = dir + "/cache";
    ::execl(bin.c_str(), bin.c_str(), "shootout", "--scene", "spheres", "--size", "96x64", "--frames", "30",
            "--out", out.c_str(), "--cache", cache.c_str(), "--no-images", (char*)nullptr);
    ::_exit(127);
  }
  // Wait for the first finished row, then kill without warning.
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  size_t rows = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(out + "/runs.csv")) {
      rows = CsvTable::parse(readFile(out + "/runs.csv")).size();
      if (rows >= 2) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_GE(rows, 2u) << "no row was finished in time";
  auto parsed = CsvTable::parse(readFile(out + "/runs.csv"));
  ASSERT_EQ(parsed[0], runsColumns());
  for (size_t i = 1; i < parsed.size(); ++i) {
    ASSERT_EQ(parsed[i].size(), runsColumns().size());
    EXPECT_EQ(parsed[i][3], "Success");  // the header above pins the column order
  }
  // The meta sidecar is complete JSON (it says the run did not finish).
  auto meta = nlohmann::json::parse(readFile(out + "/meta.json"));
  EXPECT_EQ(meta["status"], "running");
}

TEST(CliTest, MetaRecordsWhetherTheDriverThreadsWerePinned) {
  std::string dir = makeTempDir("pin");
  for (const char* mode : {"on", "off"}) {
    std::string out = dir + "/" + mode;
    CommandResult r = runVshadow({"run", "--scene", "spheres", "--size", "16x12", "--frames", "1", "--warmup", "0",
                                  "--method", "raymarch:steps=4", "--no-reference", "--no-images", "--pin-threads",
                                  mode, "--out", out});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto pinning = nlohmann::json::parse(readFile(out + "/meta.json"))["thread_pinning"];
    EXPECT_EQ(pinning["mode"], mode);
    if (std::string(mode) == "off") {
      EXPECT_EQ(pinning["applied"], false);
      EXPECT_TRUE(pinning["threads"].empty());
    } else {
      EXPECT_EQ(pinning["applied"], !pinning["threads"].empty()) << pinning.dump();
    }
  }
  CommandResult bad = runVshadow({"run", "--scene", "spheres", "--method", "raymarch", "--pin-threads", "always",
                                  "--out", dir + "/bad"});
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_EQ(nonEmptyLines(bad.err), 1) << bad.err;
  EXPECT_FALSE(fs::exists(dir + "/bad"));
}

TEST(CliTest, RoundsInterleaveTheRowsAndShowTheirSpread) {
  std::string dir = makeTempDir("rounds");
  std::string out = dir + "/out";
  CommandResult r = runVshadow({"run", "--scene", "spheres", "--size", "24x18", "--frames", "2", "--warmup", "0",
                                "--rounds", "3", "--method", "raymarch:steps=8", "--method", "minmax", "--method",
                                "dsm", "--out", out, "--cache", dir + "/cache", "--no-images", "--strict-gl"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // Round by round, each job in turn: A B, A B, A B (the progress lines name the rounds).
  size_t a1 = r.err.find("raymarch"), b1 = r.err.find("minmax"), a2 = r.err.find("raymarch", b1);
  ASSERT_NE(a2, std::string::npos) << r.err;
  EXPECT_LT(a1, b1);
  EXPECT_NE(r.err.find("(round 3/3)"), std::string::npos) << r.err;
  CsvTable runs = loadCsv(out + "/runs.csv", runsColumns(), kRunsKeyColumns);
  ASSERT_EQ(runs.rows().size(), 3u);
  for (const auto& row : runs.rows()) {
    if (field(runs, row, "method") == "dsm") {  // no volumes: one row, written once
      EXPECT_EQ(field(runs, row, "status"), "Unsupported");
      EXPECT_EQ(field(runs, row, "rounds"), "");
      continue;
    }
    EXPECT_EQ(field(runs, row, "status"), "Success");
    EXPECT_EQ(field(runs, row, "rounds"), "3");
    double median = std::stod(field(runs, row, "frame_median_ms"));
    double lo = std::stod(field(runs, row, "frame_round_min_ms")), hi = std::stod(field(runs, row, "frame_round_max_ms"));
    EXPECT_LE(lo, median);
    EXPECT_LE(median, hi);
    double scatter = std::stod(field(runs, row, "scatter_ms"));
    EXPECT_GT(scatter, 0.0);
    EXPECT_LE(std::stod(field(runs, row, "scatter_round_min_ms")), std::stod(field(runs, row, "scatter_round_max_ms")));
  }
  CsvTable passes = loadCsv(out + "/passes.csv", passesColumns(), kPassesKeyColumns);
  int frames = 0;
  for (const auto& row : passes.rows()) {
    if (field(passes, row, "pass") != "Frame") continue;
    ++frames;
    EXPECT_EQ(field(passes, row, "rounds"), "3");
    EXPECT_EQ(field(passes, row, "frames"), "6");  // every round's frames
    EXPECT_LE(std::stod(field(passes, row, "round_min_ms")), std::stod(field(passes, row, "median_ms")));
    EXPECT_LE(std::stod(field(passes, row, "median_ms")), std::stod(field(passes, row, "round_max_ms")));
  }
  EXPECT_EQ(frames, 2);
  auto meta = nlohmann::json::parse(readFile(out + "/meta.json"));
  EXPECT_EQ(meta["rounds"], 3);
}

TEST(CliTest, RoundsOutOfRangeAreRefused) {
  std::string dir = makeTempDir("rounds-bad");
  CommandResult r = runVshadow({"run", "--scene", "spheres", "--size", "16x16", "--rounds", "0", "--method", "raymarch",
                                "--out", dir + "/out"});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_FALSE(fs::exists(dir + "/out/runs.csv"));
}

}  // namespace
}  // namespace vs::testing

namespace vs::testing {
namespace {

TEST(CliTest, EqualQualityColumnsNameTheBaselineAndItsStepsAtTheRowsError) {
  std::string dir = makeTempDir("equal-quality");
  CommandResult r = runVshadow({"shootout", "--scene", "spheres", "--method", "minmax", "--size", "48x36", "--frames",
                                "1", "--warmup", "0", "--no-images", "--equal-quality", "--rounds", "2", "--out",
                                dir + "/out", "--cache", dir + "/cache", "--drift-threshold", "0"});  // no repeats
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto rows = CsvTable::parse(readFile(dir + "/out/runs.csv"));
  ASSERT_GT(rows.size(), 1u);
  auto col = [&](const std::string& name) {
    auto it = std::find(rows[0].begin(), rows[0].end(), name);
    EXPECT_NE(it, rows[0].end()) << name;
    return size_t(it - rows[0].begin());
  };
  int timedBaselines = 0;
  for (size_t i = 1; i < rows.size(); ++i) {
    const auto& row = rows[i];
    ASSERT_EQ(row[col("status")], "Success") << row[col("reason")];
    double scatter = std::stod(row[col("scatter_ms")]);
    EXPECT_GT(scatter, 0.0);
    EXPECT_LT(scatter, std::stod(row[col("frame_median_ms")]) + 1e-9);  // the method's own passes only
    // A point light: both baselines, uniform (the papers') and equiangular (the strong one).
    for (const char* baseline : {"uniform", "equiangular"}) {
      std::string steps = row[col(std::string("eq_") + baseline + "_steps")];
      ASSERT_FALSE(steps.empty()) << baseline;
      int n = std::stoi(steps.rfind(">=", 0) == 0 ? steps.substr(2) : steps);
      EXPECT_GE(n, 1);
      EXPECT_LE(n, 4096);
      std::string speedup = row[col(std::string("speedup_eq_") + baseline)];
      EXPECT_GT(std::stod(speedup.rfind(">=", 0) == 0 ? speedup.substr(2) : speedup), 0.0);
      EXPECT_FALSE(row[col(std::string("equal_time_ls_rmse_") + baseline)].empty());
      if (steps.rfind(">=", 0) == 0) continue;  // a bound keeps the bisection's time
      // A reached baseline is timed beside the row in each round: its median lies in its range, and
      // the speedup (the median of the rounds' ratios) in the ratios' range.
      std::string prefix = std::string("eq_") + baseline;
      double ms = std::stod(row[col(prefix + "_ms")]);
      EXPECT_LE(std::stod(row[col(prefix + "_round_min_ms")]), ms + 1e-9);
      EXPECT_LE(ms, std::stod(row[col(prefix + "_round_max_ms")]) + 1e-9);
      std::string ratio = std::string("speedup_eq_") + baseline;
      EXPECT_LE(std::stod(row[col(ratio + "_round_min")]), std::stod(speedup) + 1e-9);
      EXPECT_LE(std::stod(speedup), std::stod(row[col(ratio + "_round_max")]) + 1e-9);
      ++timedBaselines;
    }
  }
  // Each reached baseline was timed once per round, right after its row.
  size_t notes = 0;
  for (size_t at = r.err.find("equal quality: timing raymarch"); at != std::string::npos;
       at = r.err.find("equal quality: timing raymarch", at + 1))
    ++notes;
  EXPECT_GT(timedBaselines, 0);
  EXPECT_EQ(notes, size_t(2 * timedBaselines)) << r.err;
  // Without the flag the columns stay empty (the bisection costs baseline runs).
  CommandResult plain = runVshadow({"run", "--scene", "spheres", "--method", "minmax", "--size", "32x24", "--frames", "1",
                                    "--warmup", "0", "--no-images", "--out", dir + "/plain", "--cache", dir + "/cache"});
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  auto plainRows = CsvTable::parse(readFile(dir + "/plain/runs.csv"));
  ASSERT_EQ(plainRows.size(), 2u);
  EXPECT_TRUE(plainRows[1][col("eq_uniform_steps")].empty());
  EXPECT_FALSE(plainRows[1][col("scatter_ms")].empty());
}

}  // namespace
}  // namespace vs::testing

namespace vs::testing {
namespace {

// The match is fair: the row's L_s error and the baseline's are both taken against the exact
// ground truth, so raymarch gains nothing from sharing the reference's 2x2 PCF. Checked by running
// the matched baseline and one step fewer against the same (cached) ground truth, on the fence,
// whose wires alias in the shadow map (matched against the reference, the step count differs).
TEST(CliTest, EqualQualityIsMatchedAgainstTheExactGroundTruth) {
  std::string dir = makeTempDir("equal-quality-exact");
  std::string cache = dir + "/cache";
  CommandResult r = runVshadow({"shootout", "--scene", "fence", "--method", "minmax", "--rungs", "first", "--size",
                                "48x36", "--frames", "1", "--warmup", "0", "--no-images", "--equal-quality", "--out",
                                dir + "/out", "--cache", cache, "--drift-threshold", "0"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  CsvTable runs = loadCsv(dir + "/out/runs.csv", runsColumns(), kRunsKeyColumns);
  ASSERT_EQ(runs.rows().size(), 1u);
  const auto& row = runs.rows()[0];
  EXPECT_EQ(field(runs, row, "eq_error_against"), "exact");
  double target = std::stod(field(runs, row, "exact_ls_relmse"));
  std::string steps = field(runs, row, "eq_uniform_steps");
  ASSERT_FALSE(steps.empty());
  ASSERT_NE(steps.rfind(">=", 0), 0u) << "the baseline should reach minmax's first rung at 48x36";
  auto meta = nlohmann::json::parse(readFile(dir + "/out/meta.json"));
  EXPECT_EQ(meta["equal_quality"]["error_against"], "exact");
  EXPECT_EQ(meta["exact"]["from_cache"], false);

  auto exactError = [&](int n, const std::string& out) {
    CommandResult b = runVshadow({"run", "--scene", "fence", "--method",
                                  "raymarch:sampling=uniform:steps=" + std::to_string(n) + ":sm=" +
                                      field(runs, row, "shadow_map"),
                                  "--size", "48x36", "--frames", "1", "--warmup", "1", "--no-images", "--exact",
                                  "--out", out, "--cache", cache});
    EXPECT_EQ(b.exitCode, 0) << b.err;
    // The second computation of the same ground truth is read from the cache.
    EXPECT_EQ(nlohmann::json::parse(readFile(out + "/meta.json"))["exact"]["from_cache"], true);
    CsvTable t = loadCsv(out + "/runs.csv", runsColumns(), kRunsKeyColumns);
    return t.rows().empty() ? -1.0 : std::stod(field(t, t.rows()[0], "exact_ls_relmse"));
  };
  int n = std::stoi(steps);
  EXPECT_LE(exactError(n, dir + "/at"), target);
  if (n > 1) {
    EXPECT_GT(exactError(n - 1, dir + "/below"), target);
  }
  // The ray-marched reference plays no part in the match: a far worse one changes every reference
  // error column but not the matched step counts.
  CommandResult coarse = runVshadow({"shootout", "--scene", "fence", "--method", "minmax", "--rungs", "first", "--size",
                                     "48x36", "--frames", "1", "--warmup", "0", "--no-images", "--equal-quality",
                                     "--reference", "raymarch:steps=3", "--out", dir + "/coarse", "--cache", cache});
  ASSERT_EQ(coarse.exitCode, 0) << coarse.err;
  CsvTable coarseRuns = loadCsv(dir + "/coarse/runs.csv", runsColumns(), kRunsKeyColumns);
  ASSERT_EQ(coarseRuns.rows().size(), 1u);
  const auto& coarseRow = coarseRuns.rows()[0];
  EXPECT_NE(field(coarseRuns, coarseRow, "ls_relmse"), field(runs, row, "ls_relmse"));
  for (const char* column : {"eq_uniform_steps", "eq_equiangular_steps", "exact_ls_relmse"})
    EXPECT_EQ(field(coarseRuns, coarseRow, column), field(runs, row, column)) << column;

  // A light texture, which the ground truth does not model: matched against the reference, and the
  // row says so.
  Image gobo(2, 2);
  gobo.rgb.assign(gobo.rgb.size(), 1.0f);
  writeExr(dir + "/gobo.exr", gobo);
  writeFile(dir + "/textured.json", R"({
    "geometry": [{"generator": "plane", "params": {"center": [0, 0, 0], "size": [20, 20]}, "albedo": [0.7, 0.7, 0.7]},
                 {"generator": "sphere", "params": {"center": [0, 2, -1], "radius": 1.0, "segments": 16}, "albedo": [0.8, 0.8, 0.8]}],
    "camera": {"position": [0, 2.2, 8], "target": [0, 2.0, -1], "fov_y_deg": 60, "near": 0.1, "far": 50},
    "light": {"type": "spot", "position": [0, 6, -1], "direction": [0, -1, 0], "spot_inner_deg": 30,
              "spot_outer_deg": 40, "intensity": 100, "texture": "gobo.exr"},
    "medium": {"sigma_s": 0.1, "sigma_a": 0.01}})");
  CommandResult t = runVshadow({"shootout", "--scene", dir + "/textured.json", "--method", "minmax", "--rungs", "first",
                                "--size", "32x24", "--frames", "1", "--warmup", "0", "--no-images", "--equal-quality",
                                "--out", dir + "/textured", "--cache", cache});
  ASSERT_EQ(t.exitCode, 0) << t.err;
  CsvTable textured = loadCsv(dir + "/textured/runs.csv", runsColumns(), kRunsKeyColumns);
  ASSERT_EQ(textured.rows().size(), 1u);
  EXPECT_EQ(field(textured, textured.rows()[0], "eq_error_against").rfind("reference (", 0), 0u);
  EXPECT_FALSE(field(textured, textured.rows()[0], "eq_uniform_steps").empty());
}

}  // namespace
}  // namespace vs::testing

namespace vs::testing {
namespace {

// --rungs picks rungs of every ladder series by position: on a point light raymarch has two series
// of six rungs (uniform and equiangular steps, the two brute-force baselines), first and middle
// (6/2 = 3) of each.
TEST(CliTest, RungsPicksPositionsOfEachLadderSeries) {
  std::string dir = makeTempDir("rungs");
  CommandResult r = runVshadow({"shootout", "--scene", "spheres", "--method", "raymarch", "--rungs", "first,middle",
                                "--rungs", "99", "--size", "32x24", "--frames", "1", "--warmup", "0", "--no-images",
                                "--out", dir + "/out", "--cache", dir + "/cache"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto rows = CsvTable::parse(readFile(dir + "/out/runs.csv"));
  ASSERT_EQ(rows.size(), 5u);
  auto col = [&](const std::string& name) { return size_t(std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin()); };
  const size_t params = col("params"), series = col("series");
  EXPECT_EQ(rows[1][params].rfind("steps=8:", 0), 0u) << rows[1][params];
  EXPECT_EQ(rows[2][params].rfind("steps=64:", 0), 0u) << rows[2][params];
  for (size_t i : {1u, 2u}) {
    EXPECT_EQ(rows[i][series], "uniform");
    EXPECT_NE(rows[i][params].find("sampling=uniform"), std::string::npos) << rows[i][params];
  }
  for (size_t i : {3u, 4u}) {
    EXPECT_EQ(rows[i][series], "equiangular");
    EXPECT_NE(rows[i][params].find("sampling=equiangular"), std::string::npos) << rows[i][params];
  }
  EXPECT_EQ(rows[3][params].rfind("steps=8:", 0), 0u) << rows[3][params];
  EXPECT_EQ(rows[4][params].rfind("steps=64:", 0), 0u) << rows[4][params];
  // A directional light has no equiangular series: one brute-force curve.
  CommandResult sun = runVshadow({"shootout", "--scene", "terrain", "--method", "raymarch", "--rungs", "first",
                                  "--size", "32x24", "--frames", "1", "--warmup", "0", "--no-images",
                                  "--out", dir + "/sun", "--cache", dir + "/cache"});
  ASSERT_EQ(sun.exitCode, 0) << sun.err;
  auto sunRows = CsvTable::parse(readFile(dir + "/sun/runs.csv"));
  ASSERT_EQ(sunRows.size(), 2u);
  EXPECT_EQ(sunRows[1][series], "uniform");
  // A word that is no position is bad input: exit 2 before anything is written.
  CommandResult bad = runVshadow({"shootout", "--scene", "spheres", "--rungs", "middel", "--out", dir + "/bad"});
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("--rungs: 'middel'"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir + "/bad"));
}

}  // namespace
}  // namespace vs::testing
