#include "conformance.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "fixtures.hpp"
#include "gl_test.hpp"
#include "hard_cases.hpp"
#include "harness/io/image.hpp"
#include "harness/evaluation/metrics.hpp"

#include <nlohmann/json.hpp>

namespace vs::testing {
namespace {

constexpr int kWidth = 32, kHeight = 24;
// The shared shadow map at this size for every run, so `sm` itself is never what changes.
const std::string kShared = ":sm=256";

// Scenes that between them reach every effect a method can declare: hard cases, plus a spot light
// with a texture and volume data of two colours.
struct CoverageScene {
  std::string name;
  Scene scene;
};
const std::vector<CoverageScene>& coverageScenes() {
  static const std::vector<CoverageScene> scenes = [] {
    std::vector<CoverageScene> out;
    for (const char* name : {"epipole_on_screen", "spot_epipole_on_screen", "directional_antiparallel_to_view",
                             "volume_in_view", "opacity_half", "area_light"})
      out.push_back({name, sceneFromJson(hardCase(name).json)});
    std::string dir = makeTempDir("conformance");
    Image gobo(4, 4);
    for (size_t i = 0; i < gobo.rgb.size(); ++i) gobo.rgb[i] = float((i / 3 + i / 12) % 2) + 0.25f;
    writeExr(dir + "/gobo.exr", gobo);
    nlohmann::json textured = nlohmann::json::parse(hardCase("spot_epipole_on_screen").json);
    textured["light"]["texture"] = dir + "/gobo.exr";
    out.push_back({"textured_spot_light", sceneFromJson(textured.dump())});
    nlohmann::json coloured = nlohmann::json::parse(hardCase("volume_in_view").json);
    nlohmann::json second = coloured["volumes"][0];
    coloured["volumes"][0]["sigma_s"] = {0.5, 1.5, 3.0};
    second["sigma_s"] = {3.0, 1.5, 0.5};
    second["box_min"] = {0.7, 0.2, -1.0};
    second["box_max"] = {2.2, 1.7, 0.5};
    coloured["volumes"].push_back(second);
    out.push_back({"volume_of_two_colours", sceneFromJson(coloured.dump())});
    // Per-texel opacity: a leaf-card quad (BLEND) whose alpha runs from 0 to 1 across it, above the
    // camera in fog, a point light above it.
    std::vector<float> ramp(16 * 16);
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i) ramp[size_t(j) * 16 + i] = (float(i) + 0.5f) / 16.0f;
    std::string quad = writeAlphaQuadGltf(dir, "ramp", "BLEND", 0.0, 16, 16, ramp, 6.0, 3.0);
    out.push_back({"alpha_textured_quad", sceneFromJson(R"({"geometry": [{"gltf": ")" + quad + R"("},
        {"generator": "plane", "params": {"center": [0, 0, 0], "size": [20, 20]}}],
      "camera": {"position": [0, 1, 5], "target": [0, 2, 0], "fov_y_deg": 60, "near": 0.1, "far": 20},
      "light": {"type": "point", "position": [0.3, 6, 0.2], "intensity": 60},
      "medium": {"sigma_s": 0.1, "sigma_a": 0.02}})")});
    return out;
  }();
  return scenes;
}

struct CaseRun {
  std::string caseName;
  Scene scene;
  MethodRun run;
  std::set<std::string> keysRead;
};

// The method at its defaults on each coverage scene it supports.
std::vector<CaseRun> defaultRuns(const std::string& name) {
  std::vector<CaseRun> runs;
  for (const CoverageScene& coverage : coverageScenes()) {
    CaseRun c{coverage.name, coverage.scene, {}, {}};
    ResolvedSpec spec = resolveSpec(name + kShared, glLimits());
    auto method = createMethod(name);
    if (!method->unsupportedReason(c.scene, spec.params).empty()) continue;
    RunOptions options = RunOptions::singleFrame(kWidth, kHeight);
    Runner runner(c.scene, glLimits(), options);
    c.run = runner.run(*method, spec.params);
    EXPECT_EQ(c.run.status, RunStatus::Success) << name << " on " << coverage.name << ": " << c.run.reason;
    c.keysRead = spec.params.keysRead();
    runs.push_back(std::move(c));
  }
  return runs;
}

std::string formatValue(const ParamSpec& p, double v) {
  if (p.kind == ParamSpec::Kind::Int) return std::to_string(int(std::lround(v)));
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// Values within the parameter's range other than its default, nearest first.
std::vector<std::string> otherValues(const ParamSpec& p) {
  std::vector<std::string> out;
  switch (p.kind) {
    case ParamSpec::Kind::Bool:
      out.push_back(p.defaultValue == "1" || p.defaultValue == "true" ? "0" : "1");
      break;
    case ParamSpec::Kind::Choice:
      for (const std::string& c : p.choices)
        if (c != p.defaultValue) out.push_back(c);
      break;
    case ParamSpec::Kind::Int:
    case ParamSpec::Kind::Float: {
      double d = std::stod(p.defaultValue);
      std::vector<double> candidates;
      if (d != 0.0) candidates = {d * 2.0, d * 0.5};
      candidates.push_back(p.min + 0.25 * (p.max - p.min));
      candidates.push_back(p.min);
      candidates.push_back(p.max);
      for (double v : candidates) {
        if (p.kind == ParamSpec::Kind::Int) v = std::round(v);
        if (p.powerOfTwo) v = std::exp2(std::round(std::log2(std::max(v, 1.0))));
        if (v < p.min || v > p.max || v == d) continue;
        std::string text = formatValue(p, v);
        if (std::find(out.begin(), out.end(), text) == out.end()) out.push_back(text);
      }
      break;
    }
  }
  return out;
}

}  // namespace

void expectFolderAgrees(const std::string& name, const std::string& folder) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(VS_SOURCE_DIR) / folder;
  auto method = createMethod(name);
  EXPECT_EQ(method->name(), name);
  if (folder != "methods/_template") {
    EXPECT_EQ(folder, "methods/" + name) << "the folder is named after the method";
  }
  for (const char* part : {"README.md", "CMakeLists.txt", "tests"})
    EXPECT_TRUE(fs::exists(root / part)) << folder << " has no " << part;
  std::string readme = fs::exists(root / "README.md") ? readFile((root / "README.md").string()) : "";
  EXPECT_EQ(readme.rfind("# " + name, 0) == 0 || readme.rfind("# " + folder.substr(folder.rfind('/') + 1), 0) == 0, true)
      << folder << "/README.md does not start with the method's name";
  for (const ParamSpec& p : method->params())
    EXPECT_NE(readme.find("`" + p.name + "`"), std::string::npos)
        << folder << "/README.md does not name the parameter `" << p.name << "`";
  EXPECT_FALSE(method->description().empty());
  // Its passes: at least one, each once, none with a shared or runner pass's name.
  std::vector<std::string> passes = method->passes();
  EXPECT_FALSE(passes.empty()) << name << " declares no pass";
  std::set<std::string> unique(passes.begin(), passes.end());
  EXPECT_EQ(unique.size(), passes.size()) << name << " declares a pass twice";
  for (const std::string& pass : passes)
    EXPECT_FALSE(isSharedPass(pass) || isRunnerPass(pass)) << name << " declares the harness's pass '" << pass << "'";
  for (const std::string& pass : method->surfacePasses())
    EXPECT_NE(std::find(passes.begin(), passes.end(), pass), passes.end())
        << name << "'s surface pass '" << pass << "' is not among its passes";
}

