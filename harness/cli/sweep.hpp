// Sweeps: a JSON file naming scenes, methods, sizes, seeds and run settings, planned into shards
// (one scene x size x seed x method ladder, or one rung) with stable ids. Each shard runs into its
// own folder OUT/<id>/ through the ordinary run/shootout command, with a marker (shard.json) that
// says whether it finished, so an interrupted sweep redoes only unfinished shards. README "Sweeps".
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/cli/app.hpp"
#include "harness/pipeline/method.hpp"

namespace vs {

struct Sweep {
  std::string source;       // the file it was read from
  std::string description;
  std::vector<std::string> scenes;   // built-in names or absolute paths
  std::vector<std::string> methods;  // a method name (its shootout ladder) or a full spec
  std::vector<std::string> sizes;    // "WxH"
  std::vector<long long> seeds;
  int frames = 8, warmup = 2;
  std::string reference = "default";  // default | none | exact | a method spec
  std::string split = "ladder";       // ladder: one shard per method entry; rung: one per ladder rung
  std::string timer = "auto";
  bool images = false, exact = false, equalQuality = false;
  int exactSteps = 2048;
};

struct Shard {
  int index = 0;
  std::string id;          // stable: scene, size, seed and method spec, e.g. spheres-64x48-s1-raymarch
  std::string scene;       // name or path, as for --scene
  std::string size;
  long long seed = 1;
  std::string method;      // a method name (ladder = true: its ladder) or a spec
  bool ladder = true;
  std::string referenceSpec;  // what --reference gets ("" with reference "none")
  bool noReference = false;
  std::string definition;     // hash of everything that defines the shard's rows
};

// Reads and validates a sweep file: one-line SceneError "FILE: key: problem" or UsageError.
Sweep loadSweep(const std::string& path, const MethodRegistry& registry);
// The normalized sweep (absolute scene paths, every default written out); loadSweep reads it back.
nlohmann::json sweepJson(const Sweep& sweep);
// The shards in a stable order: scene, size, seed, method entry (and rung).
std::vector<Shard> planSweep(const Sweep& sweep, const MethodRegistry& registry);
// The request that runs one shard into `dir`.
RunRequest shardRequest(const Sweep& sweep, const Shard& shard, const std::string& dir, const std::string& cacheDir);

// The marker a shard folder carries: OUT/<id>/shard.json with "status" running|finished|failed.
struct ShardState {
  bool exists = false;
  std::string status, definition, host, reason;
  int exitCode = -1;
};
ShardState readShardState(const std::string& dir);

struct SweepOptions {
  std::string out;              // the sweep's folder
  std::string cacheDir;         // reference cache ("" = default)
  std::vector<std::string> only;  // shard ids or indices ("" = all)
  bool pendingOnly = false;     // plan: list only shards not finished in `out`
  std::string scene;            // reference: the scene whose references to fill
};

// vshadow sweep plan FILE [--out OUT [--pending]]: prints one tab-separated line per shard: index,
// id, scene, size, seed, method entry ("ladder:NAME" or a spec);
// with --out also writes OUT/sweep.json (the normalized sweep the shards run from).
int sweepPlanCommand(const std::string& file, const SweepOptions& options, const MethodRegistry& registry);
// vshadow sweep run FILE OUT [--shard ID|INDEX]...: runs the shards in order, skipping finished ones.
int sweepRunCommand(const std::string& file, const SweepOptions& options, const MethodRegistry& registry);
// vshadow sweep reference FILE --scene NAME: fills the reference cache for every size and seed of
// one scene of the sweep (what each shard of that scene will look up).
int sweepReferenceCommand(const std::string& file, const SweepOptions& options, const MethodRegistry& registry);

}  // namespace vs
