// The vshadow commands: list, run, shootout (the stages of run and shootout are in harness/shootout/).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "harness/gl/context.hpp"
#include "harness/pipeline/method.hpp"
#include "harness/shootout/request.hpp"

namespace vs {

// One line of provenance for a benchmark's output: renderer, CPU, revision, date and build, e.g.
// "llvmpipe (LLVM 15.0.6, 256 bits) (4.5 (Core Profile) Mesa 22.3.6); CPU AMD EPYC; revision
// 0123abcd4567; 2026-12-02T01:00:00Z; Release build, GNU 12.2.0, sanitizers none".
std::string provenanceLine(const ContextInfo& info);
int listCommand(const MethodRegistry& registry);
int runCommand(const RunRequest& request, bool shootout, const MethodRegistry& registry);
// Runs a command and maps its errors to the exit status: bad input (UsageError, SceneError) 2
// with one line on stderr, any other failure 1.
int reportingErrors(const std::function<int()>& command);

}  // namespace vs
