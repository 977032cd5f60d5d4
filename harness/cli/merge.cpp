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

int mergeChecked(const MergeRequest& req, const MethodRegistry& registry) {
  if (req.inputs.empty()) throw UsageError("merge: no input folders");
  if (req.out.empty()) throw UsageError("merge: --out DIR is required");
  std::error_code ec;
  fs::path outAbs = fs::weakly_canonical(fs::absolute(req.out), ec);

  // Sweep plans: given as files, or found beside the shard folders.
  std::vector<std::string> planFiles;
  std::vector<Input> inputs;
  auto addPlan = [&](const std::string& file) {
    std::string canon = fs::weakly_canonical(fs::absolute(file)).string();
    if (std::find(planFiles.begin(), planFiles.end(), canon) == planFiles.end()) planFiles.push_back(canon);
  };
  for (size_t i = 0; i < req.inputs.size(); ++i) {
    const std::string& arg = req.inputs[i];
    if (!fs::exists(arg)) throw UsageError("merge: " + arg + ": no such file or folder");
    if (fs::is_regular_file(arg)) {
      if (fs::path(arg).extension() != ".json") throw UsageError("merge: " + arg + ": not a result folder or sweep file");
      addPlan(arg);
      continue;
    }
    if (fs::weakly_canonical(fs::absolute(arg), ec) == outAbs) throw UsageError("merge: --out " + req.out + " is also an input");
    Input in;
    in.dir = arg;
    in.argIndex = i;
    bool hasShard = fs::exists(fs::path(arg) / "shard.json");
    bool hasRuns = fs::exists(fs::path(arg) / "runs.csv");
    if (!hasShard && !hasRuns) {
      std::fprintf(stderr, "vshadow merge: skipping %s: neither a shard nor a result folder\n", arg.c_str());
      continue;
    }
    in.shard = hasShard;
    in.id = fs::path(arg).lexically_normal().filename().string();
    if (in.id.empty()) in.id = fs::path(arg).lexically_normal().parent_path().filename().string();
    if (hasShard) {
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
        addPlan(parentPlan.string());
    }
    inputs.push_back(std::move(in));
  }

  // Expected shards, in plan order.
  std::vector<Shard> expected;
  std::map<std::string, Shard> expectedById;
  for (const auto& file : planFiles) {
    Sweep sweep = loadSweep(file, registry);
    for (Shard& s : planSweep(sweep, registry)) {
      if (expectedById.count(s.id)) continue;
      s.index = int(expected.size());
      expectedById[s.id] = s;
      expected.push_back(s);
    }
  }

  std::set<std::string> seen;
  for (Input& in : inputs) {
    if (!seen.insert(in.id).second) throw UsageError("merge: shard " + in.id + " is given twice (" + in.dir + ")");
    auto it = expectedById.find(in.id);
    if (it != expectedById.end()) {
      in.planIndex = it->second.index;
      if (in.shard && in.status == "finished") {
        ShardState st = readShardState(in.dir);
        if (st.definition != it->second.definition) {
          in.status = "stale";
          in.reason = "run with other settings than the sweep now defines (rerun it)";
        }
      }
    }
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
  std::stable_sort(inputs.begin(), inputs.end(), [](const Input& a, const Input& b) {
    int ka = a.planIndex < 0 ? 1 << 30 : a.planIndex, kb = b.planIndex < 0 ? 1 << 30 : b.planIndex;
    return ka != kb ? ka < kb : a.argIndex < b.argIndex;
  });

  // Columns: this build's, any a folder adds, then where each row comes from.
  std::vector<std::string> runCols = runsColumns(), passCols = passesColumns(), frameCols = framesColumns();
  bool anyFrames = false;
  for (const Input& in : inputs) {
    if (in.status != "finished") continue;
    addColumns(runCols, in.runs.header);
    addColumns(passCols, in.passes.header);
    addColumns(frameCols, in.frames.header);
    anyFrames = anyFrames || !in.frames.header.empty();
  }
  addColumns(runCols, {"seed", "host", "shard"});
  addColumns(passCols, {"width", "height", "seed", "host", "shard"});
  addColumns(frameCols, {"width", "height", "seed", "host", "shard"});

  // Rows, checked: no row twice; one renderer per scene, size and seed unless allowed.
  std::vector<std::vector<std::string>> runRows, passRows, frameRows;
  std::map<std::string, std::string> rowOwner;
  std::map<std::string, std::map<std::string, std::string>> renderersByGroup;  // group -> renderer -> shard
  std::set<std::string> renderers, hosts;
  json shardsMeta = json::array(), failedMeta = json::array();
  int failedShards = 0;
  for (const Input& in : inputs) {
    std::string seed = metaString(in.meta, "seed");
    std::string width = metaString(in.meta, "width"), height = metaString(in.meta, "height");
    json entry = {{"id", in.id}, {"folder", in.dir}, {"status", in.status}, {"host", in.host}};
    if (in.status != "finished") {
      ++failedShards;
      failedMeta.push_back({{"id", in.id}, {"reason", in.reason}});
      shardsMeta.push_back(entry);
      continue;
    }
    if (!in.host.empty()) hosts.insert(in.host);
    int failureRows = 0;
    for (size_t r = 0; r < in.runs.rows.size(); ++r) {
      std::vector<std::string> row;
      for (const auto& c : runCols) {
        if (c == "seed") row.push_back(seed);
        else if (c == "host") row.push_back(in.host);
        else if (c == "shard") row.push_back(in.id);
        else row.push_back(in.runs.get(r, c));
      }
      std::string key = in.runs.get(r, "scene") + "|" + in.runs.get(r, "method") + "|" + in.runs.get(r, "params") +
                        "|" + in.runs.get(r, "width") + "x" + in.runs.get(r, "height") + "|" + seed;
      auto [owner, fresh] = rowOwner.emplace(key, in.id);
      if (!fresh)
        throw UsageError("merge: the row " + in.runs.get(r, "scene") + " " + in.runs.get(r, "method") + " " +
                         in.runs.get(r, "params") + " at " + in.runs.get(r, "width") + "x" + in.runs.get(r, "height") +
                         " seed " + seed + " is in both " + owner->second + " and " + in.id);
      std::string renderer = in.runs.get(r, "renderer");
      if (!renderer.empty()) {
        renderers.insert(renderer);
        std::string group = in.runs.get(r, "scene") + " at " + in.runs.get(r, "width") + "x" +
                            in.runs.get(r, "height") + " seed " + seed;
        renderersByGroup[group].emplace(renderer, in.id);
      }
      if (in.runs.get(r, "status") == "Failure") ++failureRows;
      runRows.push_back(std::move(row));
    }
    appendTaggedRows(in.passes, passCols, in, width, height, seed, passRows);
    appendTaggedRows(in.frames, frameCols, in, width, height, seed, frameRows);
    entry["rows"] = in.runs.rows.size();
    entry["failure_rows"] = failureRows;
    entry["renderer"] = in.meta.contains("gl") ? in.meta["gl"].value("renderer", "") : "";
    entry["timer"] = in.meta.contains("timer") ? in.meta["timer"].value("strategy", "") : "";
    entry["git_sha"] = metaString(in.meta, "git_sha");
    entry["date"] = metaString(in.meta, "date");
    entry["meta"] = in.meta;  // the shard's own meta.json: command line, GL, CPU, timer calibration, reference
    shardsMeta.push_back(entry);
    if (failureRows > 0)
      std::fprintf(stderr, "vshadow merge: shard %s: %d row(s) are failures (see their reason column)\n", in.id.c_str(),
                   failureRows);
  }
  bool mixed = false;
  for (const auto& [group, byRenderer] : renderersByGroup) {
    if (byRenderer.size() < 2) continue;
    mixed = true;
    if (req.allowMixedRenderers) continue;
    auto a = byRenderer.begin(), b = std::next(a);
    throw UsageError("merge: rows of " + group + " come from different renderers ('" + a->first + "' in " + a->second +
                     ", '" + b->first + "' in " + b->second +
                     "): their times do not compare (--allow-mixed-renderers merges them anyway)");
  }

  std::vector<std::string> missing;
  for (const Shard& s : expected)
    if (!seen.count(s.id)) missing.push_back(s.id);

  // Everything checked: write.
  fs::create_directories(req.out, ec);
  if (ec || !fs::is_directory(req.out)) throw std::runtime_error("cannot create output folder " + req.out + ": " + ec.message());
  std::string runsText = CsvTable::format(runCols);
  for (const auto& row : runRows) runsText += CsvTable::format(row);
  std::string passesText = CsvTable::format(passCols);
  for (const auto& row : passRows) passesText += CsvTable::format(row);
  bool complete = missing.empty() && failedShards == 0;
  json meta = {{"command_line", req.commandLine},
               {"date", isoDateUtc()},
               {"status", complete ? "complete" : "incomplete"},
               {"sweeps", planFiles},
               {"shards", shardsMeta},
               {"missing", missing},
               {"failed", failedMeta},
               {"renderers", std::vector<std::string>(renderers.begin(), renderers.end())},
               {"hosts", std::vector<std::string>(hosts.begin(), hosts.end())},
               {"mixed_renderers", mixed}};
  writeFileAtomic(req.out + "/runs.csv", runsText);
  writeFileAtomic(req.out + "/passes.csv", passesText);
  if (anyFrames) {
    std::string framesText = CsvTable::format(frameCols);
    for (const auto& row : frameRows) framesText += CsvTable::format(row);
    writeFileAtomic(req.out + "/frames.csv", framesText);
  }
  writeFileAtomic(req.out + "/meta.json", meta.dump(2) + "\n");

  for (const auto& id : missing) std::fprintf(stderr, "vshadow merge: missing shard %s\n", id.c_str());
  for (const auto& f : failedMeta)
    std::fprintf(stderr, "vshadow merge: failed shard %s: %s\n", f["id"].get<std::string>().c_str(),
                 f["reason"].get<std::string>().c_str());
  std::printf("merged %d of %d shard(s), %zu rows, into %s%s\n", int(inputs.size()) - failedShards,
              int(std::max(expected.size(), inputs.size())), runRows.size(), req.out.c_str(),
              complete ? "" : " (incomplete)");
  return complete ? 0 : 3;
}

}  // namespace

int mergeCommand(const MergeRequest& request, const MethodRegistry& registry) {
  return reportingErrors([&] { return mergeChecked(request, registry); });
}

}  // namespace vs
