// vshadow report: the data the page embeds, and the command's answers to bad input.
#include "harness/report/report.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "gl_test.hpp"
#include "harness/io/results.hpp"
#include "harness/pipeline/params.hpp"
#include "report_fixture.hpp"

namespace vs::testing {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The page's embedded data, read back from the HTML.
json embeddedData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  size_t a = html.find(open);
  EXPECT_NE(a, std::string::npos);
  a += open.size();
  size_t b = html.find("</script>", a);
  return json::parse(html.substr(a, b - a));
}

std::vector<std::vector<std::string>> csvRows(const std::string& path) {
  auto rows = CsvTable::parse(readFile(path));
  rows.erase(rows.begin());
  return rows;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Every row of runs.csv is in the data exactly once, each field as its text in the CSV.
TEST(Report, EveryRowOnceWithItsFieldsAsInTheCsv) {
  std::string dir = makeTempDir("report-rows");
  writeShootoutFixture(dir + "/out", "spheres", true, false);
  json data = collectReportData(dir + "/out", dir + "/out");
  ASSERT_EQ(data["scenes"].size(), 1u);
  const json& scene = data["scenes"][0];
  EXPECT_EQ(scene["name"], "spheres");
  EXPECT_EQ(scene["columns"].get<std::vector<std::string>>(), runsColumns());
  auto csv = csvRows(dir + "/out/runs.csv");
  ASSERT_EQ(scene["rows"].size(), csv.size());
  for (const auto& row : csv) {
    int found = 0;
    for (const auto& r : scene["rows"]) found += r.get<std::vector<std::string>>() == row;
    EXPECT_EQ(found, 1) << row[1] << " " << row[2];
  }
  // Numbers keep their text: no reformatting on the way into the page.
  std::string html = renderReportPage(data);
  for (const char* text : {"\"0.00123457\"", "\"1.5e-05\"", "\"8.5e-06\"", "\">=41.5\"", "\"9.87654\"", "\"0.987654\""})
    EXPECT_GE(count(html, text), 1) << text;
  EXPECT_EQ(embeddedData(html), data);
}

TEST(Report, UnsupportedAndFailedRowsKeepTheirReasons) {
  std::string dir = makeTempDir("report-reasons");
  writeShootoutFixture(dir, "fence", false, false);
  json data = collectReportData(dir, dir);
  std::map<std::string, std::string> reasons;
  const json& scene = data["scenes"][0];
  auto columns = scene["columns"].get<std::vector<std::string>>();
  auto at = [&](const std::string& c) { return size_t(std::find(columns.begin(), columns.end(), c) - columns.begin()); };
  for (const auto& r : scene["rows"])
    if (r[at("status")] != "Success") reasons[r[at("method")].get<std::string>()] = r[at("reason")];
  ASSERT_EQ(reasons.size(), 2u);
  EXPECT_EQ(reasons["dsm"], "no volume data in the scene (dsm needs volumes)");
  EXPECT_EQ(reasons["slicemap"], "shader \"slice.frag\" failed: 0:12(3): error, </script><script>bad()</script>");
  // The markup in a reason cannot close the data's script element.
  std::string html = renderReportPage(data);
  EXPECT_EQ(html.find("<script>bad()"), std::string::npos);
  EXPECT_EQ(count(html, "</script>"), 2);
  EXPECT_EQ(embeddedData(html), data);
}

TEST(Report, PassesAndImagesBelongToTheirRows) {
  std::string dir = makeTempDir("report-passes");
  writeShootoutFixture(dir + "/res", "spheres", true, false);
  fs::create_directories(dir + "/pages");
  json data = collectReportData(dir + "/res", dir + "/pages");
  const json& scene = data["scenes"][0];
  auto names = scene["pass_names"].get<std::vector<std::string>>();
  auto shared = scene["pass_shared"].get<std::vector<bool>>();
  for (size_t p = 0; p < names.size(); ++p) EXPECT_EQ(shared[p], names[p] != "Own Pass") << names[p];
  auto columns = scene["columns"].get<std::vector<std::string>>();
  size_t status = size_t(std::find(columns.begin(), columns.end(), "status") - columns.begin());
  size_t scatter = size_t(std::find(columns.begin(), columns.end(), "scatter_ms") - columns.begin());
  for (size_t r = 0; r < scene["rows"].size(); ++r) {
    bool success = scene["rows"][r][status] == "Success";
    const json& passes = scene["passes"][r];
    EXPECT_EQ(passes.size(), success ? 6u : 0u);
    for (const auto& p : passes) {  // [pass, median, min, max]: the own pass is the row's scattering time
      if (names[p[0].get<size_t>()] == "Own Pass") {
        EXPECT_EQ(p[1], scene["rows"][r][scatter]);
      }
    }
    const json& images = scene["images"][r];
    ASSERT_EQ(images.is_null(), !success);
    if (!success) continue;
    for (const auto& url : images) {
      ASSERT_TRUE(url.is_string());
      EXPECT_EQ(url.get<std::string>().rfind("../res/images/spheres/", 0), 0u) << url;
      EXPECT_TRUE(fs::exists(fs::path(dir) / "pages" / url.get<std::string>())) << url;
    }
  }
  EXPECT_TRUE(data["warnings"].empty()) << data["warnings"];
}

// scripts/run's layout: a folder per scene (one animated, with its video beside it).
TEST(Report, ParentFolderOfScenesWithFramesAndVideo) {
  std::string dir = makeTempDir("report-parent");
  writeShootoutFixture(dir + "/spheres", "spheres", true, false);
  writeShootoutFixture(dir + "/sunsweep", "sunsweep", true, true);
  writeFile(dir + "/video-sunsweep.mp4", "not decoded here");
  json data = collectReportData(dir, dir);
  ASSERT_EQ(data["scenes"].size(), 2u);
  EXPECT_EQ(data["sources"].size(), 2u);
  EXPECT_EQ(data["sources"][0]["folder"], "spheres");
  EXPECT_EQ(data["sources"][0]["meta"]["gl"]["renderer"], "llvmpipe (LLVM 15.0.6, 256 bits)");
  const json& still = data["scenes"][0];
  const json& moving = data["scenes"][1];
  EXPECT_EQ(still["name"], "spheres");
  EXPECT_TRUE(still["frames"].is_null());
  EXPECT_TRUE(still["videos"].empty());
  EXPECT_EQ(moving["name"], "sunsweep");
  EXPECT_EQ(moving["videos"], json::array({"video-sunsweep.mp4"}));
  ASSERT_TRUE(moving["frames"].is_array());
  size_t withFrames = 0;
  for (const auto& f : moving["frames"]) withFrames += f.size() == 3;
  EXPECT_EQ(withFrames, 5u);  // the Success rows, three frames each
  EXPECT_EQ(moving["frames"][0][1], json::array({"1", "0.5", "53.25", "0.00246914", "1.5e-05"}));
}

// A merged sweep: rows tagged with seed, host and shard; passes matched on them too.
TEST(Report, MergedSweepFolder) {
  std::string dir = makeTempDir("report-merged");
  writeShootoutFixture(dir + "/a", "spheres", true, false);
  writeShootoutFixture(dir + "/b", "fence", false, false);
  CommandResult merged = runVshadow({"merge", dir + "/a", dir + "/b", "--out", dir + "/merged"});
  ASSERT_EQ(merged.exitCode, 0) << merged.err;
  json data = collectReportData(dir + "/merged", dir + "/merged");
  ASSERT_EQ(data["scenes"].size(), 2u);
  EXPECT_EQ(data["sources"][0]["meta"]["shards"].size(), 2u);
  size_t rows = 0, withPasses = 0;
  for (const auto& scene : data["scenes"]) {
    rows += scene["rows"].size();
    for (const auto& p : scene["passes"]) withPasses += !p.empty();
    auto columns = scene["columns"].get<std::vector<std::string>>();
    EXPECT_NE(std::find(columns.begin(), columns.end(), "shard"), columns.end());
  }
  EXPECT_EQ(rows, 2 * fixtureRows().size());
  EXPECT_EQ(withPasses, 2 * 5u);
  EXPECT_TRUE(data["warnings"].empty()) << data["warnings"];
}

TEST(Report, CommandWritesOnePageWithNothingFetched) {
  std::string dir = makeTempDir("report-cmd");
  writeShootoutFixture(dir, "spheres", true, false);
  CommandResult r = runVshadow({"report", dir});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out, "report: " + dir + "/report.html\n");
  std::string html = readFile(dir + "/report.html");
  EXPECT_EQ(html.rfind("<!doctype html>", 0), 0u);
  // One file: no external script, style or font; the only URLs are the images' relative paths.
  for (const char* remote : {"<script src", "<link", "@import", "url(", "src=\"http", "href=\"http", "//cdn"})
    EXPECT_EQ(html.find(remote), std::string::npos) << remote;
  EXPECT_NE(html.find("Content-Security-Policy"), std::string::npos);
  // -o elsewhere: the images are referenced from there.
  fs::create_directories(dir + "/elsewhere");
  r = runVshadow({"report", dir, "-o", dir + "/elsewhere/page.html"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  json data = embeddedData(readFile(dir + "/elsewhere/page.html"));
  EXPECT_EQ(data["scenes"][0]["images"][0][0], "../images/spheres/reference.png");
}

// --embed-images: a single file to send, within a budget; images over it stay referenced.
TEST(Report, ImagesEmbeddedWithinTheBudget) {
  std::string dir = makeTempDir("report-embed");
  writeShootoutFixture(dir, "spheres", true, false);
  json data = collectReportData(dir, dir);
  size_t total = 0, files = 0;
  for (const auto& e : fs::directory_iterator(dir + "/images/spheres")) total += fs::file_size(e.path()), ++files;
  json all = data;
  EXPECT_EQ(embedImages(all, dir, total), files);  // the reference once, though every row shows it
  for (const auto& images : all["scenes"][0]["images"])
    for (const auto& url : images.is_array() ? images : json::array())
      EXPECT_EQ(url.get<std::string>().rfind("data:image/png;base64,iVBORw0KGgo", 0), 0u);
  EXPECT_TRUE(all["warnings"].empty());
  json some = data;
  size_t embedded = embedImages(some, dir, total / 2);
  EXPECT_GT(embedded, 0u);
  EXPECT_LT(embedded, files);
  ASSERT_EQ(some["warnings"].size(), 1u);
  EXPECT_NE(some["warnings"][0].get<std::string>().find("referenced, not embedded"), std::string::npos);
  CommandResult r = runVshadow({"report", dir, "--embed-images", "1"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::string html = readFile(dir + "/report.html");
  EXPECT_EQ(html.find("images/spheres/"), std::string::npos);
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
}

struct BadInput {
  std::string name;
  std::function<void(const std::string& dir)> make;  // fills the folder
  std::string out;                                     // -o, relative to the folder; empty: default
  std::string message;                                 // part of the one line on stderr
};

TEST(Report, BadInputIsOneLineExitTwoAndNothingWritten) {
  std::vector<BadInput> cases = {
      {"missing folder", [](const std::string&) {}, "", "no such folder"},
      {"no runs.csv", [](const std::string& d) { fs::create_directories(d + "/res/empty"); }, "", "no runs.csv"},
      {"runs.csv row of the wrong width",
       [](const std::string& d) {
         writeShootoutFixture(d + "/res", "spheres", false, false);
         writeFile(d + "/res/runs.csv", readFile(d + "/res/runs.csv") + "spheres,raymarch,steps=1\n");
       },
       "", "row 8 has 3 fields"},
      {"runs.csv without a status column",
       [](const std::string& d) {
         fs::create_directories(d + "/res");
         writeFile(d + "/res/runs.csv", "scene,method,params\nspheres,raymarch,steps=1\n");
       },
       "", "no column 'status'"},
      {"empty runs.csv",
       [](const std::string& d) {
         fs::create_directories(d + "/res");
         writeFile(d + "/res/runs.csv", "");
       },
       "", "empty table"},
      {"malformed meta.json",
       [](const std::string& d) {
         writeShootoutFixture(d + "/res", "spheres", false, false);
         writeFile(d + "/res/meta.json", "{\"date\": ");
       },
       "", "meta.json: malformed JSON"},
      {"malformed passes.csv",
       [](const std::string& d) {
         writeShootoutFixture(d + "/res", "spheres", false, false);
         writeFile(d + "/res/passes.csv", "scene,method\n");
       },
       "", "passes.csv: malformed table"},
      {"-o below a regular file",
       [](const std::string& d) {
         writeShootoutFixture(d + "/res", "spheres", false, false);
         writeFile(d + "/a-file", "x");
       },
       "a-file/report.html", "is not a folder"},
  };
  for (const auto& c : cases) {
    std::string dir = makeTempDir("report-bad");
    c.make(dir);
    std::string res = dir + "/res";
    // A page already there stays as it was.
    if (fs::is_directory(res)) writeFile(res + "/report.html", "earlier page");
    std::vector<std::string> args = {"report", res};
    if (!c.out.empty()) args.insert(args.end(), {"-o", dir + "/" + c.out});
    CommandResult r = runVshadow(args);
    EXPECT_EQ(r.exitCode, 2) << c.name << ": " << r.err;
    EXPECT_EQ(count(r.err, "\n"), 1) << c.name << ": " << r.err;
    EXPECT_EQ(r.err.rfind("vshadow: error: report: ", 0), 0u) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.name << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.name;
    if (fs::is_directory(res)) {
      EXPECT_EQ(readFile(res + "/report.html"), "earlier page") << c.name;
      for (const auto& e : fs::recursive_directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << c.name << ": " << e.path();
    }
    fs::remove_all(dir);
  }
}

TEST(Report, DataErrorsAreUsageErrors) {
  EXPECT_THROW(collectReportData("/nonexistent/folder", "."), UsageError);
  std::string dir = makeTempDir("report-usage");
  writeFile(dir + "/runs.csv", CsvTable::format(runsColumns()));
  EXPECT_THROW(collectReportData(dir, dir), UsageError);  // a header and no rows
}

}  // namespace
}  // namespace vs::testing