void expectLadderResolves(const std::string& name) {
  auto method = createMethod(name);
  std::vector<std::string> rungs = method->qualityLadder();
  for (const CoverageScene& coverage : coverageScenes())
    for (const auto& series : method->qualitySeries(deriveEffects(coverage.scene)))
      rungs.insert(rungs.end(), series.rungs.begin(), series.rungs.end());
  EXPECT_FALSE(rungs.empty());
  for (const std::string& rung : rungs) {
    std::string spec = rung.empty() ? name : name + ":" + rung;
    EXPECT_NO_THROW(resolveSpec(spec, glLimits())) << "ladder rung '" << spec << "' does not resolve";
  }
}

void expectParametersReadAndEffective(const std::string& name) {
  std::vector<CaseRun> runs = defaultRuns(name);
  ASSERT_FALSE(runs.empty()) << name << " runs none of the coverage cases";
  auto method = createMethod(name);
  for (const ParamSpec& p : method->params()) {
    std::vector<const CaseRun*> reading;
    for (const CaseRun& c : runs)
      if (c.keysRead.count(p.name) && c.run.status == RunStatus::Success) reading.push_back(&c);
    if (reading.empty()) {
      ADD_FAILURE() << name << " never reads its parameter `" << p.name << "` on any coverage case";
      continue;
    }
    // The largest change of L_s or L (a method's own surface shadows) against the same settings
    // without p's change, over p's other values and the cases that read it: at the defaults, then
    // (for a parameter that only acts behind a switch, e.g. a surface-shadow bias) with each of
    // the method's other flags flipped.
    std::vector<std::string> settings = {""};
    if (!p.speedOnly)
      for (const ParamSpec& flag : method->params())
        if (flag.kind == ParamSpec::Kind::Bool && flag.name != p.name)
          settings.push_back(":" + flag.name + "=" + otherValues(flag).front());
    double largest = 0.0;
    std::string where;
    bool ran = false;
    for (const std::string& setting : settings) {
      for (const CaseRun* c : reading) {
        MethodRun base = setting.empty() ? c->run : renderScene(c->scene, name + kShared + setting, kWidth, kHeight);
        if (base.status != RunStatus::Success) continue;
        for (const std::string& value : otherValues(p)) {
          MethodRun other = renderScene(c->scene, name + kShared + setting + ":" + p.name + "=" + value, kWidth, kHeight);
          if (other.status != RunStatus::Success) continue;  // e.g. a value unsupported with the others' defaults
          ran = true;
          double change = 0.0;
          for (const auto& [a, b] : {std::pair(&other.inscatter, &base.inscatter), std::pair(&other.final, &base.final)}) {
            ErrorMetrics m = compareImages(*a, *b);
            change = std::max({change, m.relmse, m.maxAbs > 0.0 ? 1e-30 : 0.0});
          }
          if (change > largest) {
            largest = change;
            where = p.name + "=" + value + setting + " on " + c->caseName;
          }
          if (!p.speedOnly && largest > 0.0) break;
        }
        if (!p.speedOnly && largest > 0.0) break;
      }
      if (!p.speedOnly && largest > 0.0) break;
    }
    if (!ran) {
      ADD_FAILURE() << name << ": no other value of `" << p.name << "` runs on the cases that read it";
    } else if (p.speedOnly) {
      EXPECT_LE(largest, 1e-6) << name << ": `" << p.name << "` is declared .sameImage() but " << where
                               << " changes the image by relMSE " << largest;
    } else {
      EXPECT_GT(largest, 0.0) << name << ": no value of `" << p.name
                              << "` within its range changes the image on the cases that read it; declare it "
                                 ".sameImage() if it changes only speed or memory";
    }
  }
  // Every std140 mirror of the method's folder was compared with its shader block when the programs
  // above linked (gl::checkProgramInterface; a mismatch fails the run). The reference, which runs
  // every coverage case, also covers the harness's.
  std::set<std::string> checked = gl::checkedStd140Blocks();
  for (const gl::Std140Mirror& m : gl::std140Mirrors()) {
    bool ours = m.source.rfind("methods/" + name + "/", 0) == 0 || (name == "raymarch" && m.source.rfind("harness/", 0) == 0);
    if (ours) {
      EXPECT_TRUE(checked.count(m.block)) << m.cppType << " (" << m.source << ") mirrors " << m.block
                                          << ", which no program of " << name << " on the coverage cases linked";
    }
  }
}

}  // namespace vs::testing
