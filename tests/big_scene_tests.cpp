// A real-size scene end to end: `vshadow run` on an OBJ of two million triangles (200,000 in the
// sanitized build) records the load's time and memory in meta.json, and shows its progress as a bar
// on a terminal only.
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gl_test.hpp"

namespace fs = std::filesystem;
using namespace vs::testing;

namespace {

#ifdef VS_SANITIZE
constexpr int kSide = 316;   // 2 x 316^2 = 199,712 triangles
#else
constexpr int kSide = 1000;  // 2,000,000 triangles
#endif
constexpr size_t kTriangles = 2 * size_t(kSide) * size_t(kSide);
constexpr size_t kVertices = size_t(kSide + 1) * size_t(kSide + 1);

// A flat grid of kSide x kSide quads as an OBJ (integer coordinates, placed by the scene's "scale"),
// and a scene file naming it, written once for the tests of this file.
class BigScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(makeTempDir("big-scene"));
    std::string obj;
    obj.reserve(kVertices * 16 + kTriangles * 26);
    char line[96];
    for (int j = 0; j <= kSide; ++j)
      for (int i = 0; i <= kSide; ++i) obj.append(line, size_t(std::snprintf(line, sizeof line, "v %d 0 %d\n", i, j)));
    for (int j = 0; j < kSide; ++j)
      for (int i = 0; i < kSide; ++i) {
        long a = long(j) * (kSide + 1) + i + 1, c = a + kSide + 1;
        obj.append(line, size_t(std::snprintf(line, sizeof line, "f %ld %ld %ld\nf %ld %ld %ld\n", a, c, a + 1, a + 1, c, c + 1)));
      }
    writeFile(*dir_ + "/grid.obj", obj);
    writeFile(*dir_ + "/big.json", R"({"geometry": [{"obj": "grid.obj", "scale": )" + std::to_string(10.0 / kSide) +
                                       R"(, "translate": [-5, 0, -5]}],
      "camera": {"position": [0, 6, 9], "target": [0, 0, 0]},
      "light": {"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 3},
      "medium": {"sigma_s": 0.05, "sigma_a": 0.01}})");
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(*dir_, ignored);
    delete dir_;
  }
  static std::vector<std::string> runArgs(const std::string& out) {
    return {"run", "--scene", *dir_ + "/big.json", "--method", "raymarch:steps=4:sm=64", "--size", "32x24",
            "--frames", "1", "--warmup", "0", "--no-reference", "--no-images", "--out", out};
  }
  static std::string* dir_;
};
std::string* BigScene::dir_ = nullptr;

// Runs vshadow with its stdout and stderr on a pseudo-terminal; returns its exit status and
// everything it wrote there.
CommandResult runOnTerminal(const std::vector<std::string>& args) {
  int terminal = -1;
  pid_t pid = ::forkpty(&terminal, nullptr, nullptr, nullptr);
  if (pid < 0) throw std::runtime_error("forkpty failed");
  if (pid == 0) execVshadow(args);
  CommandResult r;
  char buffer[4096];
  for (;;) {
    ssize_t n = ::read(terminal, buffer, sizeof buffer);
    if (n > 0) r.err.append(buffer, size_t(n));
    else if (n < 0 && errno == EINTR) continue;
    else break;  // EIO once the child has closed the terminal
  }
  ::close(terminal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

}  // namespace

TEST_F(BigScene, RunRecordsTheLoadInMetaAndDrawsNoBarWithoutATerminal) {
  const std::string out = *dir_ + "/out";
  CommandResult r = runVshadow(runArgs(out));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // stderr is a file: no bar, no carriage returns or escape sequences, only whole lines.
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\033'), std::string::npos) << r.err;
  auto meta = nlohmann::json::parse(readFile(out + "/meta.json"));
  ASSERT_TRUE(meta.contains("scene_load")) << meta.dump(2);
  const auto& load = meta["scene_load"];
  EXPECT_EQ(load["triangles"].get<size_t>(), kTriangles);
  EXPECT_EQ(meta["scene"]["triangles"].get<size_t>(), kTriangles);
  EXPECT_EQ(load["vertices"].get<size_t>(), kVertices);
  EXPECT_EQ(load["bytes"].get<size_t>(), kVertices * 24 + kTriangles * 12);  // positions, normals, indices
  EXPECT_GT(load["ms"].get<double>(), 0.0);
  // The scene stays in memory, so the peak grew by at least most of its bytes.
  ASSERT_TRUE(load["peak_rss_delta_bytes"].is_number()) << load.dump();
  EXPECT_GE(load["peak_rss_delta_bytes"].get<double>(), 0.5 * double(load["bytes"].get<size_t>())) << load.dump();
}

TEST_F(BigScene, OnATerminalTheLoadDrawsABarAndClearsIt) {
  CommandResult r = runOnTerminal(runArgs(*dir_ + "/out-terminal"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string bar = "\r\033[K[";
  size_t at = r.err.find(bar + "#");
  if (at == std::string::npos) at = r.err.find(bar + ".");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_NE(r.err.find("loading scene " + *dir_ + "/big.json: grid.obj: "), std::string::npos) << r.err;
  // On a terminal the bar is all: no line about the load once it is done.
  EXPECT_EQ(r.err.find(" triangles in "), std::string::npos) << r.err;
}
