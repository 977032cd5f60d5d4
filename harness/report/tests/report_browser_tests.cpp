// vshadow report in a real browser: the distribution's Chromium, headless, opens generated pages
// from the file system with the page's self-test (#selftest), which clicks through the page and
// writes its verdict into pre#selftest; a screenshot is kept in the build tree. Outside CI the
// tests are skipped when Chromium is not installed (scripts/deps --tests installs it).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "gl_test.hpp"
#include "report_fixture.hpp"

namespace vs::testing {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string chromiumPath() {
  const char* env = std::getenv("VSHADOW_CHROMIUM");
  return env && *env ? env : "/usr/bin/chromium";
}

struct BrowserRun {
  int exitCode = -1;
  bool timedOut = false;
  double seconds = 0;
  std::string out, err;
};

// Runs Chromium headless on `url` with `extra` arguments, killed after `timeoutS`. The flags keep
// it off the network (no component updates, sync or background fetches) and out of the user's
// profile.
BrowserRun runChromium(const std::string& url, const std::vector<std::string>& extra, double timeoutS = 90) {
  std::string tmp = makeTempDir("report-chromium");
  std::vector<std::string> args = {chromiumPath(), "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                                   "--no-first-run", "--disable-background-networking", "--disable-component-update",
                                   "--disable-sync", "--disable-extensions", "--disable-dev-shm-usage",
                                   "--user-data-dir=" + tmp + "/profile", "--enable-logging=stderr", "--v=0",
                                   "--allow-file-access-from-files"};
  args.insert(args.end(), extra.begin(), extra.end());
  args.push_back(url);
  std::string outPath = tmp + "/stdout", errPath = tmp + "/stderr";
  auto start = std::chrono::steady_clock::now();
  pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);  // its own group, so a timeout ends every Chromium process
    int in = ::open("/dev/null", O_RDONLY);
    int out = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::setpgid(pid, pid);
  BrowserRun run;
  int status = 0;
  while (true) {
    pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > timeoutS) {
      run.timedOut = true;
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(-pid, SIGKILL);  // helpers left behind, if any
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.out = readFile(outPath);
  run.err = readFile(errPath);
  fs::remove_all(tmp);
  return run;
}

std::string htmlUnescape(std::string s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '&') {
      for (auto [entity, c] : std::vector<std::pair<std::string, char>>{
               {"&quot;", '"'}, {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&#39;", '\''}})
        if (s.compare(i, entity.size(), entity) == 0) {
          out += c;
          i += entity.size() - 1;
          goto next;
        }
    }
    out += s[i];
  next:;
  }
  return out;
}

// Lines in which Chromium logged a message of the page's console, or a script error.
std::vector<std::string> consoleLines(const std::string& err) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < err.size()) {
    size_t end = err.find('\n', start);
    if (end == std::string::npos) end = err.size();
    std::string line = err.substr(start, end - start);
    if (line.find(":CONSOLE") != std::string::npos || line.find("Uncaught") != std::string::npos) lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

bool chromiumAvailable() {
  if (::access(chromiumPath().c_str(), X_OK) == 0) return true;
  if (std::getenv("CI")) ADD_FAILURE() << chromiumPath() << " is missing (scripts/deps --tests installs chromium)";
  return false;
}

// Opens `page` with #selftest and returns the verdict the page wrote, after checking the run.
json selfTest(const std::string& page, double* seconds = nullptr) {
  BrowserRun run = runChromium("file://" + fs::absolute(page).string() + "#selftest",
                               {"--virtual-time-budget=30000", "--window-size=1280,1000", "--dump-dom"});
  if (seconds) *seconds = run.seconds;
  EXPECT_FALSE(run.timedOut) << "Chromium did not finish; its log:\n" << run.err.substr(0, 4000);
  EXPECT_EQ(run.exitCode, 0) << run.err.substr(0, 4000);
  for (const auto& line : consoleLines(run.err)) ADD_FAILURE() << "console: " << line;
  const std::string open = "<pre id=\"selftest\">";
  size_t a = run.out.find(open);
  if (a == std::string::npos) {
    ADD_FAILURE() << "no self-test verdict in the page (it did not finish in the virtual time budget?); log:\n"
                  << run.err.substr(0, 4000);
    return json::object();
  }
  a += open.size();
  size_t b = run.out.find("</pre>", a);
  json verdict = json::parse(htmlUnescape(run.out.substr(a, b - a)), nullptr, false);
  EXPECT_FALSE(verdict.is_discarded()) << run.out.substr(a, 2000);
  return verdict;
}

void expectPassed(const json& verdict) {
  ASSERT_TRUE(verdict.is_object());
  for (const auto& c : verdict.value("checks", json::array()))
    EXPECT_TRUE(c["ok"].get<bool>()) << c["name"].get<std::string>() << ": " << c["detail"].get<std::string>();
  for (const auto& e : verdict.value("errors", json::array())) ADD_FAILURE() << "page error: " << e.get<std::string>();
  EXPECT_TRUE(verdict.value("ok", false));
}

std::string artifactDir() {
  std::string dir = std::string(VS_REPORT_ARTIFACTS);
  fs::create_directories(dir);
  return dir;
}

// scripts/run's layout (a still and an animated scene) and a merged sweep beside it: the page
// loads without errors, draws a chart point per row, sorts, filters and switches images.
TEST(ReportBrowser, SmallShootoutPassesTheSelfTest) {
  if (!chromiumAvailable()) GTEST_SKIP() << chromiumPath() << " not installed";
  std::string dir = makeTempDir("report-browser");
  writeShootoutFixture(dir + "/shootout/spheres", "spheres", true, false);
  writeShootoutFixture(dir + "/shootout/sunsweep", "sunsweep", true, true);
  // The animated scene's video beside its folder, as scripts/video writes it (H.264 by ffmpeg).
  bool video = std::system(("ffmpeg -v error -nostdin -f lavfi -i color=c=gray:s=32x24:d=0.5:r=4 -c:v libx264 "
                            "-pix_fmt yuv420p -y '" + dir + "/shootout/video-sunsweep.mp4' >/dev/null 2>&1")
                               .c_str()) == 0;
  CommandResult r = runVshadow({"report", dir + "/shootout"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  json verdict = selfTest(dir + "/shootout/report.html");
  expectPassed(verdict);
  EXPECT_EQ(verdict.value("scenes", 0), 2);
  EXPECT_EQ(verdict.value("rows", 0), int(2 * fixtureRows().size()));
  // Two charts per scene, a point per Success row in each.
  EXPECT_EQ(verdict.value("points", 0), 2 * 2 * 5);
  size_t imageChecks = 0;
  for (const auto& c : verdict.value("checks", json::array()))
    imageChecks += c["name"].get<std::string>().find("image toggle") != std::string::npos;
  EXPECT_EQ(imageChecks, 2u * 3u);  // reference, method and error map in each scene
  bool videoChecked = false;
  for (const auto& c : verdict.value("checks", json::array()))
    videoChecked = videoChecked || c["name"] == "sunsweep: video loads";
  EXPECT_EQ(videoChecked, video) << (video ? "the video was not shown" : "ffmpeg could not make the test's video");

  // The screenshot, kept in the build tree.
  std::string shot = artifactDir() + "/report-small.png";
  fs::remove(shot);
  BrowserRun run = runChromium("file://" + fs::absolute(dir + "/shootout/report.html").string(),
                               {"--virtual-time-budget=10000", "--window-size=1280,1600", "--hide-scrollbars",
                                "--screenshot=" + shot});
  EXPECT_FALSE(run.timedOut);
  ASSERT_TRUE(fs::exists(shot)) << run.err.substr(0, 4000);
  EXPECT_GT(fs::file_size(shot), 10000u);
  EXPECT_EQ(readFile(shot).substr(1, 3), "PNG");
  fs::remove_all(dir);
}

// A sweep of 5,000 rows: the page opens and passes the same checks well within the bound.
TEST(ReportBrowser, LargeSweepOpensWithinTheBound) {
  if (!chromiumAvailable()) GTEST_SKIP() << chromiumPath() << " not installed";
  std::string dir = makeTempDir("report-browser-large");
  writeLargeFixture(dir + "/sweep", 5000);
  CommandResult r = runVshadow({"report", dir + "/sweep"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_LT(fs::file_size(dir + "/sweep/report.html"), 8u << 20);
  double seconds = 0;
  json verdict = selfTest(dir + "/sweep/report.html", &seconds);
  expectPassed(verdict);
  EXPECT_EQ(verdict.value("rows", 0), 5000);
  // Generous bounds: the page's own drawing, and the whole browser run from start to the DOM dump.
  EXPECT_LT(verdict.value("render_ms", 1e9), 10000) << "drawing the page took too long";
  EXPECT_LT(seconds, 60) << "the browser run took too long";
  std::printf("5,000 rows: page drawn in %d ms, browser run %.1f s\n", verdict.value("render_ms", -1), seconds);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace vs::testing
