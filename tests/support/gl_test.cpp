#include "gl_test.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace vs::testing {

namespace {
struct Shared {
  std::unique_ptr<GlContext> context;
  gl::Limits limits;
};
Shared& shared() {
  static Shared s;
  if (!s.context) {
    s.context = std::make_unique<GlContext>(true);
    gl::installDebugOutput(false);
    s.limits = gl::queryLimits();
  }
  return s;
}
}  // namespace

void GlTest::SetUp() {
  shared();
  gl::resetDebugErrorCount();
}

void GlTest::TearDown() {
  gl::checkErrors("test teardown");
  EXPECT_EQ(gl::debugErrorCount(), 0) << "GL debug error: " << gl::lastDebugError();
}

const gl::Limits& GlTest::limits() const { return shared().limits; }
const ContextInfo& contextInfo() { return shared().context->info(); }
bool isLlvmpipe() { return contextInfo().glRenderer.find("llvmpipe") != std::string::npos; }

const gl::Limits& glLimits() { return shared().limits; }

MethodRun renderScene(const Scene& scene, const std::string& spec, const RunOptions& options) {
  const gl::Limits& limits = shared().limits;
  ResolvedSpec resolved = resolveSpec(spec, limits);
  Runner runner(scene, limits, options);
  auto method = createMethod(resolved.method);
  return runner.run(*method, resolved.params);
}

MethodRun renderScene(const Scene& scene, const std::string& spec, int width, int height, int frames, int warmup,
                      uint32_t seed) {
  RunOptions options;
  options.width = width;
  options.height = height;
  options.frames = frames;
  options.warmup = warmup;
  options.seed = seed;
  options.timer = TimerStrategy::WallClock;
  return renderScene(scene, spec, options);
}

Scene sceneFromJson(const std::string& json) { return parseSceneJson(json, ".", "test scene"); }

std::string vshadowPath() { return VSHADOW_BIN; }

void execVshadow(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  std::string bin = vshadowPath();
  argv.push_back(bin.data());
  std::vector<std::string> copy = args;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  ::execv(bin.c_str(), argv.data());
  ::_exit(127);
}

CommandResult runVshadow(const std::vector<std::string>& args, const std::vector<std::string>& env) {
  std::string outPath = makeTempDir("cmd") + "/out", errPath = outPath + ".err";
  pid_t pid = ::fork();
  if (pid == 0) {
    int in = ::open("/dev/null", O_RDONLY);
    int out = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    for (const auto& e : env) ::putenv(const_cast<char*>(e.c_str()));
    execVshadow(args);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  CommandResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = readFile(outPath);
  r.err = readFile(errPath);
  return r;
}

std::string makeTempDir(const std::string& tag) {
  std::string pattern = (std::filesystem::temp_directory_path() / ("vshadow-test-" + tag + "-XXXXXX")).string();
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  if (!::mkdtemp(buf.data())) throw std::runtime_error("mkdtemp failed");
  return buf.data();
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

}  // namespace vs::testing
