#include "harness/cli/sweep.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <regex>
#include <set>

#include "harness/cli/app.hpp"
#include "harness/gl/context.hpp"
#include "harness/gl/gl.hpp"
#include "harness/io/results.hpp"
#include "harness/pipeline/runner.hpp"
#include "scenes/content_hash.hpp"
#include "scenes/json_reader.hpp"

namespace vs {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

const char* const kShardFile = "shard.json";
const char* const kSweepFile = "sweep.json";

bool isBuiltinScene(const std::string& name) {
  for (const auto& s : builtinScenes())
    if (s.name == name) return true;
  return false;
}

std::string idPart(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (std::isalnum(uint8_t(c)) || c == '.') out += c;
    else if (c == '=') out += '-';
    else out += '_';
  }
  return out;
}

std::string sceneLabel(const std::string& scene) {
  return isBuiltinScene(scene) ? scene : fs::path(scene).stem().string();
}

std::string hostName() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

// The shadow-map sizes a method entry runs at (each rung of a ladder, or the one spec).
std::vector<std::string> entrySpecs(const std::string& entry, bool ladder, const MethodRegistry& registry) {
  if (!ladder) return {entry};
  std::vector<std::string> specs;
  for (const auto& rung : createMethod(registry, entry)->qualityLadder())
    specs.push_back(entry + (rung.empty() ? "" : ":" + rung));
  return specs;
}

// Validates a spec without a GL context (the GL limits are checked when the shard runs) and
// returns its shadow-map size.
int specShadowMap(const std::string& spec, const MethodRegistry& registry) {
  MethodSpec parsed = parseMethodSpec(spec);
  auto method = createMethod(registry, parsed.method);
  ParamValues values = ParamValues::parse(parsed.method, allParams(*method, 1 << 20), parsed.params);
  return values.getInt("sm");
}

void writeShardState(const std::string& dir, const json& state) {
  writeFileAtomic(dir + "/" + kShardFile, state.dump(2) + "\n");
}

// Selects shards by id or index; UsageError for one that the plan does not have.
std::vector<Shard> selectShards(const std::vector<Shard>& shards, const std::vector<std::string>& only) {
  if (only.empty()) return shards;
  std::vector<Shard> out;
  for (const std::string& key : only) {
    bool found = false;
    static const std::regex digits("^[0-9]{1,9}$");
    for (const Shard& s : shards) {
      if (s.id == key || (std::regex_match(key, digits) && s.index == std::stoi(key))) {
        out.push_back(s);
        found = true;
        break;
      }
    }
    if (!found)
      throw UsageError("--shard '" + key + "': the sweep has no such shard (ids and indices 0.." +
                       std::to_string(int(shards.size()) - 1) + ": see vshadow sweep plan)");
  }
  return out;
}

bool shardFinished(const std::string& dir, const Shard& shard) {
  ShardState st = readShardState(dir);
  return st.exists && st.status == "finished" && st.definition == shard.definition;
}

// Removes what an unfinished run of a shard left, so the shard is redone from nothing. Only
// folders that carry a shard marker are touched.
void clearShardFolder(const std::string& dir) {
  for (const char* name : {"runs.csv", "passes.csv", "meta.json", "images"}) fs::remove_all(fs::path(dir) / name);
}

std::string sweepFolderProblem(const std::string& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) return "cannot create output folder " + out + ": " + ec.message();
  return "";
}

}  // namespace

