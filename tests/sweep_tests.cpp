// Sweeps and merging: the sweep file's validation, shard plans and their stable ids, a local
// sequential run that resumes (finished shards skipped, interrupted or changed ones redone), and
// merging shard folders (missing and failed shards named, renderers not mixed unless asked).
// The same sweep on a real Slurm cluster: tests/slurm/e2e.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gl_test.hpp"
#include "harness/io/results.hpp"
#include "harness/cli/sweep.hpp"
#include "registry.hpp"
#include "scenes/scene.hpp"

namespace vs::testing {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// Two shards on the smallest scene, at 16x16 with one frame: seconds for the whole sweep.
const char* kTinySweep = R"({
  "description": "test sweep",
  "scenes": ["spheres"],
  "methods": ["raymarch:steps=4", "raymarch:steps=8"],
  "sizes": ["16x16"],
  "seeds": [2],
  "frames": 1,
  "warmup": 0,
  "timer": "wall"
})";

std::string writeSweep(const std::string& dir, const std::string& text, const std::string& name = "sweep.json") {
  std::string path = dir + "/" + name;
  writeFile(path, text);
  return path;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) out.push_back(line);
  return out;
}

// Every entry of a folder, as a shell's DIR/* would list them.
std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string()[0] != '.') out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::vector<std::string>> csvRows(const std::string& path) { return CsvTable::parse(readFile(path)); }

size_t column(const std::vector<std::string>& header, const std::string& name) {
  auto it = std::find(header.begin(), header.end(), name);
  EXPECT_NE(it, header.end()) << name;
  return size_t(it - header.begin());
}

CommandResult merge(std::vector<std::string> inputs, const std::string& out, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"merge"};
  args.insert(args.end(), inputs.begin(), inputs.end());
  args.insert(args.end(), {"--out", out});
  args.insert(args.end(), extra.begin(), extra.end());
  return runVshadow(args);
}

TEST(SweepPlanTest, ShardsHaveStableIdsThatSettingsDoNotChange) {
  std::string dir = makeTempDir("sweep-plan");
  std::string file = writeSweep(dir, R"({"scenes": ["spheres", "fence"], "methods": ["raymarch", "minmax:rank=2"],
                                         "sizes": ["64x48", "32x32"], "seeds": [1, 7]})");
  CommandResult r = runVshadow({"sweep", "plan", file});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::vector<std::string> plan = lines(r.out);
  ASSERT_EQ(plan.size(), 2u * 2u * 2u * 2u);
  EXPECT_EQ(plan[0], "0\tspheres-64x48-s1-raymarch\tspheres\t64x48\t1\tladder:raymarch");
  EXPECT_EQ(plan[1], "1\tspheres-64x48-s1-minmax_rank-2\tspheres\t64x48\t1\tminmax:rank=2");
  EXPECT_EQ(plan[15], "15\tfence-32x32-s7-minmax_rank-2\tfence\t32x32\t7\tminmax:rank=2");
  // The same file plans the same shards; other frames keep the ids but change the definitions.
  EXPECT_EQ(runVshadow({"sweep", "plan", file}).out, r.out);
  std::string file2 = writeSweep(dir, R"({"scenes": ["spheres", "fence"], "methods": ["raymarch", "minmax:rank=2"],
                                          "sizes": ["64x48", "32x32"], "seeds": [1, 7], "frames": 3})",
                                 "frames.json");
  EXPECT_EQ(runVshadow({"sweep", "plan", file2}).out, r.out);
  auto a = planSweep(loadSweep(file, registeredMethods()), registeredMethods());
  auto b = planSweep(loadSweep(file2, registeredMethods()), registeredMethods());
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_NE(a[i].definition, b[i].definition);
  }
}

