// meta.json, the provenance of a run: the command, build, GL and CPU, timer, scene and metrics.
// The run's stages add their own sections (reference, exact, equal_quality, drift) as they finish.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "harness/gl/context.hpp"
#include "harness/gl/thread_pinning.hpp"
#include "harness/gl/timer.hpp"
#include "harness/shootout/plan.hpp"

namespace vs::shootout {

// How this binary was built: type, compiler, flags, sanitizers, assertions. A sanitizer or debug
// build's timings must never pass for a release build's.
nlohmann::json buildInfo();
// /proc/cpuinfo's first "model name" ("unknown" without one).
std::string cpuModel();

// meta.json as a run starts it: "status" is "running".
nlohmann::json metaJson(const RunRequest& req, const RunPlan& plan, const ContextInfo& info,
                        const TimerCalibration& calibration, const ThreadPinning& pinning, const std::string& date);

}  // namespace vs::shootout
