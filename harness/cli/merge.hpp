// vshadow merge: result folders (a sweep's shards, or any run folders) into one runs.csv,
// passes.csv and meta.json, each row keeping the host and renderer that produced it.
#pragma once
#include <string>
#include <vector>

#include "harness/pipeline/method.hpp"

namespace vs {

struct MergeRequest {
  std::vector<std::string> inputs;  // shard or result folders; a sweep.json names the shards expected
  std::string out;
  bool allowMixedRenderers = false;  // rows compared across renderers (their times are not comparable)
  std::string commandLine;
};

// Exit status: 0 every expected shard merged; 3 merged, but shards are missing or failed (each
// reported by id on stderr); 2 bad input (nothing written); 1 a run-time failure.
int mergeCommand(const MergeRequest& request, const MethodRegistry& registry);

}  // namespace vs