TEST(SweepPlanTest, RungSplitGivesOneShardPerRungAndOneReferenceForAll) {
  std::string dir = makeTempDir("sweep-rung");
  std::string file = writeSweep(dir, R"({"scenes": ["spheres"], "methods": ["raymarch", "minmax:sm=2048"],
                                         "split": "rung"})");
  auto shards = planSweep(loadSweep(file, registeredMethods()), registeredMethods());
  size_t rungs = createMethod("raymarch")->qualityLadder().size();
  ASSERT_EQ(shards.size(), rungs + 1);
  EXPECT_EQ(shards[0].id, "spheres-512x512-s1-raymarch_steps-8");
  EXPECT_FALSE(shards[0].ladder);
  // The largest shadow map of the sweep makes the one reference every shard compares against.
  for (const auto& s : shards) {
    EXPECT_EQ(s.referenceSpec, shards[0].referenceSpec);
    EXPECT_NE(s.referenceSpec.find(":sm=2048"), std::string::npos) << s.referenceSpec;
  }
}

TEST(SweepPlanTest, SceneFilesResolveAgainstTheSweepFile) {
  std::string dir = makeTempDir("sweep-scene");
  fs::create_directories(dir + "/scenes");
  writeFile(dir + "/scenes/mine.json", readFile(std::string(VS_SOURCE_DIR) + "/scenes/builtin/spheres.json"));
  std::string file = writeSweep(dir, R"({"scenes": ["scenes/mine.json"], "methods": ["raymarch:steps=4"]})");
  Sweep sweep = loadSweep(file, registeredMethods());
  ASSERT_EQ(sweep.scenes.size(), 1u);
  EXPECT_EQ(sweep.scenes[0], dir + "/scenes/mine.json");
  EXPECT_EQ(planSweep(sweep, registeredMethods())[0].id, "mine-512x512-s1-raymarch_steps-4");
}

struct BadSweep {
  const char* name;
  const char* text;
  const char* expect;
};

class BadSweepTest : public ::testing::TestWithParam<BadSweep> {};

TEST_P(BadSweepTest, OneLineExitTwoNothingWritten) {
  const BadSweep& bad = GetParam();
  std::string dir = makeTempDir("sweep-bad");
  std::string file = writeSweep(dir, bad.text);
  std::string out = dir + "/out";
  fs::create_directories(out);
  writeFile(out + "/sentinel", "kept\n");
  for (std::vector<std::string> args : {std::vector<std::string>{"sweep", "plan", file, "--out", out},
                                        std::vector<std::string>{"sweep", "run", file, out}}) {
    CommandResult r = runVshadow(args);
    EXPECT_EQ(r.exitCode, 2) << bad.name << ": " << r.err;
    EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(bad.expect), std::string::npos) << bad.name << ": " << r.err;
    EXPECT_EQ(entries(out), std::vector<std::string>{out + "/sentinel"}) << bad.name;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadSweepTest,
    ::testing::Values(
        BadSweep{"Syntax", R"({"scenes": ["spheres"],})", "malformed JSON"},
        BadSweep{"MisspeltKey", R"({"scenes": ["spheres"], "methods": ["raymarch"], "seed": [1]})",
                 "seed: unknown key (did you mean 'seeds'?)"},
        BadSweep{"NoScenes", R"({"methods": ["raymarch"]})", "scenes: missing required key"},
        BadSweep{"UnknownScene", R"({"scenes": ["sphere"], "methods": ["raymarch"]})", "scenes[0]: "},
        BadSweep{"UnknownMethod", R"({"scenes": ["spheres"], "methods": ["nosuch"]})",
                 "methods[0]: unknown method 'nosuch'"},
        BadSweep{"BadParameter", R"({"scenes": ["spheres"], "methods": ["raymarch:steps=0"]})",
                 "methods[0]: method 'raymarch': steps=0: out of range"},
        BadSweep{"BadSize", R"({"scenes": ["spheres"], "methods": ["raymarch"], "sizes": ["big"]})",
                 "sizes[0]: 'big': expected WxH"},
        BadSweep{"TwiceListed", R"({"scenes": ["spheres", "spheres"], "methods": ["raymarch"]})",
                 "scenes[1]: 'spheres' is listed twice"},
        BadSweep{"BadSplit", R"({"scenes": ["spheres"], "methods": ["raymarch"], "split": "pass"})", "split"},
        BadSweep{"NegativeSeed", R"({"scenes": ["spheres"], "methods": ["raymarch"], "seeds": [-1]})", "seeds[0]"},
        BadSweep{"ZeroFrames", R"({"scenes": ["spheres"], "methods": ["raymarch"], "frames": 0})", "frames"}),
    [](const ::testing::TestParamInfo<BadSweep>& info) { return info.param.name; });

