#include "harness/cli/merge.hpp"

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "harness/cli/app.hpp"
#include "harness/io/results.hpp"
#include "scenes/json_reader.hpp"
#include "harness/cli/sweep.hpp"

namespace vs {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string get(size_t row, const std::string& column) const {
    auto it = std::find(header.begin(), header.end(), column);
    return it == header.end() ? "" : rows[row][size_t(it - header.begin())];
  }
};

Table readTable(const std::string& path) {
  Table t;
  std::string text, error;
  if (!readFile(path, text, error)) throw UsageError(path + ": cannot read: " + error);
  auto rows = CsvTable::parse(text);
  if (rows.empty()) throw UsageError(path + ": empty table (no header)");
  t.header = rows.front();
  for (size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].size() == 1 && rows[i][0].empty()) continue;
    if (rows[i].size() != t.header.size())
      throw UsageError(path + ": row " + std::to_string(i) + " has " + std::to_string(rows[i].size()) +
                       " fields, the header " + std::to_string(t.header.size()));
    t.rows.push_back(rows[i]);
  }
  return t;
}

// One input folder.
struct Input {
  std::string dir, id;
  bool shard = false;        // has a shard marker
  int planIndex = -1;        // position in a sweep plan, -1 when none names it
  size_t argIndex = 0;
  std::string status, reason;  // finished | failed | running | ...
  json meta;
  Table runs, passes, frames;  // frames: moving scenes only
  std::string host;
};

