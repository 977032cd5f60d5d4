// vshadow view end to end under Xvfb (tests/viewer/xvfb): it starts, renders, writes screenshots
// and exits 0; a screenshot equals the headless `vshadow run` of the same scene, camera, method and
// size; a scripted key sequence switches method and view and the screenshots follow.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "gl_test.hpp"
#include "harness/io/image.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/pipeline/params.hpp"
#include "harness/viewer/viewer_input.hpp"

namespace vs::testing {
namespace {

namespace fs = std::filesystem;

// The viewer and `vshadow run` render with the same driver through the same Runner, seed and
// frame indices; only the context differs (a GLX window against headless EGL). On llvmpipe the
// images are identical; 1e-5 of relMSE leaves room for a driver that rounds differently between
// contexts, and is two orders of magnitude below the smallest method-to-method difference below.
constexpr double kSameImageRelMse = 1e-5;
constexpr double kDifferentImageRelMse = 1e-3;
const std::string kSize = "96x72";

double relMse(const std::string& a, const std::string& b) {
  return compareImages(readImage(a), readImage(b)).relmse;
}

// `vshadow run` of one spec without reference; returns the stem of its images.
std::string headless(const std::string& scene, const std::string& spec, const std::string& dir, int frames = 3) {
  CommandResult r = runVshadow({"run", "--scene", scene, "--method", spec, "--size", kSize, "--frames",
                                std::to_string(frames), "--warmup", "0", "--timer", "wall", "--no-reference", "--out", dir});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    std::string name = entry.path().string();
    if (name.size() > 10 && name.substr(name.size() - 10) == ".final.exr")
      return name.substr(0, name.size() - 10);
  }
  ADD_FAILURE() << "no final image in " << dir;
  return "";
}

CommandResult view(const std::vector<std::string>& extra, const std::string& dir, const std::string& scene = "spheres") {
  std::vector<std::string> args = {"view", "--scene", scene, "--size", kSize, "--timer", "wall", "--cache",
                                   dir + "/cache", "--out", dir};
  args.insert(args.end(), extra.begin(), extra.end());
  return runVshadow(args);
}

TEST(ViewerScript, ParsesEveryCommand) {
  auto c = parseScript("# comment\nframe 3\nkey 2 L f1 escape\nlook 10 -5\nlight 1.5 2\nmove 1 0 -1\n"
                       "param steps 64\nscreenshot out.png\nscene s.json\nquit\nseek 12\nkey k right left home\n",
                       "t.txt");
  ASSERT_EQ(c.size(), 11u);
  EXPECT_EQ(c[0].op, ScriptCommand::Op::Frames);
  EXPECT_EQ(c[0].count, 3);
  EXPECT_EQ(c[1].keys, (std::vector<int>{keyFromName("2"), keyFromName("L"), keyFromName("F1"), keyFromName("ESC")}));
  EXPECT_EQ(c[2].y, -5.0);
  EXPECT_EQ(c[6].value, "out.png");
  EXPECT_EQ(c[8].op, ScriptCommand::Op::Quit);
  EXPECT_EQ(c[8].where, "t.txt:10");
  EXPECT_EQ(c[9].op, ScriptCommand::Op::Seek);
  EXPECT_EQ(c[9].count, 12);
  EXPECT_EQ(c[10].keys.size(), 4u);
  EXPECT_THROW(parseScript("seek -1\n", "t.txt"), UsageError);
  EXPECT_THROW(parseScript("seek 1.5\n", "t.txt"), UsageError);
}

TEST(ViewerScript, BadLinesNameFileAndLine) {
  for (const char* text : {"jump 3", "frame", "frame 0", "frame 2.5", "key", "key NOPE", "look 1", "look x 1",
                           "move 1 2", "screenshot", "quit now"}) {
    try {
      parseScript(std::string("frame 1\n") + text + "\n", "s.txt");
      ADD_FAILURE() << text << " was accepted";
    } catch (const UsageError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("s.txt:2: ", 0), 0u) << e.what();
    }
  }
}