TEST(SweepRunTest, RunsEveryShardIntoItsFolderAndResumes) {
  std::string dir = makeTempDir("sweep-run");
  std::string file = writeSweep(dir, kTinySweep);
  std::string out = dir + "/out", cache = dir + "/cache";
  CommandResult r = runVshadow({"sweep", "run", file, out, "--cache", cache});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string a = "spheres-16x16-s2-raymarch_steps-4", b = "spheres-16x16-s2-raymarch_steps-8";
  EXPECT_EQ(entries(out), (std::vector<std::string>{out + "/" + a, out + "/" + b, out + "/sweep.json"}));
  for (const auto& id : {a, b}) {
    ShardState st = readShardState(out + "/" + id);
    EXPECT_EQ(st.status, "finished") << id;
    EXPECT_EQ(json::parse(readFile(out + "/" + id + "/meta.json"))["seed"], 2);
    EXPECT_EQ(csvRows(out + "/" + id + "/runs.csv").size(), 2u);  // header + one row
  }

  // Again: nothing to do.
  r = runVshadow({"sweep", "run", file, out, "--cache", cache});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find(a + ": finished already, skipped"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(b + ": finished already, skipped"), std::string::npos) << r.out;

  // A shard killed half-way (marker still "running", a torn table) is redone, and only it.
  json marker = json::parse(readFile(out + "/" + b + "/shard.json"));
  marker["status"] = "running";
  writeFile(out + "/" + b + "/shard.json", marker.dump());
  writeFile(out + "/" + b + "/runs.csv", "scene,method\ntorn");
  r = runVshadow({"sweep", "run", file, out, "--cache", cache});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find(a + ": finished already, skipped"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(b + ": running"), std::string::npos) << r.out;
  EXPECT_EQ(readShardState(out + "/" + b).status, "finished");
  EXPECT_EQ(csvRows(out + "/" + b + "/runs.csv").front(), runsColumns());

  // One shard by id or by index.
  r = runVshadow({"sweep", "plan", file, "--out", out, "--pending"});
  EXPECT_EQ(r.out, "");
  r = runVshadow({"sweep", "run", file, out, "--cache", cache, "--shard", "7"});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--shard '7': the sweep has no such shard"), std::string::npos) << r.err;

  // Other settings redo every shard (same ids, new definitions).
  std::string changed = kTinySweep;
  changed.replace(changed.find("\"frames\": 1"), 11, "\"frames\": 2");
  writeFile(file, changed);
  r = runVshadow({"sweep", "plan", file, "--out", out, "--pending"});
  EXPECT_EQ(lines(r.out).size(), 2u) << r.out;
  r = runVshadow({"sweep", "run", file, out, "--cache", cache, "--shard", a});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find(a + ": running"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(b), std::string::npos) << r.out;
  EXPECT_EQ(json::parse(readFile(out + "/" + a + "/meta.json"))["frames"], 2);
}

TEST(SweepRunTest, AFolderWithoutAMarkerIsNotOverwritten) {
  std::string dir = makeTempDir("sweep-foreign");
  std::string file = writeSweep(dir, kTinySweep);
  std::string out = dir + "/out";
  fs::create_directories(out + "/spheres-16x16-s2-raymarch_steps-4");
  writeFile(out + "/spheres-16x16-s2-raymarch_steps-4/runs.csv", "mine\n");
  CommandResult r = runVshadow({"sweep", "run", file, out, "--cache", dir + "/cache"});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("holds files but no shard marker"), std::string::npos) << r.err;
  EXPECT_EQ(readFile(out + "/spheres-16x16-s2-raymarch_steps-4/runs.csv"), "mine\n");
}