namespace {

// A non-empty array of distinct, non-empty strings at `key` (empty when optional and absent).
std::vector<std::string> readStringList(ObjectReader& r, const std::string& key, bool required) {
  std::vector<std::string> items;
  const Json* value = required ? &r.required(key) : r.optional(key);
  if (!value) return items;
  JsonLocation at = r.locationOf(key);
  if (!value->is_array()) at.fail("expected an array of strings");
  if (value->empty()) at.fail("must not be empty");
  std::set<std::string> seen;
  for (size_t i = 0; i < value->size(); ++i) {
    std::string s = readString((*value)[i], at.item(i));
    if (s.empty()) at.item(i).fail("must not be empty");
    if (!seen.insert(s).second) at.item(i).fail("'" + s + "' is listed twice");
    items.push_back(s);
  }
  return items;
}

// "scenes": built-in names, or files relative to the sweep file's folder; each one loads, and no
// two share a shard id part.
std::vector<std::string> readSweepScenes(ObjectReader& r, const fs::path& base) {
  std::vector<std::string> scenes;
  std::vector<std::string> entries = readStringList(r, "scenes", true);
  for (size_t i = 0; i < entries.size(); ++i) {
    std::string scene = entries[i];
    if (!isBuiltinScene(scene)) {
      bool looksLikeName = scene.find('/') == std::string::npos && fs::path(scene).extension() != ".json";
      if (looksLikeName && !fs::exists(base / scene)) {
        try {
          loadScene(scene);  // names the built-in scenes in its message
        } catch (const SceneError& e) {
          r.locationOf("scenes").item(i).fail(e.what());
        }
      }
      fs::path p(scene);
      if (p.is_relative()) p = base / p;
      scene = p.lexically_normal().string();
      try {
        loadScene(scene);
      } catch (const SceneError& e) {
        r.locationOf("scenes").item(i).fail(e.what());
      }
    }
    scenes.push_back(scene);
  }
  std::map<std::string, std::string> labels;
  for (const auto& scene : scenes) {
    auto [it, fresh] = labels.emplace(sceneLabel(scene), scene);
    if (!fresh)
      r.fail("scenes", "'" + it->second + "' and '" + scene + "' would share the shard id part '" + it->first +
                           "' (rename one file)");
  }
  return scenes;
}

// "methods": names (their ladders) or full specs, each of which resolves.
std::vector<std::string> readSweepMethods(ObjectReader& r, const MethodRegistry& registry) {
  std::vector<std::string> methods = readStringList(r, "methods", true);
  for (size_t i = 0; i < methods.size(); ++i) {
    const std::string& entry = methods[i];
    try {
      if (entry.find(':') == std::string::npos) {
        for (const auto& spec : entrySpecs(entry, true, registry)) specShadowMap(spec, registry);
      } else {
        specShadowMap(entry, registry);
      }
    } catch (const UsageError& e) {
      r.locationOf("methods").item(i).fail(e.what());
    }
  }
  return methods;
}

std::vector<std::string> readSweepSizes(ObjectReader& r) {
  std::vector<std::string> sizes = readStringList(r, "sizes", false);
  if (sizes.empty()) sizes = {"512x512"};
  static const std::regex sizeRe(R"(^([1-9][0-9]{0,5})x([1-9][0-9]{0,5})$)");
  for (size_t i = 0; i < sizes.size(); ++i)
    if (!std::regex_match(sizes[i], sizeRe)) r.locationOf("sizes").item(i).fail("'" + sizes[i] + "': expected WxH, e.g. 512x512");
  return sizes;
}

std::vector<long long> readSweepSeeds(ObjectReader& r) {
  const Json* seeds = r.optional("seeds");
  if (!seeds) return {1};
  std::vector<long long> out;
  JsonLocation at = r.locationOf("seeds");
  if (!seeds->is_array() || seeds->empty()) at.fail("expected a non-empty array of integers");
  for (size_t i = 0; i < seeds->size(); ++i) {
    long long s = readInteger((*seeds)[i], at.item(i), 0, 4294967295LL);
    if (std::find(out.begin(), out.end(), s) != out.end()) at.item(i).fail(std::to_string(s) + " is listed twice");
    out.push_back(s);
  }
  return out;
}

}  // namespace

Sweep loadSweep(const std::string& path, const MethodRegistry& registry) {
  std::string text, error;
  if (!readFile(path, text, error)) throwSceneError(path, "", "cannot open sweep file: " + error);
  Json document = parseJsonStrict(text, path);
  ObjectReader r(document, JsonLocation{path, ""});
  r.declare({"description", "scenes", "methods", "sizes", "seeds", "frames", "warmup", "reference", "split", "timer",
             "images", "exact", "exact_steps", "equal_quality"});
  Sweep sweep;
  sweep.source = path;
  sweep.description = r.string("description", "");
  sweep.scenes = readSweepScenes(r, fs::absolute(path).parent_path());
  sweep.methods = readSweepMethods(r, registry);
  sweep.sizes = readSweepSizes(r);
  sweep.seeds = readSweepSeeds(r);
  sweep.frames = int(r.integer("frames", sweep.frames, 1, 100000));
  sweep.warmup = int(r.integer("warmup", sweep.warmup, 0, 100000));
  sweep.reference = r.string("reference", "default");
  if (sweep.reference.empty()) r.fail("reference", "expected default, none, exact or a method spec");
  if (sweep.reference != "default" && sweep.reference != "none" && sweep.reference != "exact") {
    try {
      specShadowMap(sweep.reference, registry);
    } catch (const UsageError& e) {
      r.fail("reference", e.what());
    }
  }
  sweep.split = r.choice("split", {"ladder", "rung"}, "ladder");
  sweep.timer = r.choice("timer", {"auto", "gpu", "wall"}, "auto");
  sweep.images = r.boolean("images", false);
  sweep.exact = r.boolean("exact", false);
  sweep.exactSteps = int(r.integer("exact_steps", 2048, 1, 1 << 20));
  sweep.equalQuality = r.boolean("equal_quality", false);
  r.finish();
  return sweep;
}

