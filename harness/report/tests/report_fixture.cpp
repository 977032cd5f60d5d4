#include "report_fixture.hpp"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "harness/io/image.hpp"
#include "harness/io/results.hpp"

namespace vs::testing {

namespace fs = std::filesystem;

std::vector<FixtureRow> fixtureRows() {
  return {
      {"raymarch", "steps=256:jitter=1:sampling=uniform:sm=1024", "uniform", "Success", "", "41.5", "52.25", "0.00123457",
       "1.5e-05", ""},
      {"raymarch", "steps=16:jitter=1:sampling=uniform:sm=1024", "uniform", "Success", "", "3.125", "14.0625", "0.0312",
       "0.00234", ""},
      {"raymarch", "steps=32:jitter=1:sampling=equiangular:sm=1024", "equiangular", "Success", "", "6.5", "17.5",
       "0.00891", "0.000412", ""},
      {"minmax", "rank=2:steps=64:sm=1024", "", "Success", "", "2.75", "13.8", "0.00456789", "0.000123457", "3.7"},
      {"vsv", "alpha=64:theta=128:phi=128:sm=1024", "", "Success", "", "9.87654", "20.1", "0.0009", "8.5e-06", ">=41.5"},
      {"dsm", "res=256:sm=1024", "", "Unsupported", "no volume data in the scene (dsm needs volumes)", "", "", "", "", ""},
      {"slicemap", "res=128:sm=1024", "", "Failure",
       "shader \"slice.frag\" failed: 0:12(3): error, </script><script>bad()</script>", "", "", "", "", ""},
  };
}

namespace {

// A PNG of one colour with a light diagonal, so that images differ and show pixels when zoomed.
void writeTile(const std::string& path, uint8_t r, uint8_t g, uint8_t b) {
  const int w = 16, h = 12;
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &rgb[(size_t(y) * w + x) * 3];
      bool line = x == y;
      p[0] = line ? 255 : r;
      p[1] = line ? 255 : g;
      p[2] = line ? 255 : b;
    }
  writePng8(path, w, h, rgb);
}

std::string sanitize(const std::string& s) {  // as harness/cli/app.cpp
  std::string out;
  for (char c : s) out += (std::isalnum(uint8_t(c)) || c == '-' || c == '.') ? c : '_';
  return out.empty() ? "default" : out;
}

nlohmann::json fixtureMeta(const std::string& scene) {
  return {{"command_line", "vshadow shootout --scene " + scene + " --size 16x12 --frames 2"},
          {"git_sha", "0123456789ab"},
          {"date", "2026-12-07T10:00:00Z"},
          {"build", {{"type", "Release"}, {"compiler", "GNU 12.2.0"}, {"flags", "-O3"}, {"sanitizers", "none"}, {"assertions", false}}},
          {"gl", {{"vendor", "Mesa"}, {"renderer", "llvmpipe (LLVM 15.0.6, 256 bits)"}, {"version", "4.5 (Core Profile) Mesa 22.3.6"}}},
          {"egl", {{"vendor", "Mesa Project"}, {"version", "1.5"}, {"platform", "surfaceless"}}},
          {"cpu", {{"model", "Test CPU"}, {"hardware_threads", 2}}},
          {"width", 16},
          {"height", 12},
          {"frames", 2},
          {"warmup", 1},
          {"rounds", 1},
          {"seed", 1},
          {"timer", {{"strategy", "wall-clock"}, {"reason", "timestamps disagree with the wall clock"}}},
          {"scene", {{"name", scene}, {"source", "builtin:" + scene}, {"effects", "scattering+extinction+point"}, {"triangles", 1234}}},
          {"reference", {{"method", "raymarch"}, {"params", "steps=4096"}, {"cached", true}}},
          {"status", "finished"}};
}

}  // namespace