TEST(SweepRunTest, ReferenceCommandFillsTheCacheEveryShardReads) {
  std::string dir = makeTempDir("sweep-ref");
  std::string file = writeSweep(dir, kTinySweep);
  std::string cache = dir + "/cache";
  CommandResult r = runVshadow({"sweep", "reference", file, "--scene", "spheres", "--cache", cache});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("reference spheres 16x16 seed 2: computed"), std::string::npos) << r.out;
  r = runVshadow({"sweep", "run", file, dir + "/out", "--cache", cache});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (const auto& shard : entries(dir + "/out")) {
    if (!fs::is_directory(shard)) continue;
    EXPECT_EQ(json::parse(readFile(shard + "/meta.json"))["reference"]["from_cache"], true) << shard;
  }
  r = runVshadow({"sweep", "reference", file, "--scene", "fence", "--cache", cache});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--scene 'fence': not a scene of"), std::string::npos) << r.err;
}

// The Slurm submission without a cluster: the sbatch calls it would make.
TEST(SlurmSweepTest, DryRunSubmitsAReferenceJobPerSceneThenADependentArray) {
  std::string dir = makeTempDir("sweep-dry");
  std::string file = writeSweep(dir, R"({"scenes": ["spheres", "fence"], "methods": ["raymarch:steps=4", "minmax"],
                                         "sizes": ["16x16"], "frames": 1, "warmup": 0})");
  std::string out = dir + "/out";
  std::string command = std::string(VS_SOURCE_DIR) + "/scripts/slurm-sweep --dry-run --gres gpu:1 --partition gpus " +
                        "--max-parallel 2 --vshadow " + vshadowPath() + " " + file + " " + out + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string text;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, pipe)) text.append(buf, n);
  ASSERT_EQ(::pclose(pipe), 0) << text;
  std::vector<std::string> sbatch, submitted;
  for (const auto& line : lines(text)) {
    if (line.rfind("sbatch ", 0) == 0) sbatch.push_back(line);
    if (line.rfind("submitted ", 0) == 0) submitted.push_back(line);
  }
  ASSERT_EQ(sbatch.size(), 3u) << text;
  ASSERT_EQ(submitted.size(), 3u) << text;
  EXPECT_NE(sbatch[0].find("sweep reference " + out + "/sweep.json --scene spheres"), std::string::npos) << sbatch[0];
  EXPECT_NE(sbatch[1].find("--scene fence"), std::string::npos) << sbatch[1];
  for (const auto& s : sbatch) {
    EXPECT_NE(s.find("--gres=gpu:1"), std::string::npos) << s;
    EXPECT_NE(s.find("--partition=gpus"), std::string::npos) << s;
  }
  EXPECT_NE(sbatch[2].find("--array=0,1,2,3%2"), std::string::npos) << sbatch[2];
  EXPECT_NE(sbatch[2].find("--dependency=afterok:"), std::string::npos) << sbatch[2];
  EXPECT_NE(sbatch[2].find("SLURM_ARRAY_TASK_ID"), std::string::npos) << sbatch[2];
  EXPECT_EQ(submitted[2].rfind("submitted array ", 0), 0u);
  EXPECT_EQ(submitted[2].substr(submitted[2].rfind(' ') + 1), "4");
  EXPECT_TRUE(fs::exists(out + "/sweep.json"));
}

class MergeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = makeTempDir("sweep-merge");
    file_ = writeSweep(dir_, kTinySweep);
    out_ = dir_ + "/out";
    CommandResult r = runVshadow({"sweep", "run", file_, out_, "--cache", dir_ + "/cache"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  // A copy of the sweep's folder to spoil.
  std::string copy(const std::string& tag) {
    std::string to = makeTempDir("sweep-merge-" + tag) + "/out";
    fs::copy(out_, to, fs::copy_options::recursive);
    return to;
  }
  static std::string dir_, file_, out_;
};
std::string MergeTest::dir_, MergeTest::file_, MergeTest::out_;

TEST_F(MergeTest, CompleteSweepMergesWithHostRendererSeedAndShardPerRow) {
  std::string merged = dir_ + "/merged";
  CommandResult r = merge(entries(out_), merged);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.err, "");
  auto runs = csvRows(merged + "/runs.csv");
  ASSERT_EQ(runs.size(), 3u);
  const auto& h = runs[0];
  EXPECT_EQ(std::vector<std::string>(h.begin(), h.begin() + long(runsColumns().size())), runsColumns());
  EXPECT_EQ(runs[1][column(h, "params")].rfind("steps=4:", 0), 0u);
  EXPECT_EQ(runs[2][column(h, "params")].rfind("steps=8:", 0), 0u);
  for (size_t i = 1; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i][column(h, "seed")], "2");
    EXPECT_FALSE(runs[i][column(h, "host")].empty());
    EXPECT_FALSE(runs[i][column(h, "renderer")].empty());
    EXPECT_EQ(runs[i][column(h, "shard")], i == 1 ? "spheres-16x16-s2-raymarch_steps-4" : "spheres-16x16-s2-raymarch_steps-8");
  }
  auto passes = csvRows(merged + "/passes.csv");
  size_t shardPasses = csvRows(out_ + "/spheres-16x16-s2-raymarch_steps-4/passes.csv").size() - 1 +
                       csvRows(out_ + "/spheres-16x16-s2-raymarch_steps-8/passes.csv").size() - 1;
  EXPECT_EQ(passes.size() - 1, shardPasses);
  EXPECT_EQ(passes[1][column(passes[0], "width")], "16");
  json meta = json::parse(readFile(merged + "/meta.json"));
  EXPECT_EQ(meta["status"], "complete");
  EXPECT_EQ(meta["shards"].size(), 2u);
  EXPECT_EQ(meta["renderers"].size(), 1u);
}

TEST_F(MergeTest, MissingAndFailedShardsAreNamed) {
  std::string out = copy("missing");
  fs::remove_all(out + "/spheres-16x16-s2-raymarch_steps-4");
  json marker = json::parse(readFile(out + "/spheres-16x16-s2-raymarch_steps-8/shard.json"));
  marker["status"] = "running";
  writeFile(out + "/spheres-16x16-s2-raymarch_steps-8/shard.json", marker.dump());
  std::string merged = out + "-merged";
  CommandResult r = merge(entries(out), merged);
  EXPECT_EQ(r.exitCode, 3);
  EXPECT_NE(r.err.find("missing shard spheres-16x16-s2-raymarch_steps-4"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("failed shard spheres-16x16-s2-raymarch_steps-8: did not finish"), std::string::npos) << r.err;
  EXPECT_EQ(csvRows(merged + "/runs.csv").size(), 1u);  // the header only
  json meta = json::parse(readFile(merged + "/meta.json"));
  EXPECT_EQ(meta["status"], "incomplete");
  EXPECT_EQ(meta["missing"], json::array({"spheres-16x16-s2-raymarch_steps-4"}));
}

TEST_F(MergeTest, RowsFromDifferentRenderersAreRefusedUnlessAllowed) {
  std::string out = copy("mixed");
  std::string runsPath = out + "/spheres-16x16-s2-raymarch_steps-8/runs.csv";
  CsvTable table(runsColumns(), kRunsKeyColumns);
  table.loadExisting(runsPath);
  auto rows = table.rows();
  ASSERT_EQ(rows.size(), 1u);
  size_t renderer = column(runsColumns(), "renderer");
  rows[0][renderer] = "Some GPU/PCIe/SSE2";
  writeFile(runsPath, CsvTable::format(runsColumns()) + CsvTable::format(rows[0]));
  std::string merged = out + "-merged";
  CommandResult r = merge(entries(out), merged);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("come from different renderers"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--allow-mixed-renderers"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(merged));
  r = merge(entries(out), merged, {"--allow-mixed-renderers"});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  json meta = json::parse(readFile(merged + "/meta.json"));
  EXPECT_EQ(meta["mixed_renderers"], true);
  EXPECT_EQ(meta["renderers"].size(), 2u);
}

TEST_F(MergeTest, BadInputsWriteNothing) {
  std::string merged = dir_ + "/not-written";
  CommandResult r = merge({dir_ + "/nowhere"}, merged);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("no such file or folder"), std::string::npos) << r.err;
  auto twice = entries(out_);
  twice.push_back(out_ + "/spheres-16x16-s2-raymarch_steps-4");
  r = merge(twice, merged);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("is given twice"), std::string::npos) << r.err;
  r = merge(entries(out_), out_ + "/spheres-16x16-s2-raymarch_steps-4");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("is also an input"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(merged));
}