json sweepJson(const Sweep& s) {
  return {{"description", s.description}, {"scenes", s.scenes},   {"methods", s.methods},
          {"sizes", s.sizes},             {"seeds", s.seeds},     {"frames", s.frames},
          {"warmup", s.warmup},           {"reference", s.reference}, {"split", s.split},
          {"timer", s.timer},             {"images", s.images},   {"exact", s.exact},
          {"exact_steps", s.exactSteps},  {"equal_quality", s.equalQuality}};
}

std::vector<Shard> planSweep(const Sweep& sweep, const MethodRegistry& registry) {
  // The method entries as shards see them: ladders stay whole or split into rungs.
  struct Entry {
    std::string method, label;
    bool ladder;
  };
  std::vector<Entry> entries;
  int maxSm = 64;
  for (const auto& m : sweep.methods) {
    bool ladder = m.find(':') == std::string::npos;
    for (const auto& spec : entrySpecs(m, ladder, registry)) maxSm = std::max(maxSm, specShadowMap(spec, registry));
    if (ladder && sweep.split == "rung") {
      for (const auto& spec : entrySpecs(m, true, registry)) entries.push_back({spec, idPart(spec), false});
    } else {
      entries.push_back({m, idPart(m), ladder});
    }
  }
  std::vector<Shard> shards;
  std::set<std::string> ids;
  for (const auto& scene : sweep.scenes) {
    Scene loaded = loadScene(scene);
    // One reference per scene, size and seed for every shard: the reference method at the largest
    // shadow map of the whole sweep, as a single run of everything would use.
    std::string referenceSpec;
    if (sweep.reference == "default") {
      referenceSpec = referenceSpecFor(deriveEffects(loaded), maxSm, registry);
    } else if (sweep.reference != "none") {
      referenceSpec = sweep.reference;
    }
    for (const auto& size : sweep.sizes) {
      for (long long seed : sweep.seeds) {
        for (const auto& e : entries) {
          Shard s;
          s.index = int(shards.size());
          s.scene = scene;
          s.size = size;
          s.seed = seed;
          s.method = e.method;
          s.ladder = e.ladder;
          s.referenceSpec = referenceSpec;
          s.noReference = sweep.reference == "none";
          s.id = idPart(sceneLabel(scene)) + "-" + size + "-s" + std::to_string(seed) + "-" + e.label;
          if (!ids.insert(s.id).second) throw UsageError(sweep.source + ": two shards would share the id " + s.id);
          json def = {{"scene", scene},          {"scene_hash", loaded.contentHash},
                      {"size", size},            {"seed", seed},
                      {"method", e.method},      {"ladder", e.ladder},
                      {"reference", referenceSpec}, {"no_reference", s.noReference},
                      {"frames", sweep.frames},  {"warmup", sweep.warmup},
                      {"timer", sweep.timer},    {"images", sweep.images},
                      {"exact", sweep.exact},    {"exact_steps", sweep.exactSteps},
                      {"equal_quality", sweep.equalQuality}};
          ContentHasher hasher;
          hasher.addBlock(def.dump());
          s.definition = hasher.hex();
          shards.push_back(s);
        }
      }
    }
  }
  return shards;
}

