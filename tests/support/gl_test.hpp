// Test support: one headless GL context per test binary, GL debug errors fail the test, and
// helpers to render scenes and to run the vshadow binary.
#pragma once
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "harness/gl/context.hpp"
#include "harness/pipeline/runner.hpp"
#include "registry.hpp"

namespace vs::testing {

// Fixture for tests that touch GL: the context exists, and any KHR_debug error fails the test.
class GlTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  const gl::Limits& limits() const;
};

const ContextInfo& contextInfo();
bool isLlvmpipe();

// Renders `scene` with a method spec ("raymarch:steps=64") through the real runner.
MethodRun renderScene(const Scene& scene, const std::string& spec, int width, int height, int frames = 1,
                      int warmup = 0, uint32_t seed = 1);
MethodRun renderScene(const Scene& scene, const std::string& spec, const RunOptions& options);
const gl::Limits& glLimits();
Scene sceneFromJson(const std::string& json);

struct CommandResult {
  int exitCode = -1;
  std::string out, err;
};
// Runs the built vshadow with arguments (no shell); stdin is closed.
CommandResult runVshadow(const std::vector<std::string>& args, const std::vector<std::string>& env = {});
std::string vshadowPath();
// In a forked child: becomes `vshadow ARGS` (exit 127 when it cannot).
[[noreturn]] void execVshadow(const std::vector<std::string>& args);
std::string makeTempDir(const std::string& tag);
std::string readFile(const std::string& path);
void writeFile(const std::string& path, const std::string& text);

}  // namespace vs::testing