void writeShootoutFixture(const std::string& dir, const std::string& scene, bool images, bool frames) {
  fs::create_directories(dir);
  const auto& cols = runsColumns();
  std::string runs = CsvTable::format(cols), passes = CsvTable::format(passesColumns());
  std::string framesCsv = CsvTable::format(framesColumns());
  const fs::path imageDir = fs::path(dir) / "images" / sanitize(scene);
  if (images) {
    fs::create_directories(imageDir);
    writeTile((imageDir / "reference.png").string(), 40, 60, 200);
  }
  int k = 0;
  for (const FixtureRow& f : fixtureRows()) {
    ResultRow row(cols);
    row.set("scene", scene).set("method", f.method).set("params", f.params).set("series", f.series);
    row.set("status", f.status).set("reason", f.reason).set("effects", "scattering+extinction+point");
    row.set("width", "16").set("height", "12").set("frames", "2").set("timer", "wall-clock");
    row.set("renderer", "llvmpipe (LLVM 15.0.6, 256 bits)").set("date", "2026-12-07T10:00:00Z");
    if (f.status == "Success") {
      row.set("scatter_ms", f.scatterMs).set("frame_median_ms", f.frameMs).set("ls_rmse", f.lsRmse);
      row.set("ls_relmse", f.lsRelmse).set("rmse", f.lsRmse).set("psnr", "38.5").set("ssim", "0.987654");
      row.set("passes", "Shadow Map;G Buffer;Direct Lighting;Own Pass;Composite").set("rounds", "1");
      row.set("method_stats", "pixels_per_s=92771.8;" + f.method + "_iterations_mean=" + std::to_string(10 + k));
      if (!f.speedupUniform.empty()) {
        row.set("eq_error_against", "exact").set("eq_uniform_steps", "97").set("eq_uniform_ms", "10.2");
        row.set("eq_uniform_round_min_ms", "9.9").set("eq_uniform_round_max_ms", "10.4");
        row.set("speedup_eq_uniform", f.speedupUniform).set("speedup_eq_uniform_round_min", "3.5");
        row.set("speedup_eq_uniform_round_max", "3.9");
      }
      double own = std::stod(f.scatterMs);
      for (auto [pass, ms] : std::vector<std::pair<std::string, double>>{{"Shadow Map", 4.5}, {"G Buffer", 2.25},
                                                                           {"Direct Lighting", 1.5}, {"Own Pass", own},
                                                                           {"Composite", 0.75}, {"Frame", 9.0 + own}}) {
        ResultRow p(passesColumns());
        p.set("scene", scene).set("method", f.method).set("params", f.params).set("pass", pass);
        p.set("median_ms", ms).set("min_ms", ms * 0.9).set("max_ms", ms * 1.1).set("frames", 2);
        p.set("timer", "wall-clock").set("renderer", "llvmpipe (LLVM 15.0.6, 256 bits)");
        passes += CsvTable::format(p.fields());
      }
      if (images) {
        std::string stem = (imageDir / (sanitize(f.method) + "_" + sanitize(f.params))).string();
        writeTile(stem + ".png", uint8_t(60 + 30 * k), 60, 190);
        writeTile(stem + ".error.png", 10, uint8_t(40 * k), 10);
      }
      for (int frame = 0; frames && frame < 3; ++frame) {
        ResultRow fr(framesColumns());
        fr.set("scene", scene).set("method", f.method).set("params", f.params).set("frame", frame);
        fr.set("time_s", frame * 0.5).set("frame_ms", std::stod(f.frameMs) + frame);
        fr.set("ls_rmse", std::stod(f.lsRmse) * (1 + frame)).set("ls_relmse", f.lsRelmse);
        fr.set("pass_ms", "Own Pass=" + f.scatterMs).set("timer", "wall-clock").set("renderer", "llvmpipe");
        framesCsv += CsvTable::format(fr.fields());
      }
    }
    runs += CsvTable::format(row.fields());
    ++k;
  }
  writeFileAtomic(dir + "/runs.csv", runs);
  writeFileAtomic(dir + "/passes.csv", passes);
  if (frames) writeFileAtomic(dir + "/frames.csv", framesCsv);
  nlohmann::json meta = fixtureMeta(scene);
  if (frames)
    meta["scene"]["animation"] = {{"description", "the sun sweeps"}, {"duration_s", 1.5}, {"fps", 2}, {"sequence_frames", 3}};
  writeFileAtomic(dir + "/meta.json", meta.dump(2) + "\n");
}

void writeLargeFixture(const std::string& dir, int rows) {
  fs::create_directories(dir);
  const auto& cols = runsColumns();
  std::string runs = CsvTable::format(cols), passes = CsvTable::format(passesColumns());
  const char* methods[] = {"raymarch", "minmax", "vsv", "froxel", "slicemap"};
  uint32_t state = 12345;
  auto random = [&state] {  // a small LCG: the same table every time
    state = state * 1664525u + 1013904223u;
    return double(state >> 8) / double(1u << 24);
  };
  for (int i = 0; i < rows; ++i) {
    const std::string method = methods[i % 5], params = "steps=" + std::to_string(i) + ":sm=1024";
    ResultRow row(cols);
    row.set("scene", "forest").set("method", method).set("params", params).set("width", "384").set("height", "288");
    bool unsupported = i % 97 == 13;
    row.set("status", unsupported ? "Unsupported" : "Success");
    if (unsupported) row.set("reason", "area lights are not supported");
    double scatter = 0.5 + 100 * random(), error = 1e-4 + 0.05 * random();
    if (!unsupported) {
      row.set("scatter_ms", scatter).set("frame_median_ms", scatter + 8).set("ls_rmse", error).set("ls_relmse", error * error);
      for (auto [pass, ms] : std::vector<std::pair<std::string, double>>{
               {"Shadow Map", 4.0}, {"G Buffer", 2.0}, {"Own Pass", scatter}, {"Frame", scatter + 8}}) {
        ResultRow p(passesColumns());
        p.set("scene", "forest").set("method", method).set("params", params).set("pass", pass).set("median_ms", ms);
        passes += CsvTable::format(p.fields());
      }
    }
    runs += CsvTable::format(row.fields());
  }
  writeFileAtomic(dir + "/runs.csv", runs);
  writeFileAtomic(dir + "/passes.csv", passes);
  writeFileAtomic(dir + "/meta.json", fixtureMeta("forest").dump(2) + "\n");
}

}  // namespace vs::testing