RunRequest shardRequest(const Sweep& sweep, const Shard& shard, const std::string& dir, const std::string& cacheDir) {
  RunRequest r;
  r.scene = shard.scene;
  r.methods = {shard.method};
  r.size = shard.size;
  r.out = dir;
  r.cacheDir = cacheDir;
  r.referenceSpec = shard.referenceSpec;
  r.noReference = shard.noReference;
  r.timer = sweep.timer;
  r.frames = sweep.frames;
  r.warmup = sweep.warmup;
  r.seed = shard.seed;
  r.exact = sweep.exact;
  r.exactSteps = sweep.exactSteps;
  r.noImages = !sweep.images;
  r.equalQuality = sweep.equalQuality;
  // The command that reruns this shard alone (recorded in its meta.json).
  r.commandLine = std::string("vshadow ") + (shard.ladder ? "shootout" : "run") + " --scene " + shard.scene +
                  " --method " + shard.method + " --size " + shard.size + " --seed " + std::to_string(shard.seed) +
                  " --frames " + std::to_string(sweep.frames) + " --warmup " + std::to_string(sweep.warmup) +
                  " --timer " + sweep.timer + (shard.noReference ? " --no-reference" : "") +
                  (shard.referenceSpec.empty() ? "" : " --reference " + shard.referenceSpec) +
                  (sweep.exact ? " --exact --exact-steps " + std::to_string(sweep.exactSteps) : "") +
                  (sweep.images ? "" : " --no-images") + (sweep.equalQuality ? " --equal-quality" : "") + " --out " +
                  dir;
  return r;
}

ShardState readShardState(const std::string& dir) {
  ShardState st;
  std::string text, error;
  if (!readFile(dir + "/" + kShardFile, text, error)) return st;
  try {
    json j = json::parse(text);
    st.exists = true;
    st.status = j.value("status", "");
    st.definition = j.value("definition", "");
    st.host = j.value("host", "");
    st.reason = j.value("reason", "");
    st.exitCode = j.value("exit_code", -1);
  } catch (const std::exception&) {
    st.exists = true;
    st.status = "unreadable";
  }
  return st;
}

int sweepPlanCommand(const std::string& file, const SweepOptions& options, const MethodRegistry& registry) {
  return reportingErrors([&]() -> int {
    Sweep sweep = loadSweep(file, registry);
    std::vector<Shard> shards = planSweep(sweep, registry);
    if (!options.out.empty()) {
      std::string problem = sweepFolderProblem(options.out);
      if (!problem.empty()) throw std::runtime_error(problem);
      writeFileAtomic(options.out + "/" + kSweepFile, sweepJson(sweep).dump(2) + "\n");
    }
    for (const Shard& s : shards) {
      if (options.pendingOnly && !options.out.empty() && shardFinished(options.out + "/" + s.id, s)) continue;
      std::printf("%d\t%s\t%s\t%s\t%lld\t%s\n", s.index, s.id.c_str(), s.scene.c_str(), s.size.c_str(), s.seed,
                  (s.ladder ? "ladder:" + s.method : s.method).c_str());
    }
    return 0;
  });
}