TEST(Viewer, BadInputIsOneLineExit2BeforeAWindowOpens) {
  std::string dir = makeTempDir("view-bad");
  writeFile(dir + "/bad.txt", "frame 1\nfly 2\n");
  const std::vector<std::vector<std::string>> cases = {
      {"view", "--scene", "nope"},
      {"view", "--scene", "spheres", "--method", "bogus"},
      {"view", "--scene", "spheres", "--method", "raymarch:steps=0"},
      {"view", "--scene", "spheres", "--size", "0x5"},
      {"view", "--scene", "spheres", "--script", dir + "/bad.txt"},
      {"view", "--scene", "spheres", "--script", dir + "/missing.txt"},
      {"view", "--scene", "spheres", "--frames", "1", "--screenshot", dir + "/shot.jpg"}};
  for (const auto& args : cases) {
    CommandResult r = runVshadow(args);
    EXPECT_EQ(r.exitCode, 2) << args.back() << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("vshadow: error: ", 0), 0u) << r.err;
  }
}

TEST(Viewer, ScreenshotMatchesTheHeadlessRun) {
  std::string dir = makeTempDir("view-shot");
  const std::string spec = "raymarch:steps=32";
  CommandResult r = view({"--method", spec, "--frames", "3", "--screenshot", dir + "/shot.png"}, dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir + "/shot.png"));
  ASSERT_TRUE(fs::exists(dir + "/shot.exr"));
  Image shot = readImage(dir + "/shot.exr");
  EXPECT_EQ(shot.width, 96);
  EXPECT_EQ(shot.height, 72);
  std::string stem = headless("spheres", spec, dir + "/run");
  EXPECT_LT(relMse(dir + "/shot.exr", stem + ".final.exr"), kSameImageRelMse);
  // The PNG is the PNG the run writes without a reference (exposure from the image itself).
  EXPECT_LT(compareImages(readImage(dir + "/shot.png"), readImage(stem + ".png")).maxAbs, 1e-6);
}