std::string metaString(const json& meta, const std::string& key) {
  auto it = meta.find(key);
  if (it == meta.end() || it->is_null()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump();
}

void addColumns(std::vector<std::string>& columns, const std::vector<std::string>& more) {
  for (const auto& c : more)
    if (std::find(columns.begin(), columns.end(), c) == columns.end()) columns.push_back(c);
}

// The rows of a per-row table (passes.csv, frames.csv) in `columns`, each tagged with where it
// comes from: the input's size, seed, host and shard.
void appendTaggedRows(const Table& table, const std::vector<std::string>& columns, const Input& in,
                      const std::string& width, const std::string& height, const std::string& seed,
                      std::vector<std::vector<std::string>>& out) {
  for (size_t r = 0; r < table.rows.size(); ++r) {
    std::vector<std::string> row;
    for (const auto& c : columns) {
      if (c == "seed") row.push_back(seed);
      else if (c == "host") row.push_back(in.host);
      else if (c == "shard") row.push_back(in.id);
      else if (c == "width") row.push_back(width);
      else if (c == "height") row.push_back(height);
      else row.push_back(table.get(r, c));
    }
    out.push_back(std::move(row));
  }
}

// The folders and sweep plans named on the command line.
struct Arguments {
  std::vector<std::string> planFiles;  // canonical paths, each once
  std::vector<Input> inputs;           // in argument order; folders that are neither skipped
};

void addPlan(std::vector<std::string>& planFiles, const std::string& file) {
  std::string canon = fs::weakly_canonical(fs::absolute(file)).string();
  if (std::find(planFiles.begin(), planFiles.end(), canon) == planFiles.end()) planFiles.push_back(canon);
}

// A shard folder's marker: its id and host, its state, and the sweep.json beside it when the
// folder is named after the shard.
void readShardMarker(const std::string& arg, Input& in, std::vector<std::string>& planFiles) {
  std::string text, error;
  readFile((fs::path(arg) / "shard.json").string(), text, error);
  try {
    json s = json::parse(text);
    in.id = s.value("id", in.id);
    in.host = s.value("host", "");
  } catch (const std::exception&) {
  }
  ShardState st = readShardState(arg);
  in.status = st.status;
  in.reason = st.reason;
  fs::path parentPlan = fs::absolute(arg).lexically_normal().parent_path() / "sweep.json";
  if (in.id == fs::path(arg).lexically_normal().filename().string() && fs::exists(parentPlan))
    addPlan(planFiles, parentPlan.string());
}

// Sweep plans: given as files, or found beside the shard folders.
Arguments readArguments(const MergeRequest& req) {
  if (req.inputs.empty()) throw UsageError("merge: no input folders");
  if (req.out.empty()) throw UsageError("merge: --out DIR is required");
  std::error_code ec;
  fs::path outAbs = fs::weakly_canonical(fs::absolute(req.out), ec);
  Arguments args;
  for (size_t i = 0; i < req.inputs.size(); ++i) {
    const std::string& arg = req.inputs[i];
    if (!fs::exists(arg)) throw UsageError("merge: " + arg + ": no such file or folder");
    if (fs::is_regular_file(arg)) {
      if (fs::path(arg).extension() != ".json") throw UsageError("merge: " + arg + ": not a result folder or sweep file");
      addPlan(args.planFiles, arg);
      continue;
    }
    if (fs::weakly_canonical(fs::absolute(arg), ec) == outAbs) throw UsageError("merge: --out " + req.out + " is also an input");
    bool hasShard = fs::exists(fs::path(arg) / "shard.json");
    bool hasRuns = fs::exists(fs::path(arg) / "runs.csv");
    if (!hasShard && !hasRuns) {
      std::fprintf(stderr, "vshadow merge: skipping %s: neither a shard nor a result folder\n", arg.c_str());
      continue;
    }
    Input in;
    in.dir = arg;
    in.argIndex = i;
    in.shard = hasShard;
    in.id = fs::path(arg).lexically_normal().filename().string();
    if (in.id.empty()) in.id = fs::path(arg).lexically_normal().parent_path().filename().string();
    if (hasShard) readShardMarker(arg, in, args.planFiles);
    args.inputs.push_back(std::move(in));
  }
  return args;
}

// The shards the sweep plans define, in plan order, each once.
struct Expected {
  std::vector<Shard> shards;
  std::map<std::string, Shard> byId;
};

Expected expectedShards(const std::vector<std::string>& planFiles, const MethodRegistry& registry) {
  Expected expected;
  for (const auto& file : planFiles) {
    Sweep sweep = loadSweep(file, registry);
    for (Shard& s : planSweep(sweep, registry)) {
      if (expected.byId.count(s.id)) continue;
      s.index = int(expected.shards.size());
      expected.byId[s.id] = s;
      expected.shards.push_back(s);
    }
  }
  return expected;
}

// An input's place in the plan; a finished shard the plan now defines otherwise is stale.
void placeInPlan(Input& in, const Expected& expected) {
  auto it = expected.byId.find(in.id);
  if (it == expected.byId.end()) return;
  in.planIndex = it->second.index;
  if (in.shard && in.status == "finished") {
    ShardState st = readShardState(in.dir);
    if (st.definition != it->second.definition) {
      in.status = "stale";
      in.reason = "run with other settings than the sweep now defines (rerun it)";
    }
  }
}

// meta.json (an object when unreadable) decides a plain folder's status and can fail a shard's;
// a finished input's tables are read.
void readResults(Input& in) {
  std::string metaText, error;
  if (readFile(in.dir + "/meta.json", metaText, error)) {
    try {
      in.meta = json::parse(metaText);
    } catch (const std::exception&) {
      in.meta = json::object();
    }
  }
  if (!in.shard) {
    in.status = metaString(in.meta, "status") == "finished" ? "finished" : "failed";
    if (in.status != "finished") in.reason = "meta.json does not say finished";
  } else if (in.status == "finished" && metaString(in.meta, "status") != "finished") {
    in.status = "failed";
    in.reason = "meta.json does not say finished";
  }
  if (in.status == "running") in.reason = "did not finish (killed, or still running)";
  if (in.status == "finished") {
    in.runs = readTable(in.dir + "/runs.csv");
    if (fs::exists(in.dir + "/passes.csv")) in.passes = readTable(in.dir + "/passes.csv");
    if (fs::exists(in.dir + "/frames.csv")) in.frames = readTable(in.dir + "/frames.csv");
  }
}

// Every input read and given its status, no shard twice; then in plan order, the rest in argument
// order. Returns the ids seen.
std::set<std::string> settleInputs(std::vector<Input>& inputs, const Expected& expected) {
  std::set<std::string> seen;
  for (Input& in : inputs) {
    if (!seen.insert(in.id).second) throw UsageError("merge: shard " + in.id + " is given twice (" + in.dir + ")");
    placeInPlan(in, expected);
    readResults(in);
  }
  std::stable_sort(inputs.begin(), inputs.end(), [](const Input& a, const Input& b) {
    int ka = a.planIndex < 0 ? 1 << 30 : a.planIndex, kb = b.planIndex < 0 ? 1 << 30 : b.planIndex;
    return ka != kb ? ka < kb : a.argIndex < b.argIndex;
  });
  return seen;
}

struct Columns {
  std::vector<std::string> runs, passes, frames;
  bool anyFrames = false;  // frames.csv is written only when an input has one
};

// Columns: this build's, any a folder adds, then where each row comes from.
Columns mergedColumns(const std::vector<Input>& inputs) {
  Columns cols{runsColumns(), passesColumns(), framesColumns()};
  for (const Input& in : inputs) {
    if (in.status != "finished") continue;
    addColumns(cols.runs, in.runs.header);
    addColumns(cols.passes, in.passes.header);
    addColumns(cols.frames, in.frames.header);
    cols.anyFrames = cols.anyFrames || !in.frames.header.empty();
  }
  addColumns(cols.runs, {"seed", "host", "shard"});
  addColumns(cols.passes, {"width", "height", "seed", "host", "shard"});
  addColumns(cols.frames, {"width", "height", "seed", "host", "shard"});
  return cols;
}

// The merged rows and what meta.json says about the inputs they come from.
struct Merged {
  std::vector<std::vector<std::string>> runRows, passRows, frameRows;
  std::map<std::string, std::string> rowOwner;                                  // row key -> shard
  std::map<std::string, std::map<std::string, std::string>> renderersByGroup;  // group -> renderer -> shard
  std::set<std::string> renderers, hosts;
  json shardsMeta = json::array(), failedMeta = json::array();
  int failedShards = 0;
};

// An input's runs.csv rows, tagged; no row twice. Returns how many rows are failures.
int addRunRows(const Input& in, const std::vector<std::string>& columns, const std::string& seed, Merged& m) {
  int failureRows = 0;
  for (size_t r = 0; r < in.runs.rows.size(); ++r) {
    std::vector<std::string> row;
    for (const auto& c : columns) {
      if (c == "seed") row.push_back(seed);
      else if (c == "host") row.push_back(in.host);
      else if (c == "shard") row.push_back(in.id);
      else row.push_back(in.runs.get(r, c));
    }
    std::string size = in.runs.get(r, "width") + "x" + in.runs.get(r, "height");
    std::string key = in.runs.get(r, "scene") + "|" + in.runs.get(r, "method") + "|" + in.runs.get(r, "params") +
                      "|" + size + "|" + seed;
    auto [owner, fresh] = m.rowOwner.emplace(key, in.id);
    if (!fresh)
      throw UsageError("merge: the row " + in.runs.get(r, "scene") + " " + in.runs.get(r, "method") + " " +
                       in.runs.get(r, "params") + " at " + size + " seed " + seed + " is in both " + owner->second +
                       " and " + in.id);
    std::string renderer = in.runs.get(r, "renderer");
    if (!renderer.empty()) {
      m.renderers.insert(renderer);
      m.renderersByGroup[in.runs.get(r, "scene") + " at " + size + " seed " + seed].emplace(renderer, in.id);
    }
    if (in.runs.get(r, "status") == "Failure") ++failureRows;
    m.runRows.push_back(std::move(row));
  }
  return failureRows;
}

// One input into the merge: its rows when it finished, its entry in meta.json's shards either way.
void addInput(const Input& in, const Columns& cols, Merged& m) {
  std::string seed = metaString(in.meta, "seed");
  std::string width = metaString(in.meta, "width"), height = metaString(in.meta, "height");
  json entry = {{"id", in.id}, {"folder", in.dir}, {"status", in.status}, {"host", in.host}};
  if (in.status != "finished") {
    ++m.failedShards;
    m.failedMeta.push_back({{"id", in.id}, {"reason", in.reason}});
    m.shardsMeta.push_back(entry);
    return;
  }
  if (!in.host.empty()) m.hosts.insert(in.host);
  int failureRows = addRunRows(in, cols.runs, seed, m);
  appendTaggedRows(in.passes, cols.passes, in, width, height, seed, m.passRows);
  appendTaggedRows(in.frames, cols.frames, in, width, height, seed, m.frameRows);
  entry["rows"] = in.runs.rows.size();
  entry["failure_rows"] = failureRows;
  entry["renderer"] = in.meta.contains("gl") ? in.meta["gl"].value("renderer", "") : "";
  entry["timer"] = in.meta.contains("timer") ? in.meta["timer"].value("strategy", "") : "";
  entry["git_sha"] = metaString(in.meta, "git_sha");
  entry["date"] = metaString(in.meta, "date");
  entry["meta"] = in.meta;  // the shard's own meta.json: command line, GL, CPU, timer calibration, reference
  m.shardsMeta.push_back(entry);
  if (failureRows > 0)
    std::fprintf(stderr, "vshadow merge: shard %s: %d row(s) are failures (see their reason column)\n", in.id.c_str(),
                 failureRows);
}

// One renderer per scene, size and seed unless allowed: times from two do not compare. Returns
// whether any group has more than one.
bool checkRenderers(const Merged& m, bool allowMixed) {
  bool mixed = false;
  for (const auto& [group, byRenderer] : m.renderersByGroup) {
    if (byRenderer.size() < 2) continue;
    mixed = true;
    if (allowMixed) continue;
    auto a = byRenderer.begin(), b = std::next(a);
    throw UsageError("merge: rows of " + group + " come from different renderers ('" + a->first + "' in " + a->second +
                     ", '" + b->first + "' in " + b->second +
                     "): their times do not compare (--allow-mixed-renderers merges them anyway)");
  }
  return mixed;
}

std::vector<std::string> missingShards(const Expected& expected, const std::set<std::string>& seen) {
  std::vector<std::string> missing;
  for (const Shard& s : expected.shards)
    if (!seen.count(s.id)) missing.push_back(s.id);
  return missing;
}

std::string csvText(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  std::string text = CsvTable::format(header);
  for (const auto& row : rows) text += CsvTable::format(row);
  return text;
}

// Everything checked: runs.csv, passes.csv, frames.csv (when any input has one) and meta.json.
void writeMerged(const MergeRequest& req, const std::vector<std::string>& planFiles, const Columns& cols,
                 const Merged& m, const std::vector<std::string>& missing, bool mixed, bool complete) {
  std::error_code ec;
  fs::create_directories(req.out, ec);
  if (ec || !fs::is_directory(req.out)) throw std::runtime_error("cannot create output folder " + req.out + ": " + ec.message());
  json meta = {{"command_line", req.commandLine},
               {"date", isoDateUtc()},
               {"status", complete ? "complete" : "incomplete"},
               {"sweeps", planFiles},
               {"shards", m.shardsMeta},
               {"missing", missing},
               {"failed", m.failedMeta},
               {"renderers", std::vector<std::string>(m.renderers.begin(), m.renderers.end())},
               {"hosts", std::vector<std::string>(m.hosts.begin(), m.hosts.end())},
               {"mixed_renderers", mixed}};
  writeFileAtomic(req.out + "/runs.csv", csvText(cols.runs, m.runRows));
  writeFileAtomic(req.out + "/passes.csv", csvText(cols.passes, m.passRows));
  if (cols.anyFrames) writeFileAtomic(req.out + "/frames.csv", csvText(cols.frames, m.frameRows));
  writeFileAtomic(req.out + "/meta.json", meta.dump(2) + "\n");
}

int mergeChecked(const MergeRequest& req, const MethodRegistry& registry) {
  Arguments args = readArguments(req);
  Expected expected = expectedShards(args.planFiles, registry);
  std::set<std::string> seen = settleInputs(args.inputs, expected);
  Columns cols = mergedColumns(args.inputs);
  Merged merged;
  for (const Input& in : args.inputs) addInput(in, cols, merged);
  bool mixed = checkRenderers(merged, req.allowMixedRenderers);
  std::vector<std::string> missing = missingShards(expected, seen);
  bool complete = missing.empty() && merged.failedShards == 0;
  writeMerged(req, args.planFiles, cols, merged, missing, mixed, complete);

  // Written: what is missing or failed, then one line on what was merged.
  for (const auto& id : missing) std::fprintf(stderr, "vshadow merge: missing shard %s\n", id.c_str());
  for (const auto& f : merged.failedMeta)
    std::fprintf(stderr, "vshadow merge: failed shard %s: %s\n", f["id"].get<std::string>().c_str(),
                 f["reason"].get<std::string>().c_str());
  std::printf("merged %d of %d shard(s), %zu rows, into %s%s\n", int(args.inputs.size()) - merged.failedShards,
              int(std::max(expected.shards.size(), args.inputs.size())), merged.runRows.size(), req.out.c_str(),
              complete ? "" : " (incomplete)");
  return complete ? 0 : 3;
}

}  // namespace

int mergeCommand(const MergeRequest& request, const MethodRegistry& registry) {
  return reportingErrors([&] { return mergeChecked(request, registry); });
}

}  // namespace vs