int sweepRunCommand(const std::string& file, const SweepOptions& options, const MethodRegistry& registry) {
  Sweep sweep;
  std::vector<Shard> selected;
  // Validate and write the normalized sweep first: bad input fails before any shard runs.
  int prepared = reportingErrors([&]() -> int {
    sweep = loadSweep(file, registry);
    selected = selectShards(planSweep(sweep, registry), options.only);
    for (const Shard& s : selected) {
      std::string dir = options.out + "/" + s.id;
      if (fs::exists(dir) && !fs::is_directory(dir)) throw UsageError(dir + " exists and is not a folder");
      if (fs::is_directory(dir) && !fs::is_empty(dir) && !readShardState(dir).exists)
        throw UsageError(dir + " holds files but no shard marker (" + kShardFile + "): not overwriting it");
    }
    std::string problem = sweepFolderProblem(options.out);
    if (!problem.empty()) {
      std::fprintf(stderr, "vshadow: error: %s\n", problem.c_str());
      return 1;
    }
    // The normalized sweep beside the shards: what `vshadow merge` checks completeness against.
    std::string normalized = sweepJson(sweep).dump(2) + "\n";
    std::string existing, error;
    std::string sweepPath = options.out + "/" + kSweepFile;
    if (!readFile(sweepPath, existing, error) || existing != normalized) writeFileAtomic(sweepPath, normalized);
    return 0;
  });
  if (prepared != 0) return prepared;

  int worst = 0;
  for (const Shard& s : selected) {
    std::string dir = options.out + "/" + s.id;
    if (shardFinished(dir, s)) {
      std::printf("shard %d %s: finished already, skipped\n", s.index, s.id.c_str());
      std::fflush(stdout);
      continue;
    }
    std::printf("shard %d %s: running\n", s.index, s.id.c_str());
    std::fflush(stdout);
    fs::create_directories(dir);
    clearShardFolder(dir);
    json state = {{"id", s.id},       {"index", s.index},     {"definition", s.definition},
                  {"scene", s.scene}, {"size", s.size},       {"seed", s.seed},
                  {"method", s.method}, {"ladder", s.ladder}, {"host", hostName()},
                  {"started", isoDateUtc()}, {"status", "running"}};
    if (const char* job = std::getenv("SLURM_JOB_ID")) state["slurm_job_id"] = job;
    if (const char* task = std::getenv("SLURM_ARRAY_TASK_ID")) state["slurm_array_task_id"] = task;
    writeShardState(dir, state);
    int rc = runCommand(shardRequest(sweep, s, dir, options.cacheDir), s.ladder, registry);
    std::string metaText, error;
    bool metaFinished = false;
    if (readFile(dir + "/meta.json", metaText, error)) {
      try {
        metaFinished = json::parse(metaText).value("status", "") == "finished";
      } catch (const std::exception&) {
      }
    }
    state["exit_code"] = rc;
    state["ended"] = isoDateUtc();
    if ((rc == 0 || rc == 3) && metaFinished) {
      state["status"] = "finished";
      if (rc == 3) state["reason"] = "some rows are failures (see runs.csv)";
    } else {
      state["status"] = "failed";
      state["reason"] = "vshadow exited with status " + std::to_string(rc);
    }
    writeShardState(dir, state);
    std::printf("shard %d %s: %s\n", s.index, s.id.c_str(), state["status"].get<std::string>().c_str());
    std::fflush(stdout);
    int code = state["status"] == "finished" ? rc : (rc == 0 ? 1 : rc);
    if (code == 2 || code == 1) worst = (worst == 2 || code == 2) ? 2 : 1;
    else if (code == 3 && worst == 0) worst = 3;
  }
  return worst;
}

int sweepReferenceCommand(const std::string& file, const SweepOptions& options, const MethodRegistry& registry) {
  return reportingErrors([&]() -> int {
    Sweep sweep = loadSweep(file, registry);
    std::vector<Shard> shards = planSweep(sweep, registry);
    std::string scene;
    for (const auto& s : sweep.scenes)
      if (s == options.scene || sceneLabel(s) == options.scene) scene = s;
    if (scene.empty()) throw UsageError("--scene '" + options.scene + "': not a scene of " + file);
    // Each size and seed once, with the spec every shard of the scene uses.
    std::map<std::pair<std::string, long long>, std::string> wanted;
    for (const Shard& s : shards)
      if (s.scene == scene && !s.noReference && s.referenceSpec != "exact") wanted[{s.size, s.seed}] = s.referenceSpec;
    if (wanted.empty()) {
      std::printf("%s: the sweep uses no cached reference (reference: %s)\n", options.scene.c_str(),
                  sweep.reference.c_str());
      return 0;
    }
    Scene loaded = loadScene(scene);
    GlContext context(true);
    gl::installDebugOutput(false);
    gl::Limits limits = gl::queryLimits();
    std::string cacheDir = options.cacheDir.empty() ? defaultCacheDir() : options.cacheDir;
    for (const auto& [key, spec] : wanted) {
      RunOptions ro;
      static const std::regex sizeRe(R"(^(\d+)x(\d+)$)");
      std::smatch m;
      std::regex_match(key.first, m, sizeRe);
      ro.width = std::stoi(m[1]);
      ro.height = std::stoi(m[2]);
      int maxSize = std::min({limits.maxTextureSize, limits.maxViewportW, limits.maxViewportH});
      if (ro.width > maxSize || ro.height > maxSize)
        throw UsageError("size " + key.first + " exceeds this GL implementation's limit of " + std::to_string(maxSize) +
                         " pixels per side");
      ro.seed = uint32_t(key.second);
      ro.frames = 1;
      ro.warmup = 0;
      Reference ref = obtainReference(loaded, limits, ro, 64, cacheDir, registry, spec);
      std::printf("reference %s %s seed %lld: %s\n", sceneLabel(scene).c_str(), key.first.c_str(), key.second,
                  ref.fromCache ? "from cache" : ("computed in " + num(ref.computeMs / 1000.0) + " s").c_str());
      std::fflush(stdout);
    }
    return 0;
  });
}

}  // namespace vs