TEST(Viewer, ScriptedKeysSwitchMethodAndView) {
  std::string dir = makeTempDir("view-keys");
  writeFile(dir + "/keys.txt",
            "frame 2\nscreenshot " + dir + "/a.png\n"  // method 1, final image
            "key 2\nframe 2\nscreenshot " + dir + "/b.png\n"  // method 2
            "key L\nframe 1\nscreenshot " + dir + "/c.png\n"  // its L_s
            "key B\nframe 1\nscreenshot " + dir + "/d.png\n"  // first buffer: the shared shadow map
            "key B\nframe 1\nscreenshot " + dir + "/e.png\n"  // minmax's rectified shadow map
            "key F\nlight 40 -10\nframe 2\nscreenshot " + dir + "/f.png\n"  // the light moved
            "scene " + dir + "/moved.json\n");
  CommandResult r = view({"--method", "raymarch:steps=32", "--method", "minmax", "--script", dir + "/keys.txt"}, dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (const char* f : {"a", "b", "c", "d", "e", "f"}) {
    ASSERT_TRUE(fs::exists(dir + "/" + f + ".png")) << f;
    ASSERT_TRUE(fs::exists(dir + "/" + f + ".exr")) << f;
  }
  std::string raymarch = headless("spheres", "raymarch:steps=32", dir + "/run1");
  std::string minmax = headless("spheres", "minmax", dir + "/run2");
  EXPECT_LT(relMse(dir + "/a.exr", raymarch + ".final.exr"), kSameImageRelMse);
  EXPECT_LT(relMse(dir + "/b.exr", minmax + ".final.exr"), kSameImageRelMse);
  EXPECT_GT(relMse(dir + "/b.exr", dir + "/a.exr"), kDifferentImageRelMse);
  EXPECT_LT(relMse(dir + "/c.exr", minmax + ".ls.exr"), kSameImageRelMse);
  EXPECT_GT(relMse(dir + "/c.exr", dir + "/b.exr"), kDifferentImageRelMse);
  // Buffers: a face of the 1024^2 shared cube shadow map, then minmax's own rectified map.
  Image shadow = readImage(dir + "/d.exr");
  EXPECT_EQ(shadow.width, 1024);
  EXPECT_EQ(shadow.height, 1024);
  EXPECT_NE(r.err.find("d.exr (shadow map (shared) layer 0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("e.exr (rectified shadow map"), std::string::npos) << r.err;
  // The moved light changes the image, and the saved scene renders headless to the same image.
  EXPECT_GT(relMse(dir + "/f.exr", dir + "/b.exr"), kDifferentImageRelMse);
  std::string moved = headless(dir + "/moved.json", "minmax", dir + "/run3");
  EXPECT_LT(relMse(dir + "/f.exr", moved + ".final.exr"), kSameImageRelMse);
}

TEST(Viewer, ErrorMapAgainstTheReference) {
  std::string dir = makeTempDir("view-error");
  writeFile(dir + "/error.txt", "frame 1\nkey E\nframe 1\nscreenshot " + dir + "/error.png\nkey R\nframe 1\nscreenshot " +
                                    dir + "/reference.png\n");
  CommandResult r = view({"--method", "raymarch:steps=8", "--script", dir + "/error.txt"}, dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // The EXR of the error view is |L - L_ref| per channel: non-zero for 8 steps, zero nowhere negative.
  Image error = readImage(dir + "/error.exr"), reference = readImage(dir + "/reference.exr");
  double total = 0;
  for (float v : error.rgb) {
    EXPECT_GE(v, 0.0f);
    total += v;
  }
  EXPECT_GT(total, 0.0);
  EXPECT_EQ(reference.width, 96);
}

// A moving scene plays its sequence; K pauses, Right steps, seek jumps. Every screenshot is the
// headless run's image of the same frame, and the reference follows the frame shown.
TEST(Viewer, PlaysPausesStepsAndSeeksASequence) {
  std::string dir = makeTempDir("view-play");
  writeFile(dir + "/play.txt",
            "frame 3\nkey K\nframe 2\nscreenshot " + dir + "/f2.png\n"  // frames 0, 1, 2 played; paused at 2
            "key RIGHT\nframe 1\nscreenshot " + dir + "/f3.png\n"      // a step forward
            "seek 1\nframe 1\nscreenshot " + dir + "/f1.png\n"         // a jump back
            "key R\nframe 1\nscreenshot " + dir + "/r1.png\n"          // the reference of frame 1
            "seek 3\nframe 1\nscreenshot " + dir + "/r3.png\n");       // and of frame 3
  CommandResult r = view({"--method", "minmax", "--script", dir + "/play.txt"}, dir, "sunsweep");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (int frame : {1, 2, 3}) {
    const std::string f = std::to_string(frame);
    std::string stem = headless("sunsweep", "minmax", dir + "/run" + f, frame + 1);
    EXPECT_LT(relMse(dir + "/f" + f + ".exr", stem + ".final.exr"), kSameImageRelMse) << "frame " << f;
  }
  EXPECT_GT(relMse(dir + "/f1.exr", dir + "/f3.exr"), kDifferentImageRelMse);  // the sun moves
  EXPECT_GT(relMse(dir + "/r1.exr", dir + "/r3.exr"), kDifferentImageRelMse);
  EXPECT_NE(r.err.find("reference for frame 1 "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("reference for frame 3 "), std::string::npos) << r.err;

  // A frame outside the sequence, or a seek on a still scene: one line naming the script's line, exit 2.
  writeFile(dir + "/far.txt", "frame 1\nseek 25\n");
  CommandResult far = view({"--method", "minmax", "--script", dir + "/far.txt"}, dir, "sunsweep");
  EXPECT_EQ(far.exitCode, 2) << far.err;
  EXPECT_NE(far.err.find("far.txt:2: seek 25: the sequence has frames 0 to 24"), std::string::npos) << far.err;
  CommandResult still = view({"--method", "minmax", "--script", dir + "/far.txt"}, dir);
  EXPECT_EQ(still.exitCode, 2) << still.err;
  EXPECT_NE(still.err.find("does not move"), std::string::npos) << still.err;
}

}  // namespace
}  // namespace vs::testing