// A shard run with other settings than the sweep now defines is not merged: it is named to rerun.
TEST_F(MergeTest, StaleShardIsNamedToRerun) {
  std::string out = copy("stale");
  std::string markerPath = out + "/spheres-16x16-s2-raymarch_steps-4/shard.json";
  json marker = json::parse(readFile(markerPath));
  marker["definition"] = "0000000000000000";
  writeFile(markerPath, marker.dump());
  std::string merged = out + "-merged";
  CommandResult r = merge(entries(out), merged);
  EXPECT_EQ(r.exitCode, 3);
  EXPECT_NE(r.err.find("failed shard spheres-16x16-s2-raymarch_steps-4: run with other settings than the sweep now "
                       "defines (rerun it)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(csvRows(merged + "/runs.csv").size(), 2u);  // the header and the other shard's row
  json meta = json::parse(readFile(merged + "/meta.json"));
  EXPECT_EQ(meta["status"], "incomplete");
  EXPECT_EQ(meta["failed"][0]["id"], "spheres-16x16-s2-raymarch_steps-4");
}

// Result folders without a shard marker: their meta.json says whether they finished, a row in two
// of them is refused, failure rows are counted, folders of neither kind are skipped.
TEST_F(MergeTest, PlainResultFoldersAreCheckedToo) {
  std::string dir = makeTempDir("sweep-merge-plain");
  std::string a = dir + "/a", b = dir + "/b";
  fs::copy(out_ + "/spheres-16x16-s2-raymarch_steps-4", a);
  fs::remove(a + "/shard.json");
  fs::copy(a, b);
  fs::create_directory(dir + "/neither");
  writeFile(dir + "/notes.txt", "not a sweep\n");

  CommandResult r = merge({a, b}, dir + "/twice");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find(" is in both a and b"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/twice"));
  r = merge({a, dir + "/notes.txt"}, dir + "/txt");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("notes.txt: not a result folder or sweep file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/txt"));

  json meta = json::parse(readFile(b + "/meta.json"));
  meta["status"] = "failed";
  writeFile(b + "/meta.json", meta.dump());
  auto runs = csvRows(a + "/runs.csv");
  runs[1][column(runs[0], "status")] = "Failure";
  writeFile(a + "/runs.csv", CsvTable::format(runs[0]) + CsvTable::format(runs[1]));
  r = merge({a, b, dir + "/neither"}, dir + "/merged");
  EXPECT_EQ(r.exitCode, 3);
  EXPECT_NE(r.err.find("skipping " + dir + "/neither: neither a shard nor a result folder"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("shard a: 1 row(s) are failures"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("failed shard b: meta.json does not say finished"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("merged 1 of 2 shard(s), 1 rows"), std::string::npos) << r.out;
  json merged = json::parse(readFile(dir + "/merged/meta.json"));
  EXPECT_EQ(merged["shards"][0]["failure_rows"], 1);
  EXPECT_EQ(merged["missing"], json::array());
}

}  // namespace
}  // namespace vs::testing
