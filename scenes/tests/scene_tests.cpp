// Tests for scene loading: JSON validation, built-in scenes, generators, glTF, degenerate input, hashes.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "scenes/builtin_scenes.hpp"
#include "scenes/content_hash.hpp"
#include "scenes/gltf_loader.hpp"
#include "scenes/mesh_utils.hpp"
#include "scenes/procedural.hpp"
#include "scenes/scene.hpp"
#include "fixtures.hpp"

namespace fs = std::filesystem;
using vs::Scene;
using vs::SceneError;

namespace {

// A fresh directory per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    path_ = fs::temp_directory_path() /
            ("vs_scene_tests_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& contents) const {
    fs::path target = path_ / name;
    fs::create_directories(target.parent_path());
    std::ofstream(target, std::ios::binary) << contents;
    return target.string();
  }

 private:
  fs::path path_;
};

const char* kCamera = R"("camera": {"position": [0, 2, 6], "target": [0, 1, 0]})";
const char* kPointLight = R"("light": {"type": "point", "position": [0, 5, 0], "intensity": 50})";

// A scene with the standard camera; an empty `light` leaves the light out.
std::string sceneText(const std::string& geometry, const std::string& light = kPointLight,
                      const std::string& extra = "") {
  std::string text = std::string("{\n  \"geometry\": [") + geometry + "],\n  " + kCamera;
  if (!light.empty()) text += ",\n  " + light;
  if (!extra.empty()) text += ",\n  " + extra;
  return text + "\n}\n";
}

Scene parse(const std::string& text) { return vs::parseSceneJson(text, "", "test.json"); }

// Writes `text` to a file, loads it and returns the SceneError message ("" when it loads).
std::string loadError(const TempDir& dir, const std::string& text, const std::string& name = "broken_scene.json") {
  std::string path = dir.write(name, text);
  try {
    vs::loadScene(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

// Every SceneError must be one line naming the file.
void expectErrorMentions(const std::string& message, const std::vector<std::string>& parts) {
  ASSERT_FALSE(message.empty()) << "expected a SceneError";
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find("broken_scene.json"), std::string::npos) << message;
  for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
}

void expectValidMesh(const vs::Mesh& mesh) {
  ASSERT_EQ(mesh.positions.size(), mesh.normals.size());
  ASSERT_EQ(mesh.indices.size() % 3, 0u);
  for (uint32_t i : mesh.indices) ASSERT_LT(i, mesh.positions.size());
  for (const glm::vec3& n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
  for (const glm::vec3& p : mesh.positions) ASSERT_TRUE(std::isfinite(p.x + p.y + p.z));
}

// Fraction of triangles whose counter-clockwise face normal agrees with their vertex normals.
double windingAgreement(const vs::Mesh& mesh) {
  size_t agree = 0;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const glm::vec3 &a = mesh.positions[mesh.indices[t]], &b = mesh.positions[mesh.indices[t + 1]],
                    &c = mesh.positions[mesh.indices[t + 2]];
    glm::vec3 n = mesh.normals[mesh.indices[t]] + mesh.normals[mesh.indices[t + 1]] + mesh.normals[mesh.indices[t + 2]];
    if (glm::dot(glm::cross(b - a, c - a), n) > 0.0f) ++agree;
  }
  return mesh.indices.empty() ? 1.0 : double(agree) / double(mesh.triangleCount());
}

using vs::testing::base64;
using vs::testing::makeGlb;

template <class T>
void appendRaw(std::vector<unsigned char>& bytes, const std::vector<T>& values) {
  size_t at = bytes.size();
  bytes.resize(at + values.size() * sizeof(T));
  std::memcpy(bytes.data() + at, values.data(), values.size() * sizeof(T));
}

// A one-quad glTF: 4 positions (48 bytes) + 6 uint16 indices (12 bytes) = 60 bytes of buffer.
struct QuadGltf {
  std::vector<unsigned char> buffer;
  QuadGltf() {
    appendRaw(buffer, std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    appendRaw(buffer, std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  }
  // bufferUri: "" for a GLB BIN chunk; lightJson: the KHR_lights_punctual light object or "".
  std::string json(const std::string& bufferUri, const std::string& lightJson, const std::string& nodeTransform,
                   size_t indexCount = 6, int indexAccessor = 1) const {
    std::string uriField = bufferUri.empty() ? "" : "\"uri\": \"" + bufferUri + "\", ";
    std::string lightNode = lightJson.empty() ? ""
                                              : R"(, {"translation": [1, 2, 3], "rotation": [-0.7071068, 0, 0, 0.7071068],
                   "extensions": {"KHR_lights_punctual": {"light": 0}}})";
    std::string lightExtension = lightJson.empty() ? "" : R"(, "extensions": {"KHR_lights_punctual": {"lights": [)" + lightJson + "]}}";
    return R"({"asset": {"version": "2.0"}, "scene": 0,
      "scenes": [{"nodes": [0)" + std::string(lightJson.empty() ? "" : ", 1") + R"(]}],
      "nodes": [{"mesh": 0)" + nodeTransform + "}" + lightNode + R"(],
      "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0}, "indices": )" +
           std::to_string(indexAccessor) + R"(, "material": 0}]}],
      "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.5, 0.75, 1.0]}}],
      "buffers": [{)" + uriField + R"("byteLength": 60}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5123, "count": )" + std::to_string(indexCount) + R"(, "type": "SCALAR"}]
      )" + lightExtension + "}";
  }
  std::string dataUri() const { return "data:application/octet-stream;base64," + base64(buffer); }
};

bool lightInView(const Scene& scene) {
  const vs::Camera& c = scene.camera;
  glm::vec3 forward = glm::normalize(c.target - c.position);
  glm::vec3 toLight = scene.light.type == vs::LightType::Directional ? -scene.light.direction
                                                                     : scene.light.position - c.position;
  toLight = glm::normalize(toLight);
  float angle = glm::degrees(std::acos(glm::clamp(glm::dot(forward, toLight), -1.0f, 1.0f)));
  return angle < 0.5f * c.fovYDeg;  // inside the cone of the vertical field of view
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Valid scenes

TEST(SceneJson, ParsesAllSections) {
  Scene scene = parse(R"({
    "description": "unit test",
    "geometry": [{"generator": "sphere", "params": {"center": [0, 1, 0], "radius": 1, "segments": 16}, "albedo": [0.5, 0.6, 0.7]}],
    "camera": {"position": [0, 2, 6], "target": [0, 1, 0], "up": [0, 2, 0], "fov_y_deg": 45, "near": 0.5, "far": 80},
    "light": {"type": "spot", "position": [0, 5, 0], "target": [0, 0, 0], "color": [1, 0.5, 0.25], "intensity": 100,
              "spot_inner_deg": 10, "spot_outer_deg": 40},
    "medium": {"sigma_s": 0.05, "sigma_a": 0.01, "phase": "hg", "g": 0.3}
  })");
  EXPECT_EQ(scene.name, "test");
  EXPECT_EQ(scene.source, "test.json");
  EXPECT_EQ(scene.description, "unit test");
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.triangleCount(), 2u * 16u * 7u);  // segments 16, rings default 8
  EXPECT_EQ(scene.meshes[0].albedo, glm::vec3(0.5f, 0.6f, 0.7f));
  EXPECT_FLOAT_EQ(scene.camera.fovYDeg, 45.0f);
  EXPECT_FLOAT_EQ(scene.camera.nearZ, 0.5f);
  EXPECT_FLOAT_EQ(scene.camera.farZ, 80.0f);
  EXPECT_EQ(scene.camera.up, glm::vec3(0, 1, 0));
  EXPECT_EQ(scene.light.type, vs::LightType::Spot);
  EXPECT_NEAR(glm::distance(scene.light.direction, glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
  EXPECT_EQ(scene.light.color, glm::vec3(1, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(scene.light.spotInnerDeg, 10.0f);
  EXPECT_FLOAT_EQ(scene.light.spotOuterDeg, 40.0f);
  EXPECT_FALSE(scene.light.hasTexture());
  EXPECT_EQ(scene.medium.phase, vs::Phase::HenyeyGreenstein);
  EXPECT_FLOAT_EQ(scene.medium.sigmaT(), 0.06f);
  EXPECT_FLOAT_EQ(scene.medium.g, 0.3f);
  EXPECT_EQ(scene.droppedTriangles, 0u);
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  EXPECT_NEAR(lo.y, 0.0f, 1e-5f);
  EXPECT_NEAR(hi.y, 2.0f, 1e-5f);
}

TEST(SceneJson, EmptyGeometryAndNoMediumAreLegal) {
  Scene scene = parse(sceneText(""));
  EXPECT_TRUE(scene.meshes.empty());
  EXPECT_EQ(scene.triangleCount(), 0u);
  EXPECT_EQ(scene.medium.sigmaT(), 0.0f);
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  EXPECT_EQ(lo, glm::vec3(-0.5f));
  EXPECT_EQ(hi, glm::vec3(0.5f));
}

TEST(SceneJson, DirectionalLightFromDirectionOrTarget) {
  Scene a = parse(sceneText("", R"("light": {"type": "directional", "direction": [0, -2, 0], "intensity": 3})"));
  EXPECT_EQ(a.light.type, vs::LightType::Directional);
  EXPECT_EQ(a.light.direction, glm::vec3(0, -1, 0));
  Scene b = parse(sceneText("", R"("light": {"type": "directional", "position": [0, 4, 0], "target": [4, 0, 0], "intensity": 3})"));
  EXPECT_NEAR(glm::distance(b.light.direction, glm::normalize(glm::vec3(1, -1, 0))), 0.0f, 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Built-in scenes

TEST(BuiltinScenes, AllLoadWithTheirStatedSizes) {
  std::vector<std::string> names;
  for (const vs::BuiltinSceneInfo& info : vs::builtinScenes()) {
    names.push_back(info.name);
    EXPECT_FALSE(info.description.empty()) << info.name;
    Scene scene = vs::loadScene(info.name);
    EXPECT_EQ(scene.name, info.name);
    EXPECT_EQ(scene.source, "builtin:" + info.name);
    EXPECT_EQ(scene.description, info.description);
    EXPECT_GT(scene.triangleCount(), 0u) << info.name;
    EXPECT_EQ(scene.droppedTriangles, 0u) << info.name;
    EXPECT_GT(scene.medium.sigmaS, 0.0f) << info.name;
    EXPECT_EQ(scene.contentHash.size(), 16u);
    for (const vs::Mesh& mesh : scene.meshes) expectValidMesh(mesh);
  }
  for (const char* expected : {"spheres", "room", "fence", "trees", "terrain"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;

  Scene spheres = vs::loadScene("spheres");
  EXPECT_LE(spheres.triangleCount(), 5000u);
  EXPECT_EQ(spheres.light.type, vs::LightType::Point);
  EXPECT_TRUE(lightInView(spheres)) << "the spheres scene must have its epipole on screen";

  auto start = std::chrono::steady_clock::now();
  Scene room = vs::loadScene("room");
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(room.triangleCount(), 100000u);
  EXPECT_EQ(room.light.type, vs::LightType::Point);
  EXPECT_TRUE(lightInView(room));
  EXPECT_LT(seconds, 2.0);  // about 0.01 s optimised; generous for debug/sanitizer builds

  EXPECT_EQ(vs::loadScene("fence").light.type, vs::LightType::Spot);
  EXPECT_EQ(vs::loadScene("trees").light.type, vs::LightType::Directional);
  EXPECT_EQ(vs::loadScene("terrain").light.type, vs::LightType::Directional);
  // Moving geometry: the room's torus and knot turn, nothing else moves.
  Scene spin = vs::loadScene("roomspin");
  ASSERT_TRUE(spin.animation.movesGeometry());
  EXPECT_FALSE(spin.animation.movesLight() || spin.animation.movesCamera());
  Scene turned = vs::sceneAt(spin, 0.5);
  int moved = 0;
  for (size_t i = 0; i < spin.meshes.size(); ++i) moved += turned.meshes[i].positions != spin.meshes[i].positions;
  EXPECT_EQ(moved, 2);
  // A moving built-in scene: the sun sweeps over the terrain; the epipole enters the screen.
  Scene sweep = vs::loadScene("sunsweep");
  ASSERT_TRUE(sweep.animation.moves());
  EXPECT_TRUE(sweep.animation.movesLight());
  bool inView = false, outOfView = false;
  for (int i = 0; i < sweep.animation.frameCount(); ++i) {
    bool seen = lightInView(vs::sceneAt(sweep, sweep.animation.timeOf(uint32_t(i))));
    inView = inView || seen;
    outOfView = outOfView || !seen;
  }
  EXPECT_TRUE(inView && outOfView) << "the sun must enter and leave the view";
}

TEST(BuiltinScenes, LightIsInsideTheRoom) {
  Scene room = vs::loadScene("room");
  glm::vec3 lo, hi;
  room.bounds(lo, hi);
  EXPECT_TRUE(glm::all(glm::greaterThan(room.light.position, lo)) && glm::all(glm::lessThan(room.light.position, hi)));
}

// ---------------------------------------------------------------------------------------------
// Errors: one line, naming the file and the JSON path

TEST(SceneErrors, UnknownKeys) {
  TempDir dir;
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0, 5, 0], "intensty": 5})")),
                      {"light.intensty", "unknown key", "did you mean 'intensity'"});
  expectErrorMentions(loadError(dir, sceneText("") + "x"), {"malformed JSON"});
  expectErrorMentions(loadError(dir, R"({"geometry": [], "camera": {"position": [0,0,1], "target": [0,0,0]},
                                       "lihgt": {"type": "point", "position": [0,1,0], "intensity": 1}})"),
                      {"lihgt", "unknown key", "did you mean 'light'"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "spot", "position": [0,5,0], "intensity": 5, "directon": [0,-1,0]})")),
                      {"light.directon", "did you mean 'direction'"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "sphere", "params": {"radus": 1}})")),
                      {"geometry[0].params.radus", "did you mean 'radius'"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "spehre"})")),
                      {"geometry[0].generator", "unknown generator", "did you mean 'sphere'"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generater": "sphere"})")), {"geometry[0].generater"});
  expectErrorMentions(loadError(dir, sceneText("", kPointLight, R"("medium": {"sigma_s": 0.1, "sigma_a": 0, "g": 0.5})")),
                      {"medium.g", "hg"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0,5,0], "intensity": 5, "spot_outer_deg": 30})")),
                      {"light.spot_outer_deg", "spot"});
}

TEST(SceneErrors, MissingRequiredKeys) {
  TempDir dir;
  expectErrorMentions(loadError(dir, R"({"geometry": [], "light": {"type": "point", "position": [0,1,0], "intensity": 1}})"),
                      {"camera", "missing required key"});
  expectErrorMentions(loadError(dir, R"({"geometry": [], "camera": {"position": [0,0,1], "target": [0,0,0]}})"),
                      {"light", "missing required key"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0, 5, 0]})")),
                      {"light.intensity", "missing required key"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "spot", "position": [0, 5, 0], "intensity": 1})")),
                      {"light.direction", "missing required key"});
  expectErrorMentions(loadError(dir, sceneText("", kPointLight, R"("medium": {"sigma_s": 0.1})")), {"medium.sigma_a"});
  // A present valid key is never taken for a misspelling of a missing one.
  expectErrorMentions(loadError(dir, sceneText("", kPointLight, R"("medium": {"sigma_a": 0.1})")),
                      {"medium.sigma_s: missing required key"});
}

TEST(SceneErrors, OutOfRangeValues) {
  TempDir dir;
  auto withCamera = [](const std::string& camera) {
    return R"({"geometry": [], "light": {"type": "point", "position": [0,1,0], "intensity": 1}, "camera": )" + camera + "}";
  };
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,0,1], "target": [0,0,0], "fov_y_deg": 180})")),
                      {"camera.fov_y_deg", "(0, 180)", "180"});
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,0,1], "target": [0,0,0], "near": 0})")), {"camera.near"});
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,0,1], "target": [0,0,0], "near": 1, "far": 0.5})")),
                      {"camera.far"});
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,0,1], "target": [0,0,1]})")), {"camera.target"});
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,0,1], "target": [0,0,0], "up": [0,0,1]})")), {"camera.up"});
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,"a",1], "target": [0,0,0]})")),
                      {"camera.position[1]", "expected a number"});
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,1e999,1], "target": [0,0,0]})")),
                      {"number overflow", "line 1"});
  expectErrorMentions(loadError(dir, withCamera(R"({"position": [0,1e39,1], "target": [0,0,0]})")),
                      {"camera.position[1]", "single precision"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0, 5, 0], "intensity": -1})")),
                      {"light.intensity", "[0, 1e+20]"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0, 5, 0], "intensity": 1, "color": [1, -1, 1]})")),
                      {"light.color[1]"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "spot", "position": [0, 5, 0], "direction": [0,-1,0], "intensity": 1, "spot_inner_deg": 40, "spot_outer_deg": 30})")),
                      {"light.spot_inner_deg"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "spot", "position": [0, 5, 0], "direction": [0,-1,0], "intensity": 1, "spot_outer_deg": 90})")),
                      {"light.spot_outer_deg"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "lamp", "position": [0, 5, 0], "intensity": 1})")),
                      {"light.type", "lamp"});
  expectErrorMentions(loadError(dir, sceneText("", kPointLight, R"("medium": {"sigma_s": -0.1, "sigma_a": 0})")), {"medium.sigma_s"});
  expectErrorMentions(loadError(dir, sceneText("", kPointLight, R"("medium": {"sigma_s": 0.1, "sigma_a": 0, "phase": "hg", "g": 1})")),
                      {"medium.g", "(-1, 1)"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "sphere", "params": {"radius": -1}})")),
                      {"geometry[0].params.radius", "> 0"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "sphere", "params": {"segments": 2.5}})")),
                      {"geometry[0].params.segments", "integer"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "sphere", "albedo": [0.5, 0.5, 1.5]})")),
                      {"geometry[0].albedo[2]", "[0, 1]"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "torus", "params": {"major_radius": 1, "minor_radius": 2}})")),
                      {"geometry[0].params.minor_radius"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "room", "params": {"size": [4, 3, 4], "window": {"wall": "+x", "size": [5, 1]}}})")),
                      {"geometry[0].params.window", "inside"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "sphere", "params": {"segments": 8192, "rings": 8192}})")),
                      {"geometry[0].params", "limit"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "forest", "params": {"size": [2, 2], "count": 50, "min_spacing": 1}})")),
                      {"geometry[0].params", "could not place"});
}

TEST(SceneErrors, MalformedJsonHasLineAndColumn) {
  TempDir dir;
  expectErrorMentions(loadError(dir, "{\n  \"geometry\": [,]\n}\n"), {"malformed JSON", "line 2", "column"});
  expectErrorMentions(loadError(dir, ""), {"malformed JSON"});
  expectErrorMentions(loadError(dir, "[1, 2]"), {"top level"});
  expectErrorMentions(loadError(dir, sceneText("", kPointLight, R"("camera": {"position": [0,0,1], "target": [0,0,0]})")),
                      {"camera", "duplicate key"});
}

TEST(SceneErrors, MissingFiles) {
  TempDir dir;
  std::string missing = dir.file("no_such_scene.json");
  try {
    vs::loadScene(missing);
    FAIL() << "expected SceneError";
  } catch (const SceneError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("no_such_scene.json"), std::string::npos) << message;
    EXPECT_NE(message.find("cannot open"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
  EXPECT_THROW(vs::loadScene("not_a_builtin_scene"), SceneError);
  expectErrorMentions(loadError(dir, sceneText(R"({"gltf": "models/missing.gltf"})")),
                      {"geometry[0].gltf", "missing.gltf", "cannot open"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0,5,0], "intensity": 1, "texture": "gobo.png"})")),
                      {"light.texture", "gobo.png"});
}

// ---------------------------------------------------------------------------------------------
// glTF

TEST(Gltf, EmbeddedBufferWithPointLightRoundTrip) {
  TempDir dir;
  QuadGltf quad;
  dir.write("models/quad.gltf", quad.json(quad.dataUri(), R"({"type": "point", "color": [1, 0.5, 0.5], "intensity": 42})",
                                          R"(, "translation": [10, 0, 0])"));
  std::string scenePath =
      dir.write("scene.json", sceneText(R"({"gltf": "models/quad.gltf", "translate": [0, 0, 5], "scale": 2})", ""));
  Scene scene = vs::loadScene(scenePath);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const vs::Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(mesh.albedo, glm::vec3(0.25f, 0.5f, 0.75f));
  expectValidMesh(mesh);
  // Node translation (10, 0, 0), then scale 2, then translate (0, 0, 5).
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  EXPECT_EQ(lo, glm::vec3(20, 0, 5));
  EXPECT_EQ(hi, glm::vec3(22, 2, 5));
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);  // computed, counter-clockwise
  // No "light" in the scene JSON: the glTF light is used, placed by the same transforms.
  EXPECT_EQ(scene.light.type, vs::LightType::Point);
  EXPECT_FLOAT_EQ(scene.light.intensity, 42.0f);
  EXPECT_EQ(scene.light.color, glm::vec3(1, 0.5f, 0.5f));
  EXPECT_NEAR(glm::distance(scene.light.position, glm::vec3(2, 4, 11)), 0.0f, 1e-5f);

  // A light in the scene JSON wins.
  std::string withLight = dir.write("scene_light.json", sceneText(R"({"gltf": "models/quad.gltf"})"));
  EXPECT_FLOAT_EQ(vs::loadScene(withLight).light.intensity, 50.0f);
}

TEST(Gltf, ExternalBinWithSpotLight) {
  TempDir dir;
  QuadGltf quad;
  dir.write("quad.bin", std::string(quad.buffer.begin(), quad.buffer.end()));
  std::string path = dir.write("quad.gltf", quad.json("quad.bin",
                                                      R"({"type": "spot", "intensity": 7, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}})",
                                                      ""));
  vs::ContentHasher hasher;
  vs::GltfContent content = vs::loadGltf(path, glm::mat4(1.0f), &hasher);
  ASSERT_EQ(content.meshes.size(), 1u);
  ASSERT_TRUE(content.hasLight);
  EXPECT_EQ(content.light.type, vs::LightType::Spot);
  EXPECT_NEAR(content.light.spotInnerDeg, 0.2f * 57.29578f, 1e-3f);
  EXPECT_NEAR(content.light.spotOuterDeg, 0.5f * 57.29578f, 1e-3f);
  EXPECT_NEAR(glm::distance(content.light.position, glm::vec3(1, 2, 3)), 0.0f, 1e-6f);
  // The light node is rotated -90 degrees about X, so its -Z axis points down.
  EXPECT_NEAR(glm::distance(content.light.direction, glm::vec3(0, -1, 0)), 0.0f, 1e-5f);
}

TEST(Gltf, BinaryGlb) {
  TempDir dir;
  QuadGltf quad;
  std::vector<unsigned char> glb = makeGlb(quad.json("", "", R"(, "scale": [1, 1, -1])"), quad.buffer);
  std::string path = dir.write("quad.glb", std::string(glb.begin(), glb.end()));
  vs::GltfContent content = vs::loadGltf(path, glm::mat4(1.0f));
  ASSERT_EQ(content.meshes.size(), 1u);
  EXPECT_EQ(content.meshes[0].triangleCount(), 2u);
  EXPECT_FALSE(content.hasLight);
  // The mirroring scale flips the winding, so the computed normals still agree with it.
  EXPECT_EQ(windingAgreement(content.meshes[0]), 1.0);
}

TEST(Gltf, TruncatedOrInconsistentBuffersAreErrors) {
  TempDir dir;
  QuadGltf quad;
  dir.write("short.bin", std::string(quad.buffer.begin(), quad.buffer.begin() + 40));
  std::string truncated = dir.write("truncated.gltf", quad.json("short.bin", "", ""));
  try {
    vs::loadGltf(truncated, glm::mat4(1.0f));
    FAIL() << "expected SceneError";
  } catch (const SceneError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("truncated.gltf"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // Through a scene, the error names both files.
  std::string scenePath = dir.write("broken_scene.json", sceneText(R"({"gltf": "truncated.gltf"})"));
  try {
    vs::loadScene(scenePath);
    FAIL() << "expected SceneError";
  } catch (const SceneError& e) {
    expectErrorMentions(e.what(), {"geometry[0].gltf", "truncated.gltf"});
  }

  dir.write("quad.bin", std::string(quad.buffer.begin(), quad.buffer.end()));
  std::string tooManyIndices = dir.write("count.gltf", quad.json("quad.bin", "", "", 12));
  EXPECT_THROW(vs::loadGltf(tooManyIndices, glm::mat4(1.0f)), SceneError);
  std::string badAccessor = dir.write("accessor.gltf", quad.json("quad.bin", "", "", 6, 7));
  EXPECT_THROW(vs::loadGltf(badAccessor, glm::mat4(1.0f)), SceneError);

  std::vector<unsigned char> badIndexBuffer = quad.buffer;
  badIndexBuffer[48] = 9;  // first index -> vertex 9 of 4
  dir.write("badindex.bin", std::string(badIndexBuffer.begin(), badIndexBuffer.end()));
  std::string badIndex = dir.write("badindex.gltf", quad.json("badindex.bin", "", ""));
  EXPECT_THROW(vs::loadGltf(badIndex, glm::mat4(1.0f)), SceneError);

  std::string malformed = dir.write("malformed.gltf", "{\"asset\": {\"version\": \"2.0\"}, ");
  EXPECT_THROW(vs::loadGltf(malformed, glm::mat4(1.0f)), SceneError);
  std::vector<unsigned char> glb = makeGlb(quad.json("", "", ""), quad.buffer);
  std::string shortGlb = dir.write("short.glb", std::string(glb.begin(), glb.begin() + long(glb.size() / 2)));
  EXPECT_THROW(vs::loadGltf(shortGlb, glm::mat4(1.0f)), SceneError);
  EXPECT_THROW(vs::loadGltf(dir.file("absent.gltf"), glm::mat4(1.0f)), SceneError);
}

// A PNG chunk that declares more bytes than the file holds (found by the glTF fuzzer: a tEXt length
// that made the decoder ask for 2 GB for a 2x2 image) is one line before any decoding.
TEST(Gltf, PngChunkLongerThanTheFileIsAnError) {
  const std::string path = std::string(VS_SOURCE_DIR) + "/tests/fuzz/corpus/gltf/png_chunk_longer_than_file.glb";
  try {
    vs::loadGltf(path, glm::mat4(1.0f));
    FAIL() << "expected SceneError";
  } catch (const SceneError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("corrupt PNG: chunk tEXt declares"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

// ---------------------------------------------------------------------------------------------
// Degenerate input

TEST(Degenerate, NanAndZeroAreaTrianglesAreDropped) {
  Scene scene = parse(sceneText(R"(
    {"generator": "triangle", "params": {"vertices": [[0, 0, 0], [1, 0, 0], ["nan", 1, 0]]}},
    {"generator": "triangle", "params": {"vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}},
    {"generator": "triangle", "params": {"vertices": [[0, 0, 0], ["inf", 0, 0], [0, 1, 0]]}},
    {"generator": "triangle", "params": {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                                         "normals": [[0, 0, 0], ["nan", 0, 0], [0, 0, 5]]}})"));
  EXPECT_EQ(scene.droppedTriangles, 3u);
  ASSERT_EQ(scene.meshes.size(), 1u);  // meshes left without triangles are removed
  const vs::Mesh& mesh = scene.meshes[0];
  expectValidMesh(mesh);
  EXPECT_EQ(mesh.triangleCount(), 1u);
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(glm::distance(n, glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

TEST(Degenerate, SanitizeCompactsVerticesAndDropsBadIndices) {
  vs::Mesh mesh;
  float nan = std::nanf("");
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {nan, 0, 0}, {5, 5, 5}, {1, 1, 0}};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 0}};
  mesh.indices = {0, 1, 2, 0, 3, 2, 1, 2, 2, 0, 1, 42, 1, 5, 2};
  EXPECT_EQ(vs::sanitizeMesh(mesh), 3u);
  expectValidMesh(mesh);
  EXPECT_EQ(mesh.positions.size(), 4u);  // NaN vertex and unused vertex removed
  EXPECT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(mesh.positions[3], glm::vec3(1, 1, 0));
  EXPECT_NEAR(glm::distance(mesh.normals[3], glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Generators

TEST(Generators, EveryGeneratorMakesAValidConsistentlyWoundMesh) {
  for (const std::string& name : vs::generatorNames()) {
    nlohmann::json params = nlohmann::json::object();
    if (name == "triangle") params["vertices"] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    if (name == "forest") params["count"] = 3;
    if (name == "terrain") params["resolution"] = 16;
    std::vector<vs::Mesh> meshes = vs::generateMeshes(name, params, "test", "generator", "params");
    ASSERT_EQ(meshes.size(), 1u) << name;
    vs::Mesh mesh = meshes[0];
    EXPECT_GT(mesh.triangleCount(), 0u) << name;
    EXPECT_EQ(vs::sanitizeMesh(mesh), 0u) << name << " produced degenerate triangles";
    expectValidMesh(mesh);
    EXPECT_GE(windingAgreement(mesh), 0.999) << name;
  }
}

TEST(Generators, NormalsPointOutwardOrIntoTheRoom) {
  auto outwardFraction = [](const vs::Mesh& mesh, glm::vec3 center, float sign) {
    size_t outward = 0;
    for (size_t v = 0; v < mesh.positions.size(); ++v)
      if (sign * glm::dot(mesh.normals[v], mesh.positions[v] - center) > 0.0f) ++outward;
    return double(outward) / double(mesh.positions.size());
  };
  vs::SphereParams sphere;
  sphere.center = {1, 2, 3};
  EXPECT_EQ(outwardFraction(vs::makeSphere(sphere), sphere.center, 1.0f), 1.0);
  vs::BoxParams box;
  box.rotateDeg = {10, 20, 30};
  EXPECT_EQ(outwardFraction(vs::makeBox(box), box.center, 1.0f), 1.0);
  vs::RoomParams room;
  room.hasWindow = true;
  vs::Mesh roomMesh = vs::makeRoom(room);
  EXPECT_EQ(outwardFraction(roomMesh, room.center + glm::vec3(0, 0.5f * room.size.y, 0), -1.0f), 1.0);
  EXPECT_EQ(roomMesh.triangleCount(), 2u * (5 + 4));  // floor, ceiling, 3 walls, window wall in 4 parts
  vs::TorusParams torus;
  vs::Mesh torusMesh = vs::makeTorus(torus);
  for (size_t v = 0; v < torusMesh.positions.size(); ++v) {
    glm::vec3 p = torusMesh.positions[v];
    glm::vec3 ringPoint = torus.majorRadius * glm::normalize(glm::vec3(p.x, 0, p.z));
    EXPECT_GT(glm::dot(torusMesh.normals[v], p - ringPoint), 0.0f);
  }
}

TEST(Generators, SeededGeneratorsAreDeterministic) {
  vs::TreeParams tree;
  tree.seed = 11;
  vs::Mesh a = vs::makeTree(tree), b = vs::makeTree(tree);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.indices, b.indices);
  tree.seed = 12;
  EXPECT_NE(vs::makeTree(tree).positions, a.positions);
  EXPECT_EQ(a.triangleCount(), size_t(1 + 3 + 9 + 27 + 81 + 243) * 5 * 2);

  vs::TerrainParams terrain;
  terrain.resolution = 32;
  EXPECT_EQ(vs::makeTerrain(terrain).positions, vs::makeTerrain(terrain).positions);
  vs::Mesh flat = vs::makeTerrain(terrain);
  terrain.seed = 2;
  EXPECT_NE(vs::makeTerrain(terrain).positions, flat.positions);
  float lowest = 1e9f, highest = -1e9f;
  for (const glm::vec3& p : flat.positions) {
    lowest = std::min(lowest, p.y);
    highest = std::max(highest, p.y);
  }
  EXPECT_GE(lowest, 0.0f);
  EXPECT_LE(highest, terrain.height);
  EXPECT_GT(highest - lowest, 0.1f * terrain.height);
}

TEST(Generators, ForestPlacementStaysTheSameBitForBit) {
  // Trees are placed against a grid of min_spacing cells instead of every tree placed before (which
  // cost n^2): the forest must be exactly what comparing with every tree gave (FNV-1a over the
  // positions' bits and the indices; 400 trees that crowd their 40 x 30 area, so spots are refused).
  vs::ForestParams p;
  p.count = 400;
  p.size = glm::vec2(40.0f, 30.0f);
  p.minSpacing = 1.3f;
  p.seed = 7;
  p.tree.depth = 2;
  vs::Mesh m = vs::makeForest(p);
  uint64_t hash = 1469598103934665603ull;
  for (const glm::vec3& q : m.positions)
    for (int k = 0; k < 3; ++k) {
      uint32_t bits;
      std::memcpy(&bits, &q[k], sizeof bits);
      hash = (hash ^ bits) * 1099511628211ull;
    }
  for (uint32_t i : m.indices) hash = (hash ^ i) * 1099511628211ull;
  EXPECT_EQ(m.triangleCount(), 16000u);
  EXPECT_EQ(hash, 0x8b716bcf51d59178ull);
}

TEST(Generators, FenceWiresAreThin) {
  vs::FenceParams fence;
  fence.frame = false;
  vs::Mesh mesh = vs::makeChainlinkFence(fence);
  float minZ = 1e9f, maxZ = -1e9f;
  for (const glm::vec3& p : mesh.positions) {
    minZ = std::min(minZ, p.z);
    maxZ = std::max(maxZ, p.z);
  }
  EXPECT_LE(maxZ - minZ, 4.0f * fence.wireRadius + 1e-5f);
  EXPECT_GT(mesh.triangleCount(), 12u * 50u);
}

// ---------------------------------------------------------------------------------------------
// Light textures

TEST(LightTexture, SrgbPngIsLinearisedTopRowFirst) {
  TempDir dir;
  std::string png = dir.file("gobo.png");
  {
    auto out = OIIO::ImageOutput::create(png);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::UINT8);
    ASSERT_TRUE(out->open(png, spec));
    const unsigned char pixels[12] = {255, 0, 0, 128, 128, 128, 0, 0, 0, 0, 0, 255};
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels));
    out->close();
  }
  std::string scenePath = dir.write("scene.json", sceneText("", R"("light": {"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0], "intensity": 1, "texture": "gobo.png"})"));
  Scene scene = vs::loadScene(scenePath);
  ASSERT_TRUE(scene.light.hasTexture());
  EXPECT_EQ(scene.light.textureWidth, 2);
  EXPECT_EQ(scene.light.textureHeight, 2);
  EXPECT_EQ(scene.light.texturePath, png);
  const std::vector<float>& rgb = scene.light.textureRGB;
  EXPECT_NEAR(rgb[0], 1.0f, 1e-6f);      // top-left red
  EXPECT_NEAR(rgb[3], 0.21586f, 1e-4f);  // sRGB 128 -> linear
  EXPECT_NEAR(rgb[11], 1.0f, 1e-6f);     // bottom-right blue
}

// ---------------------------------------------------------------------------------------------
// Content hash

TEST(ContentHash, IsFnv1aAndStable) {
  vs::ContentHasher hasher;
  hasher.addBytes("a", 1);
  EXPECT_EQ(hasher.value(), 0xaf63dc4c8601ec8cull);  // published FNV-1a 64 test vector
  EXPECT_EQ(hasher.hex(), "af63dc4c8601ec8c");

  EXPECT_EQ(vs::loadScene("spheres").contentHash, vs::loadScene("spheres").contentHash);
  EXPECT_NE(vs::loadScene("spheres").contentHash, vs::loadScene("fence").contentHash);
  std::string text = sceneText(R"({"generator": "box"})");
  EXPECT_EQ(parse(text).contentHash, parse(text).contentHash);
  EXPECT_NE(parse(text).contentHash, parse(text + " ").contentHash);
}

TEST(ContentHash, CoversReferencedFiles) {
  TempDir dir;
  QuadGltf quad;
  dir.write("quad.bin", std::string(quad.buffer.begin(), quad.buffer.end()));
  dir.write("quad.gltf", quad.json("quad.bin", "", ""));
  std::string scenePath = dir.write("scene.json", sceneText(R"({"gltf": "quad.gltf"})"));
  std::string before = vs::loadScene(scenePath).contentHash;
  EXPECT_EQ(vs::loadScene(scenePath).contentHash, before);
  std::vector<unsigned char> moved = quad.buffer;
  moved[0] = 0x3f;  // change one byte of the first vertex; the file size stays the same
  dir.write("quad.bin", std::string(moved.begin(), moved.end()));
  EXPECT_NE(vs::loadScene(scenePath).contentHash, before);
}

// ---- effects of issue "every effect the papers need": volumes, opacity, area lights

namespace {

std::string volumeScene(const std::string& volume) { return sceneText("", kPointLight, "\"volumes\": [" + volume + "]"); }

std::string rawBytesU16(const std::vector<uint16_t>& values) {
  std::string bytes;
  for (uint16_t v : values) {
    bytes += char(v & 0xff);
    bytes += char(v >> 8);
  }
  return bytes;
}

std::string rawBytesF32(const std::vector<float>& values) {
  std::string bytes(values.size() * 4, '\0');
  std::memcpy(bytes.data(), values.data(), bytes.size());  // this project builds for little-endian hosts
  return bytes;
}

}  // namespace

TEST(Volumes, RawFilesOfEveryTypeLoadLittleEndianWithHeader) {
  TempDir dir;
  dir.write("d.u8", std::string("HDR") + std::string("\x00\xff\x80\x40\x00\x00\x00\xff", 8));
  dir.write("d.u16", rawBytesU16({0, 65535, 32768, 1, 0, 0, 0, 65535}));
  dir.write("d.f32", rawBytesF32({0.0f, 2.5f, 0.5f, 0.25f, 0.0f, 0.0f, 0.0f, 1e4f}));
  const char* box = R"("box_min": [-1, 0, -1], "box_max": [1, 2, 1])";
  Scene u8 = vs::loadScene(dir.write("u8.json", volumeScene(std::string(R"({"raw": "d.u8", "type": "u8", "dims": [2, 2, 2], "header_bytes": 3, )") + box + "}")));
  ASSERT_EQ(u8.volumes.size(), 1u);
  EXPECT_FLOAT_EQ(u8.volumes[0].voxel(1, 0, 0), 1.0f);
  EXPECT_NEAR(u8.volumes[0].voxel(0, 1, 0), 128.0f / 255.0f, 1e-6);
  EXPECT_FLOAT_EQ(u8.volumes[0].voxel(1, 1, 1), 1.0f);
  Scene u16 = vs::loadScene(dir.write("u16.json", volumeScene(std::string(R"({"raw": "d.u16", "type": "u16", "dims": [2, 2, 2], )") + box + "}")));
  EXPECT_FLOAT_EQ(u16.volumes[0].voxel(1, 0, 0), 1.0f);
  EXPECT_NEAR(u16.volumes[0].voxel(0, 1, 0), 32768.0f / 65535.0f, 1e-6);
  Scene f32 = vs::loadScene(dir.write("f32.json", volumeScene(std::string(R"({"raw": "d.f32", "type": "f32", "dims": [2, 2, 2], "density_scale": 2, "sigma_s": 0.5, "sigma_a": 0.25, )") + box + "}")));
  const vs::Volume& v = f32.volumes[0];
  EXPECT_FLOAT_EQ(v.voxel(1, 1, 1), 1e4f);
  EXPECT_FLOAT_EQ(v.densityScale, 2.0f);
  EXPECT_FLOAT_EQ(v.sigmaT().g, 0.75f);
  EXPECT_FALSE(v.chromatic());
  // Trilinear between voxel centres, zero outside the box.
  EXPECT_FLOAT_EQ(v.densityAt(glm::vec3(-0.5f, 0.5f, -0.5f)), 0.0f);
  EXPECT_FLOAT_EQ(v.densityAt(glm::vec3(0.5f, 0.5f, -0.5f)), 2.5f);
  EXPECT_NEAR(v.densityAt(glm::vec3(0.0f, 0.5f, -0.5f)), 1.25f, 1e-6);
  EXPECT_FLOAT_EQ(v.densityAt(glm::vec3(0.0f, 5.0f, 0.0f)), 0.0f);
  // The raw file is part of the content hash.
  dir.write("d.f32", rawBytesF32({0.0f, 2.5f, 0.5f, 0.25f, 0.0f, 0.0f, 0.0f, 1e3f}));
  Scene changed = vs::loadScene(dir.file("f32.json"));
  EXPECT_NE(changed.contentHash, f32.contentHash);
}

TEST(Volumes, CoefficientsAreANumberOrAnRgbTriple) {
  const char* box = R"("density": [1], "dims": [1, 1, 1], "box_min": [-1, 0, -1], "box_max": [1, 2, 1])";
  Scene s = parse(volumeScene(std::string(R"({"sigma_s": [0.5, 1, 2], "sigma_a": 0.25, )") + box + "}"));
  const vs::Volume& v = s.volumes[0];
  EXPECT_FLOAT_EQ(v.sigmaT().r, 0.75f);
  EXPECT_FLOAT_EQ(v.sigmaT().b, 2.25f);
  EXPECT_TRUE(v.chromatic());
  TempDir dir;
  expectErrorMentions(loadError(dir, volumeScene(std::string(R"({"sigma_a": [1, 2], )") + box + "}")), {"sigma_a"});
  expectErrorMentions(loadError(dir, volumeScene(std::string(R"({"sigma_s": [1, -2, 1], )") + box + "}")), {"sigma_s"});
}

TEST(Volumes, GeneratorsMakeTheFourDataSetsAtTheirSizes) {
  struct Expect {
    const char* name;
    int x, y, z;
  };
  for (Expect e : {Expect{"density_box", 64, 64, 64}, Expect{"bucky", 32, 32, 32}, Expect{"rods", 64, 64, 64},
                   Expect{"cloud", 128, 8, 128}}) {
    std::string scale = std::string(e.name) == "cloud" ? ", \"scale\": 0.25" : "";
    Scene s = parse(volumeScene(std::string(R"({"generator": ")") + e.name + "\"" + scale +
                                R"(, "box_min": [-1, 0, -1], "box_max": [1, 2, 1]})"));
    const vs::Volume& v = s.volumes[0];
    EXPECT_EQ(v.dims[0], e.x) << e.name;
    EXPECT_EQ(v.dims[1], e.y) << e.name;
    EXPECT_EQ(v.dims[2], e.z) << e.name;
    float lo = 1e9f, hi = -1e9f;
    for (float d : v.density) {
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    EXPECT_GE(lo, 0.0f) << e.name;
    EXPECT_LE(hi, 1.0f) << e.name;
    EXPECT_GT(hi, 0.5f) << e.name << " has no dense part";
    EXPECT_LT(lo, 0.05f) << e.name << " has no empty part";
  }
  // The density box is densest at its centre and empty at its faces.
  Scene box = parse(volumeScene(R"({"generator": "density_box", "box_min": [-1, -1, -1], "box_max": [1, 1, 1]})"));
  EXPECT_GT(box.volumes[0].densityAt(glm::vec3(0.0f)), 0.95f);
  EXPECT_LT(box.volumes[0].densityAt(glm::vec3(0.99f, 0.0f, 0.0f)), 0.05f);
}

TEST(Volumes, CloudDensitiesStayTheSameBitForBit) {
  // Results and caches depend on the cloud's densities: its table-driven noise must give exactly
  // what evaluating the value noise per sample gave (FNV-1a over every voxel's bits).
  Scene s = parse(volumeScene(R"({"generator": "cloud", "scale": 0.25, "seed": 3, "box_min": [-1, 0, -1], "box_max": [1, 2, 1]})"));
  const vs::Volume& v = s.volumes[0];
  ASSERT_EQ(v.density.size(), size_t(128 * 8 * 128));
  uint64_t hash = 1469598103934665603ull;
  for (float d : v.density) {
    uint32_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    hash = (hash ^ bits) * 1099511628211ull;
  }
  EXPECT_EQ(hash, 0x1253b6c75d1a6e3bull);
}

TEST(Volumes, GridsMadeAgainAreTheSameAndKeyedBySeedAndScale) {
  // generateVolume keeps the last grids it made: a second scene gets the same grid, a change of
  // seed or scale a different one.
  auto cloud = [&](const char* extra) {
    return parse(volumeScene(std::string(R"({"generator": "cloud", )") + extra +
                             R"(, "box_min": [-1, 0, -1], "box_max": [1, 2, 1]})"))
        .volumes[0];
  };
  vs::Volume a = cloud(R"("scale": 0.25, "seed": 3)"), again = cloud(R"("scale": 0.25, "seed": 3)");
  vs::Volume seed = cloud(R"("scale": 0.25, "seed": 4)"), scale = cloud(R"("scale": 0.125, "seed": 3)");
  EXPECT_EQ(a.density, again.density);
  EXPECT_EQ(again.dims[0], 128);
  EXPECT_NE(a.density, seed.density);
  EXPECT_EQ(scale.dims[0], 64);
  EXPECT_EQ(scale.density.size(), size_t(64 * 4 * 64));
}

TEST(Volumes, BadRawFilesAndKeysAreOneLineErrors) {
  TempDir dir;
  dir.write("eight.u8", std::string(8, '\x10'));
  dir.write("nan.f32", rawBytesF32({0.0f, std::nanf(""), 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}));
  dir.write("neg.f32", rawBytesF32({0.0f, -1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}));
  const std::string box = R"("box_min": [0, 0, 0], "box_max": [1, 1, 1])";
  auto raw = [&](const std::string& keys) { return volumeScene("{" + keys + ", " + box + "}"); };
  expectErrorMentions(loadError(dir, raw(R"("raw": "eight.u8", "type": "u8", "dims": [2, 2, 1])")),
                      {"volumes[0].raw", "8 bytes", "need 4"});
  expectErrorMentions(loadError(dir, raw(R"("raw": "eight.u8", "type": "u8", "dims": [2, 2, 4])")),
                      {"volumes[0].raw", "8 bytes", "need 16"});
  expectErrorMentions(loadError(dir, raw(R"("raw": "eight.u8", "type": "u12", "dims": [2, 2, 2])")), {"volumes[0].type", "u12"});
  expectErrorMentions(loadError(dir, raw(R"("raw": "eight.u8", "type": "u8", "dims": [0, 2, 2])")), {"volumes[0].dims[0]"});
  expectErrorMentions(loadError(dir, raw(R"("raw": "eight.u8", "type": "u8", "dims": [2, 2, 4096])")), {"volumes[0].dims[2]"});
  expectErrorMentions(loadError(dir, raw(R"("raw": "nan.f32", "type": "f32", "dims": [2, 2, 2])")), {"voxel 1", "nan"});
  expectErrorMentions(loadError(dir, raw(R"("raw": "neg.f32", "type": "f32", "dims": [2, 2, 2])")), {"voxel 1", "-1"});
  expectErrorMentions(loadError(dir, raw(R"("raw": "missing.u8", "type": "u8", "dims": [2, 2, 2])")), {"missing.u8"});
  expectErrorMentions(loadError(dir, volumeScene(R"({"generator": "cloud", "box_min": [0, 0, 0], "box_max": [1, 0, 1]})")),
                      {"volumes[0].box_max"});
  expectErrorMentions(loadError(dir, volumeScene(R"({"generator": "smoke", "box_min": [0, 0, 0], "box_max": [1, 1, 1]})")),
                      {"volumes[0].generator", "smoke"});
}

TEST(SemiTransparent, OpacityAndTransmittanceColourAreReadAndRanged) {
  Scene s = parse(sceneText(R"({"generator": "plane", "opacity": 0.5, "transmittance_color": [0.2, 0.8, 0.2]}, {"generator": "box"})"));
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_FLOAT_EQ(s.meshes[0].opacity, 0.5f);
  EXPECT_FALSE(s.meshes[0].isOpaque());
  EXPECT_TRUE(s.meshes[0].hasTransmittanceColor());
  EXPECT_NEAR(s.meshes[0].crossingTransmittance().g, 0.9f, 1e-6);
  EXPECT_NEAR(s.meshes[0].crossingTransmittance().r, 0.6f, 1e-6);
  EXPECT_TRUE(s.meshes[1].isOpaque());
  TempDir dir;
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "plane", "opacity": 1.5})")), {"geometry[0].opacity", "[0, 1]"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "plane", "opacity": -0.1})")), {"geometry[0].opacity"});
}

TEST(AreaLights, RectAndDiskAreReadWithUnitsAndSampled) {
  Scene rect = parse(sceneText("", R"("light": {"type": "rect", "position": [0, 4, 0], "direction": [0, -1, 0], "width": 2, "height": 0.5, "tangent": [1, 0, 0.5], "intensity": 3})"));
  const vs::Light& l = rect.light;
  EXPECT_EQ(l.type, vs::LightType::Rect);
  EXPECT_FLOAT_EQ(l.area(), 1.0f);
  EXPECT_NEAR(glm::dot(l.tangent, l.direction), 0.0f, 1e-6);
  EXPECT_NEAR(glm::length(l.tangent), 1.0f, 1e-6);
  for (float u : {0.0f, 0.25f, 0.999f})
    for (float v : {0.0f, 0.5f, 0.999f}) {
      glm::vec3 p = l.samplePoint(u, v);
      EXPECT_NEAR(p.y, 4.0f, 1e-5);
      EXPECT_LE(std::fabs(glm::dot(p - l.position, l.tangent)), 1.0f + 1e-5f);
    }
  Scene disk = parse(sceneText("", R"("light": {"type": "disk", "position": [0, 4, 0], "target": [0, 0, 0], "radius": 0.5, "intensity": 3, "two_sided": true})"));
  EXPECT_NEAR(disk.light.area(), 0.785398f, 1e-5);
  EXPECT_TRUE(disk.light.twoSided);
  for (float u : {0.0f, 0.3f, 0.999f})
    for (float v : {0.01f, 0.5f, 0.999f}) EXPECT_LE(glm::length(disk.light.samplePoint(u, v) - disk.light.position), 0.5f + 1e-5f);
  TempDir dir;
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "rect", "position": [0, 4, 0], "direction": [0, -1, 0], "width": 0, "height": 1, "intensity": 1})")),
                      {"light.width", "> 0"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "disk", "position": [0, 4, 0], "direction": [0, -1, 0], "radius": -1, "intensity": 1})")),
                      {"light.radius"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "disk", "position": [0, 4, 0], "direction": [0, -1, 0], "radius": 1, "width": 1, "intensity": 1})")),
                      {"light.width"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0, 4, 0], "radius": 1, "intensity": 1})")),
                      {"light.radius", "area"});
  // Power instead of radiance: a one-sided Lambertian emitter of area A radiates pi L A.
  Scene byPower = parse(sceneText("", R"("light": {"type": "rect", "position": [0, 4, 0], "direction": [0, -1, 0], "width": 2, "height": 0.5, "power": 31.4159265})"));
  EXPECT_NEAR(byPower.light.intensity, 10.0f, 1e-4);
  Scene twoSided = parse(sceneText("", R"("light": {"type": "rect", "position": [0, 4, 0], "direction": [0, -1, 0], "width": 2, "height": 0.5, "power": 31.4159265, "two_sided": true})"));
  EXPECT_NEAR(twoSided.light.intensity, 5.0f, 1e-4);
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "rect", "position": [0, 4, 0], "direction": [0, -1, 0], "width": 1, "height": 1, "power": 1, "intensity": 1})")),
                      {"light.power", "not both"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0, 4, 0], "power": 1, "intensity": 1})")),
                      {"light.power"});
}

TEST(SceneErrors, ValuesThatCannotRenderFiniteAreRejected) {
  TempDir dir;
  expectErrorMentions(loadError(dir, R"({"geometry": [], "light": {"type": "point", "position": [0,1,0], "intensity": 1},
                                          "camera": {"position": [0,0,1], "target": [0,0,0], "near": 1e-30, "far": 1e30}})"),
                      {"camera.far", "1e9"});
  expectErrorMentions(loadError(dir, sceneText("", R"("light": {"type": "point", "position": [0, 4, 0], "intensity": 1e30})")),
                      {"light.intensity"});
  expectErrorMentions(loadError(dir, sceneText("", kPointLight, R"("medium": {"sigma_s": 1e30, "sigma_a": 0})")),
                      {"medium.sigma_s"});
}

TEST(Gltf, BlendAndMaskMaterialsTakeTheirAlphaFromTheTexture) {
  TempDir dir;
  // 2x1 texture: alpha 0.25 on the left, 1 on the right.
  std::string blend = vs::testing::writeAlphaQuadGltf(dir.file(""), "blend", "BLEND", 0.0, 2, 1, {0.25f, 1.0f}, 2.0, 1.0);
  std::string mask = vs::testing::writeAlphaQuadGltf(dir.file(""), "mask", "MASK", 0.5, 2, 1, {0.25f, 1.0f}, 2.0, 1.0);
  Scene s = parse(sceneText(R"({"gltf": ")" + blend + R"("}, {"gltf": ")" + mask + R"("})"));
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.alphaTextures.size(), 2u);
  const vs::Mesh& b = s.meshes[0];
  ASSERT_EQ(b.alphaTexture, 0);
  ASSERT_EQ(b.uvs.size(), b.positions.size());
  EXPECT_FALSE(b.isOpaque());
  EXPECT_LT(b.alphaCutoff, 0.0f);
  const vs::AlphaTexture& t = s.alphaTextures[0];
  EXPECT_NEAR(t.sample({0.25f, 0.5f}), 0.25f, 2e-3);   // left texel centre
  EXPECT_NEAR(t.sample({0.75f, 0.5f}), 1.0f, 2e-3);    // right texel centre
  EXPECT_NEAR(t.sample({0.5f, 0.5f}), 0.625f, 2e-3);   // halfway: bilinear
  EXPECT_NEAR(t.sample({1.25f, 0.5f}), 0.25f, 2e-3);   // repeats
  EXPECT_NEAR(b.opacityAt(0.25f), 0.25f, 1e-6);
  const vs::Mesh& m = s.meshes[1];
  EXPECT_EQ(m.alphaTexture, 1);
  EXPECT_FLOAT_EQ(m.alphaCutoff, 0.5f);
  EXPECT_EQ(m.opacityAt(0.25f), 0.0f);  // cut out
  EXPECT_EQ(m.opacityAt(0.75f), 1.0f);  // opaque
  // The texture is part of the content hash.
  std::string before = s.contentHash;
  vs::testing::writeAlphaQuadGltf(dir.file(""), "blend", "BLEND", 0.0, 2, 1, {0.5f, 1.0f}, 2.0, 1.0);
  EXPECT_NE(parse(sceneText(R"({"gltf": ")" + blend + R"("}, {"gltf": ")" + mask + R"("})")).contentHash, before);
  // A texture that cannot be decoded is a one-line error naming the image.
  dir.write("blend.png", "not a png");
  expectErrorMentions(loadError(dir, sceneText(R"({"gltf": ")" + blend + R"("})")), {"image 0", "blend.png"});
  // An OPAQUE material's base colour does not change visibility: never decoded, so a broken or
  // missing image is no error.
  std::string opaque = vs::testing::writeAlphaQuadGltf(dir.file(""), "opaque", "OPAQUE", 0.0, 2, 1, {0.25f, 1.0f}, 2.0, 1.0);
  dir.write("opaque.png", "not a png");
  Scene o = parse(sceneText(R"({"gltf": ")" + opaque + R"("})"));
  ASSERT_EQ(o.meshes.size(), 1u);
  EXPECT_TRUE(o.meshes[0].isOpaque());
  EXPECT_TRUE(o.alphaTextures.empty());
  fs::remove(dir.file("opaque.png"));
  EXPECT_EQ(loadError(dir, sceneText(R"({"gltf": ")" + opaque + R"("})")), "");
}

// The same alpha texture in every form a downloaded asset uses: a file, a data: URI, a buffer view
// of a base64 buffer, and a buffer view of a .glb. One decoder path: every form gives the same
// alpha, and a broken embedded image is one line naming the image.
TEST(Gltf, EmbeddedImagesDecodeLikeImageFiles) {
  TempDir dir;
  const std::vector<float> alpha = {0.25f, 1.0f, 0.5f, 0.0f};
  std::string fileGltf = vs::testing::writeAlphaQuadGltf(dir.file(""), "file", "BLEND", 0.0, 2, 2, alpha, 2.0, 1.0);
  const Scene reference = parse(sceneText(R"({"gltf": ")" + fileGltf + R"("})"));
  ASSERT_EQ(reference.alphaTextures.size(), 1u);
  for (const char* form : {"data-uri", "buffer-view", "glb"}) {
    std::string path = vs::testing::writeAlphaQuadGltf(dir.file(""), form, "BLEND", 0.0, 2, 2, alpha, 2.0, 1.0, form);
    EXPECT_FALSE(fs::exists(dir.file(std::string(form) + ".png")));
    Scene s = parse(sceneText(R"({"gltf": ")" + path + R"("})"));
    ASSERT_EQ(s.alphaTextures.size(), 1u) << form;
    EXPECT_EQ(s.alphaTextures[0].alpha, reference.alphaTextures[0].alpha) << form;
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].alphaTexture, 0);
    EXPECT_EQ(s.meshes[0].uvs, reference.meshes[0].uvs) << form;
  }
  // A .glb whose embedded PNG is corrupt: one line naming the image.
  std::string glb = vs::testing::writeAlphaQuadGltf(dir.file(""), "broken", "BLEND", 0.0, 2, 2, alpha, 2.0, 1.0, "glb");
  std::string bytes;
  {
    std::ifstream in(glb, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  size_t png = bytes.find("\x89PNG");
  ASSERT_NE(png, std::string::npos);
  for (size_t i = png + 16; i < bytes.size(); ++i) bytes[i] = 'x';  // past the signature and IHDR length
  dir.write("broken.glb", bytes);
  expectErrorMentions(loadError(dir, sceneText(R"({"gltf": "broken.glb"})")), {"image 0", "corrupt PNG"});
  // An image's buffer view that runs past the end of its buffer: an error, never a read past it.
  {
    std::string glbPath = vs::testing::writeAlphaQuadGltf(dir.file(""), "long", "BLEND", 0.0, 2, 2, alpha, 2.0, 1.0, "glb");
    std::ifstream in(glbPath, std::ios::binary);
    std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, file.data() + 12, 4);
    nlohmann::json doc = nlohmann::json::parse(file.substr(20, jsonLength));
    std::vector<unsigned char> bin(file.begin() + 20 + jsonLength + 8, file.end());
    doc["bufferViews"][3]["byteLength"] = 1 << 20;
    std::vector<unsigned char> glb = makeGlb(doc.dump(), bin);
    dir.write("long.glb", std::string(glb.begin(), glb.end()));
    std::string message = loadError(dir, sceneText(R"({"gltf": "long.glb"})"));
    EXPECT_FALSE(message.empty());
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // An image in no format the loader reads.
  std::string notImage = vs::testing::writeAlphaQuadGltf(dir.file(""), "odd", "BLEND", 0.0, 2, 2, alpha, 2.0, 1.0);
  dir.write("odd.png", "GIF89a, not a png");
  expectErrorMentions(loadError(dir, sceneText(R"({"gltf": "odd.gltf"})")), {"image 0 ('odd.png')"});
  (void)notImage;
}

TEST(Obj, MeshesPerMaterialWithKdAndDissolve) {
  TempDir dir;
  dir.write("box.mtl", "newmtl red\nKd 0.9 0.1 0.1\nnewmtl glass\nKd 0.2 0.3 0.4\nd 0.25\nnewmtl leaf\nKd 0.1 0.8 0.1\nTr 0.6\n");
  dir.write("box.obj",
            "# a quad in two materials and a triangle\nmtllib box.mtl\no thing\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n"
            "usemtl red\nf 1//1 2//1 3//1 4//1\n"
            "usemtl glass\nf -4 -3 -2\n"
            "usemtl leaf\nf 1/1 2/1 4/1\n");
  const std::string entry = R"({"obj": ")" + dir.file("box.obj") + R"(", "translate": [0, 2, 0], "scale": 2})";
  Scene s = parse(sceneText(entry));
  ASSERT_EQ(s.meshes.size(), 3u);
  const vs::Mesh& red = s.meshes[0];
  EXPECT_EQ(red.triangleCount(), 2u);  // the quad, triangulated
  EXPECT_NEAR(red.albedo.r, 0.9f, 1e-6);
  EXPECT_TRUE(red.isOpaque());
  EXPECT_NEAR(red.positions[2].y, 4.0f, 1e-6);  // (1, 1, 0) scaled by 2, moved up by 2
  EXPECT_NEAR(glm::length(red.normals[0] - glm::vec3(0, 0, 1)), 0.0f, 1e-6);
  EXPECT_FLOAT_EQ(s.meshes[1].opacity, 0.25f);
  EXPECT_NEAR(s.meshes[2].opacity, 0.4f, 1e-6);  // Tr 0.6
  std::string hash = s.contentHash;
  dir.write("box.mtl", "newmtl red\nKd 0.5 0.1 0.1\nnewmtl glass\nKd 0.2 0.3 0.4\nd 0.25\nnewmtl leaf\nKd 0.1 0.8 0.1\nTr 0.6\n");
  EXPECT_NE(parse(sceneText(entry)).contentHash, hash);  // the MTL file is part of the hash
}

// Downloaded OBJs often come without their MTL (the widely mirrored Sibenik cathedral names
// untitled.mtl and ships none): in-scattering does not depend on albedo, so the scene loads with
// one warning per missing library or material, naming the file and line.
TEST(Obj, AMissingMaterialLibraryOrMaterialIsAWarningNotAnError) {
  TempDir dir;
  dir.write("room.mtl", "newmtl wall\nKd 0.5 0.5 0.5\n");
  dir.write("nave.obj",
            "mtllib untitled.mtl\nmtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
            "usemtl wall\nf 1 2 3\nusemtl stone\nf 2 4 3\nusemtl stone\nf 1 3 4\n");
  Scene s = parse(sceneText(R"({"obj": ")" + dir.file("nave.obj") + R"("})"));
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("nave.obj:1: material library"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("untitled.mtl"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[1].find("nave.obj:9: material 'stone'"), std::string::npos) << s.warnings[1];  // once
  for (const std::string& w : s.warnings) EXPECT_EQ(w.find('\n'), std::string::npos);
  ASSERT_EQ(s.meshes.size(), 2u);
  float wall = -1.0f, stone = -1.0f;
  for (const vs::Mesh& m : s.meshes) {
    EXPECT_TRUE(m.isOpaque()) << m.name;
    (m.name.find("wall") != std::string::npos ? wall : stone) = m.albedo.r;
  }
  EXPECT_FLOAT_EQ(wall, 0.5f);
  EXPECT_FLOAT_EQ(stone, vs::Mesh().albedo.r);  // the default albedo
  // A complete OBJ warns about nothing.
  dir.write("plain.obj", "mtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl wall\nf 1 2 3\n");
  EXPECT_TRUE(parse(sceneText(R"({"obj": ")" + dir.file("plain.obj") + R"("})")).warnings.empty());
}

// tinyobjloader reads a material value that is not a number as 0: an unreadable `d` would make an
// invisible surface and an unreadable `Kd` a black one. Such a line is an error naming the MTL
// file and line, like a malformed OBJ line.
TEST(Obj, MaterialValuesThatAreNotNumbersAreErrorsWithTheirLine) {
  TempDir dir;
  dir.write("glass.obj", "mtllib glass.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glass\nf 1 2 3\n");
  auto mtlError = [&](const std::string& mtl) {
    dir.write("glass.mtl", mtl);
    return loadError(dir, sceneText(R"({"obj": "glass.obj"})"));
  };
  expectErrorMentions(mtlError("newmtl glass\nKd 0.2 0.3 0.4\nd abc\n"),
                      {"geometry[0].obj", "glass.mtl:3", "dissolve 'd'", "'abc' is not a finite number"});
  expectErrorMentions(mtlError("newmtl glass\nTr 0,5\n"), {"glass.mtl:2", "transparency 'Tr'", "'0,5'"});
  expectErrorMentions(mtlError("# colour\nnewmtl glass\nKd 0.2 grey 0.4\n"), {"glass.mtl:3", "'Kd'", "'grey'"});
  expectErrorMentions(mtlError("newmtl glass\nd\n"), {"glass.mtl:2", "needs 1 number, got 0"});
  expectErrorMentions(mtlError("newmtl glass\nd 1e999\n"), {"glass.mtl:2", "'1e999'"});
  expectErrorMentions(mtlError("newmtl glass\nKd 0.5\n"), {"glass.mtl:2", "needs 3 numbers, got 1"});
  // Readable values load as before, comments and other statements left alone.
  dir.write("glass.mtl", "# the pane\nnewmtl glass\nKd 0.2 0.3 0.4\nd 0.25 # mostly clear\nillum 2\nmap_Kd glass.png\n");
  Scene s = parse(sceneText(R"({"obj": ")" + dir.file("glass.obj") + R"("})"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_FLOAT_EQ(s.meshes[0].opacity, 0.25f);
  EXPECT_FLOAT_EQ(s.meshes[0].albedo.g, 0.3f);
}

// Vertices are shared within a mesh by (position, normal): a position used with two normals is two
// vertices, and a position used by two materials is a vertex in each of their meshes.
TEST(Obj, VerticesAreSharedPerMeshAndNormal) {
  TempDir dir;
  dir.write("m.mtl", "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 1 0\n");
  dir.write("m.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 0.6 0.8\n"
            "usemtl a\nf 1//1 2//1 3//1\nf 2//1 4//1 3//1\nf 1//2 2//2 3//2\n"
            "usemtl b\nf 2//1 4//1 3//1\nusemtl a\nf 3//1 2//1 4//1\n");
  Scene s = parse(sceneText(R"({"obj": ")" + dir.file("m.obj") + R"("})"));
  ASSERT_EQ(s.meshes.size(), 2u);
  const vs::Mesh& a = s.meshes[0].name.find("/a") != std::string::npos ? s.meshes[0] : s.meshes[1];
  const vs::Mesh& b = &a == &s.meshes[0] ? s.meshes[1] : s.meshes[0];
  EXPECT_EQ(a.triangleCount(), 4u);
  EXPECT_EQ(a.positions.size(), 7u);  // 4 positions with normal 1, 3 with normal 2
  EXPECT_EQ(a.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 4, 5, 6, 2, 1, 3}));
  EXPECT_EQ(b.triangleCount(), 1u);
  EXPECT_EQ(b.positions.size(), 3u);
  EXPECT_EQ(b.indices, (std::vector<uint32_t>{0, 1, 2}));
}

// A long load says how it is going: every stage of an OBJ and a glTF file and the cleaning, with
// fractions in [0, 1] that never go back within a stage; the scene's sizes are what it holds.
TEST(Loading, ReportsItsStagesAndTheScenesSize) {
  TempDir dir;
  std::string obj = "mtllib none.mtl\n";
  const int n = 300;  // 2 n^2 = 180,000 triangles: past the reporting stride of every stage
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) obj += "v " + std::to_string(i) + " 0 " + std::to_string(j) + "\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      int a = j * (n + 1) + i + 1, c = a + n + 1;
      obj += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(a + 1) + "\nf " +
             std::to_string(a + 1) + " " + std::to_string(c) + " " + std::to_string(c + 1) + "\n";
    }
  dir.write("grid.obj", obj);
  std::string gltf = vs::testing::writeAlphaQuadGltf(dir.file(""), "quad", "BLEND", 0.0, 2, 1, {0.25f, 1.0f}, 2.0, 1.0, "glb");
  std::string path = dir.write("big.json", sceneText(R"({"obj": "grid.obj"}, {"gltf": ")" + gltf + R"("})"));
  std::vector<std::pair<std::string, double>> calls;
  Scene s = vs::loadScene(path, [&](const std::string& stage, double fraction) { calls.emplace_back(stage, fraction); });
  std::vector<std::string> stages;
  for (size_t i = 0; i < calls.size(); ++i) {
    EXPECT_GE(calls[i].second, 0.0);
    EXPECT_LE(calls[i].second, 1.0);
    if (stages.empty() || stages.back() != calls[i].first) stages.push_back(calls[i].first);
    else EXPECT_GE(calls[i].second, calls[i - 1].second) << calls[i].first;
  }
  EXPECT_EQ(stages, (std::vector<std::string>{"grid.obj: checking", "grid.obj: parsing", "grid.obj: building meshes",
                                              "quad.glb: parsing", "quad.glb: reading meshes", "cleaning meshes"}));
  EXPECT_GT(calls.size(), 10u);
  EXPECT_EQ(s.triangleCount(), size_t(2 * n * n + 2));
  EXPECT_EQ(s.vertexCount(), size_t((n + 1) * (n + 1) + 4));
  // Positions and normals (12 bytes each), indices (4), the quad's uvs (8) and its 2x1 alpha texture.
  EXPECT_EQ(s.dataBytes(), s.vertexCount() * 24 + s.triangleCount() * 12 + 4 * 8 + 2 * 4);
  EXPECT_EQ(vs::loadScene(path).triangleCount(), s.triangleCount());  // without a listener
}

TEST(Obj, MalformedLinesAndMissingFilesAreOneLineErrorsWithLineNumbers) {
  TempDir dir;
  auto objError = [&](const std::string& text) {
    dir.write("bad.obj", text);
    return loadError(dir, sceneText(R"({"obj": "bad.obj"})"));
  };
  expectErrorMentions(objError("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"), {"geometry[0].obj", "bad.obj:2", "'v'", "got 2"});
  expectErrorMentions(objError("v 0 0 0\nv 1 zero 0\n"), {"bad.obj:2", "'zero'"});
  expectErrorMentions(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"), {"bad.obj:4", "index 4 out of range"});
  expectErrorMentions(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"), {"bad.obj:4", "at least 3"});
  expectErrorMentions(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n"), {"bad.obj:4", "1/x"});
  expectErrorMentions(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2 3\n"), {"bad.obj:4", "normal index 2"});
  expectErrorMentions(loadError(dir, sceneText(R"({"obj": "nowhere.obj"})")), {"nowhere.obj"});
  expectErrorMentions(loadError(dir, sceneText(R"({"obj": "bad.obj", "albedo": [1, 1, 1]})")), {"geometry[0].albedo"});
}

namespace {

std::string movingScene(const std::string& animation, const std::string& light = kPointLight) {
  return sceneText(R"({"generator": "sphere", "params": {"center": [0, 1, 0], "radius": 0.5}})", light,
                   "\"animation\": " + animation);
}

}  // namespace

TEST(Animation, TracksInterpolateLinearStepAndCatmullRomThroughTheirKeys) {
  vs::Track<float> track;
  track.times = {0.0f, 1.0f, 3.0f};
  track.values = {0.0f, 2.0f, 4.0f};
  track.mode = vs::Interpolation::Linear;
  EXPECT_FLOAT_EQ(track.at(-1.0), 0.0f);  // before the first key: its value
  EXPECT_FLOAT_EQ(track.at(0.5), 1.0f);
  EXPECT_FLOAT_EQ(track.at(2.0), 3.0f);
  EXPECT_FLOAT_EQ(track.at(9.0), 4.0f);  // after the last key: its value
  track.mode = vs::Interpolation::Step;
  EXPECT_FLOAT_EQ(track.at(0.99), 0.0f);
  EXPECT_FLOAT_EQ(track.at(1.0), 2.0f);
  EXPECT_FLOAT_EQ(track.at(2.9), 2.0f);
  track.mode = vs::Interpolation::CatmullRom;
  for (size_t k = 0; k < track.times.size(); ++k) EXPECT_NEAR(track.at(track.times[k]), track.values[k], 1e-6);
  // C1 at the middle key: the slopes on both sides agree.
  const double h = 1e-3;
  double left = (track.at(1.0) - track.at(1.0 - h)) / h, right = (track.at(1.0 + h) - track.at(1.0)) / h;
  EXPECT_NEAR(left, right, 1e-2);
  // Collinear keys stay on their line.
  vs::Track<glm::vec3> line;
  line.times = {0.0f, 1.0f, 2.0f};
  line.values = {glm::vec3(0), glm::vec3(1, 2, 3), glm::vec3(2, 4, 6)};
  line.mode = vs::Interpolation::CatmullRom;
  glm::vec3 mid = line.at(0.5);
  EXPECT_NEAR(mid.x, 0.5f, 1e-5f);
  EXPECT_NEAR(mid.y, 1.0f, 1e-5f);
  EXPECT_NEAR(mid.z, 1.5f, 1e-5f);
}

TEST(Animation, FrameTimesArePureFunctionsOfTheFrameIndexAndLoop) {
  Scene scene = parse(movingScene(R"({"duration": 1, "fps": 4,
    "light": {"position": {"times": [0, 1], "values": [[0, 5, 0], [4, 5, 0]]}}})"));
  const vs::Animation& a = scene.animation;
  ASSERT_TRUE(a.moves());
  EXPECT_TRUE(a.movesLight());
  EXPECT_FALSE(a.movesCamera());
  EXPECT_EQ(a.frameCount(), 5);  // t = 0, 0.25, 0.5, 0.75, 1
  EXPECT_DOUBLE_EQ(a.timeOf(2), 0.5);
  EXPECT_DOUBLE_EQ(a.timeOf(4), 1.0);
  EXPECT_DOUBLE_EQ(a.timeOf(5), 0.0);  // the sequence loops
  EXPECT_NE(a.describe().find("light position"), std::string::npos) << a.describe();

  Scene atHalf = vs::sceneAt(scene, 0.5);
  EXPECT_FALSE(atHalf.animation.moves());
  EXPECT_NEAR(atHalf.light.position.x, 2.0f, 1e-6f);
  EXPECT_NE(atHalf.contentHash, scene.contentHash);
  EXPECT_NE(atHalf.contentHash, vs::sceneAt(scene, 0.25).contentHash);
  EXPECT_EQ(atHalf.contentHash, vs::sceneAt(scene, 0.5).contentHash);
  // A still scene is its own state at any time.
  Scene still = parse(sceneText(""));
  EXPECT_FALSE(still.animation.moves());
  EXPECT_EQ(vs::sceneAt(still, 3.0).contentHash, still.contentHash);
}

TEST(Animation, DirectionsStayUnitAndCameraTracksMoveTheCamera) {
  Scene scene = parse(movingScene(R"({"duration": 2,
    "camera": {"position": {"times": [0, 2], "values": [[0, 2, 6], [6, 2, 0]], "interpolation": "catmull-rom"},
               "fov_y_deg": {"times": [0, 2], "values": [40, 80], "interpolation": "step"}},
    "light": {"direction": {"times": [0, 2], "values": [[0, -1, 0], [1, -1, 0]]}}})",
                                  R"("light": {"type": "directional", "direction": [0, -1, 0], "intensity": 2})"));
  Scene mid = vs::sceneAt(scene, 1.0);
  EXPECT_NEAR(glm::length(mid.light.direction), 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(mid.camera.fovYDeg, 40.0f);
  EXPECT_FLOAT_EQ(vs::sceneAt(scene, 2.0).camera.fovYDeg, 80.0f);
  EXPECT_NEAR(vs::sceneAt(scene, 2.0).camera.position.x, 6.0f, 1e-5f);
}

TEST(Animation, BadTracksAreOneLineErrors) {
  TempDir dir;
  const std::string position = R"("position": {"times": [0, 1], "values": [[0, 5, 0], [1, 5, 0]]})";
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {"position": {"times": [0.5, 0.5], "values": [[0,5,0],[1,5,0]]}}})")),
                      {"animation.light.position.times[1]", "increase strictly"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {"position": {"times": [], "values": []}}})")),
                      {"animation.light.position.times", "at least one key"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {"position": {"times": [0, 1], "values": [[0,5,0]]}}})")),
                      {"animation.light.position.values", "1 values for 2 key times"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {"position": {"times": [0, 2], "values": [[0,5,0],[1,5,0]]}}})")),
                      {"animation.light.position.times[1]"});  // past the duration
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {)" + position + R"(, "interpolation": "cubic"}})")),
                      {"animation.light"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {"position": {"times": [0], "values": [[0,5,0]], "interpolation": "cubic"}}})")),
                      {"animation.light.position.interpolation", "catmull-rom"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "lihgt": {)" + position + "}}")),
                      {"animation.lihgt", "light"});  // unknown key, with the likely one
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1})")), {"animation", "at least one track"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 0, "light": {)" + position + "}}")),
                      {"animation.duration"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {"direction": {"times": [0], "values": [[0,-1,0]]}}})")),
                      {"animation.light.direction", "point light"});  // the light type has no such track
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "camera": {"position": {"times": [0, 1], "values": [[0,2,6],[0,1,0]]}}})")),
                      {"animation.camera", "target coincides with its position", "frame"});
  expectErrorMentions(loadError(dir, movingScene(R"({"duration": 1, "light": {"position": {"times": [0], "values": [[0,"x",0]]}}})")),
                      {"animation.light.position.values[0]"});
}

namespace {

// A floor and a named ball; `animation` moves them.
std::string movingGeometryScene(const std::string& animation) {
  return sceneText(R"({"name": "floor", "generator": "plane", "params": {"center": [0, 0, 0], "size": [8, 8]}},
    {"name": "ball", "generator": "sphere", "params": {"center": [2, 1, 0], "radius": 0.5}})",
                   kPointLight, "\"animation\": " + animation);
}

glm::vec3 centreOf(const vs::Mesh& mesh) {
  glm::vec3 sum(0.0f);
  for (const glm::vec3& p : mesh.positions) sum += p;
  return sum / float(std::max<size_t>(mesh.positions.size(), 1));
}

}  // namespace

TEST(Animation, GeometryEntriesMoveRigidlyAboutTheirPivot) {
  // The ball turns about the vertical axis through the origin (a quarter turn per second), rises
  // and grows; the floor stays.
  Scene scene = parse(movingGeometryScene(R"({"duration": 2, "fps": 2, "geometry": [{"entry": "ball",
    "pivot": [0, 1, 0], "axis": [0, 2, 0], "angle_deg": {"times": [0, 2], "values": [0, 180]},
    "translate": {"times": [0, 2], "values": [[0, 0, 0], [0, 1, 0]]},
    "scale": {"times": [0, 2], "values": [1, 2]}}]})"));
  ASSERT_TRUE(scene.animation.movesGeometry());
  EXPECT_FALSE(scene.animation.movesLight());
  EXPECT_NE(scene.animation.describe().find("geometry 'ball'"), std::string::npos) << scene.animation.describe();
  ASSERT_EQ(scene.meshes.size(), 2u);
  const vs::Mesh& restBall = scene.meshes[1];
  Scene at1 = vs::sceneAt(scene, 1.0);  // 90 degrees, 0.5 up, scale 1.5
  glm::vec3 c = centreOf(at1.meshes[1]);
  EXPECT_NEAR(c.x, 0.0f, 1e-3f);
  EXPECT_NEAR(c.y, 1.5f, 1e-3f);
  EXPECT_NEAR(c.z, -3.0f, 1e-3f);  // (2, 0, 0) from the pivot, turned 90 degrees about +y, scaled 1.5
  // Rigid with uniform scale: distances grow by the scale, normals stay unit and turn with it.
  const glm::vec3 a = restBall.positions[0], b = restBall.positions[restBall.positions.size() / 2];
  const glm::vec3 a1 = at1.meshes[1].positions[0], b1 = at1.meshes[1].positions[restBall.positions.size() / 2];
  EXPECT_NEAR(glm::length(a1 - b1), 1.5f * glm::length(a - b), 1e-4f);
  for (const glm::vec3& n : at1.meshes[1].normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  // The floor does not move; the scene's bounds hold every frame's pose, and are the same in every
  // still frame (light fits and ranges match between a played and a still frame).
  EXPECT_EQ(at1.meshes[0].positions, scene.meshes[0].positions);
  glm::vec3 lo, hi, lo1, hi1;
  scene.bounds(lo, hi);
  at1.bounds(lo1, hi1);
  EXPECT_EQ(lo, lo1);
  EXPECT_EQ(hi, hi1);
  for (int i = 0; i < scene.animation.frameCount(); ++i) {
    Scene frame = vs::sceneAt(scene, scene.animation.timeOf(uint32_t(i)));
    for (const glm::vec3& p : frame.meshes[1].positions) {
      EXPECT_TRUE(glm::all(glm::lessThanEqual(lo, p + 1e-4f)) && glm::all(glm::lessThanEqual(p, hi + 1e-4f)))
          << "frame " << i;
    }
  }
  // By index too, with the pivot at the entry's centre by default.
  Scene byIndex = parse(movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": 1,
    "angle_deg": {"times": [0, 1], "values": [0, 90]}}]})"));
  glm::vec3 still = centreOf(vs::sceneAt(byIndex, 1.0).meshes[1]);
  EXPECT_NEAR(glm::length(still - glm::vec3(2, 1, 0)), 0.0f, 1e-3f);  // turning about its own centre
}

TEST(Animation, BadGeometryMotionsAreOneLineErrors) {
  TempDir dir;
  const std::string angle = R"("angle_deg": {"times": [0, 1], "values": [0, 90]})";
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": "bal", )" + angle + "}]}")),
                      {"animation.geometry[0].entry", "'bal'", "ball"});
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": 2, )" + angle + "}]}")),
                      {"animation.geometry[0].entry"});
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": "ball"}]})")),
                      {"animation.geometry[0]", "'translate', 'angle_deg' or 'scale'"});
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": "ball", "axis": [0, 0, 0], )" + angle + "}]}")),
                      {"animation.geometry[0].axis", "zero"});
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": "ball", "scale": {"times": [0], "values": [0]}}]})")),
                      {"animation.geometry[0].scale.values[0]"});
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": "ball", "spin": 1, )" + angle + "}]}")),
                      {"animation.geometry[0].spin"});
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 1, "geometry": [{"entry": "ball", )" + angle +
                                                         R"(}, {"entry": 1, )" + angle + "}]}")),
                      {"animation.geometry[1].entry", "already has a motion"});
  // Catmull-Rom through positive keys can dip below zero between them: refused at load, naming the frame.
  expectErrorMentions(loadError(dir, movingGeometryScene(R"({"duration": 3, "fps": 8, "geometry": [{"entry": "ball",
    "scale": {"times": [0, 1, 1.5, 3], "values": [1, 0.01, 0.01, 40], "interpolation": "catmull-rom"}}]})")),
                      {"animation.geometry[0].scale", "not positive", "frame"});
}

namespace {

// A glTF whose quad (node 1, 1 unit along x from its parent) hangs under node 0, which the
// animation "Slide" raises 2 units over 2 s (LINEAR) and turns 90 degrees about +y at t = 1 (STEP);
// a second animation only animates morph weights.
std::string writeAnimatedGltf(const TempDir& dir, const std::string& interpolation = "LINEAR") {
  QuadGltf quad;
  std::vector<unsigned char> bytes = quad.buffer;  // 60 bytes
  appendRaw(bytes, std::vector<float>{0, 2});                         // 60: translation key times
  appendRaw(bytes, std::vector<float>{0, 0, 0, 0, 2, 0});             // 68: translations
  appendRaw(bytes, std::vector<float>{0, 1});                         // 92: rotation key times
  appendRaw(bytes, std::vector<float>{0, 0, 0, 1, 0, 0.7071068f, 0, 0.7071068f});  // 100: rotations
  const std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"children": [1]}, {"mesh": 0, "translation": [1, 0, 0]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "buffers": [{"uri": "data:application/octet-stream;base64,)" + base64(bytes) + R"(", "byteLength": 132}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12},
                    {"buffer": 0, "byteOffset": 60, "byteLength": 8}, {"buffer": 0, "byteOffset": 68, "byteLength": 24},
                    {"buffer": 0, "byteOffset": 92, "byteLength": 8}, {"buffer": 0, "byteOffset": 100, "byteLength": 32}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
      {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [2]},
      {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
      {"bufferView": 4, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
      {"bufferView": 5, "componentType": 5126, "count": 2, "type": "VEC4"}],
    "animations": [
      {"name": "Slide", "samplers": [{"input": 2, "output": 3, "interpolation": ")" + interpolation + R"("},
                                     {"input": 4, "output": 5, "interpolation": "STEP"}],
       "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}},
                    {"sampler": 1, "target": {"node": 0, "path": "rotation"}}]},
      {"name": "Morph", "samplers": [{"input": 2, "output": 3}], "channels": [{"sampler": 0, "target": {"node": 1, "path": "weights"}}]}]})";
  return dir.write("animated.gltf", json);
}

std::string gltfMotionScene(const std::string& motion) {
  return sceneText(R"({"name": "rig", "gltf": "animated.gltf", "translate": [0, 0, 5]},
    {"name": "ball", "generator": "sphere", "params": {"center": [4, 1, 0], "radius": 0.5}})",
                   kPointLight, R"("animation": {"duration": 2, "fps": 2, "geometry": [)" + motion + "]}");
}

// Leaf cards with a procedural leaf alpha texture (the built-in foliage_alpha): per-vertex texture
// coordinates across each card, a BLEND texture of the blade, veins, rim and nothing around them.
TEST(Procedural, LeafCardsTakeAProceduralLeafAlphaTexture) {
  Scene scene = parse(sceneText(R"({"name": "leaves", "generator": "leaf_cards", "params": {"count": 20},
                                    "alpha_texture": {"pattern": "leaf", "size": 32}})"));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const vs::Mesh& leaves = scene.meshes[0];
  ASSERT_EQ(leaves.alphaTexture, 0);
  EXPECT_LT(leaves.alphaCutoff, 0.0f);  // BLEND
  EXPECT_FALSE(leaves.isOpaque());
  ASSERT_EQ(leaves.uvs.size(), leaves.positions.size());
  ASSERT_EQ(scene.alphaTextures.size(), 1u);
  const vs::AlphaTexture& leaf = scene.alphaTextures[0];
  ASSERT_EQ(leaf.width, 32);
  ASSERT_EQ(leaf.alpha.size(), 32u * 32u);
  std::set<float> levels(leaf.alpha.begin(), leaf.alpha.end());
  EXPECT_EQ(*levels.begin(), 0.0f);    // around the blade
  EXPECT_EQ(*levels.rbegin(), 0.6f);   // the blade
  EXPECT_TRUE(levels.count(0.3f));     // the veins
  EXPECT_GT(levels.size(), 3u);        // and the rim between
  EXPECT_EQ(leaf.sample({0.5f, 0.5f}), 0.3f);  // the midrib at the centre
  EXPECT_EQ(leaf.sample({0.02f, 0.5f}), 0.0f);  // beside the blade

  TempDir dir;
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "plane", "alpha_texture": {"pattern": "leaf"}})")),
                      {"alpha_texture", "leaf_cards"});
  expectErrorMentions(loadError(dir, sceneText(R"({"generator": "leaf_cards", "alpha_texture": {"pattern": "bark"}})")),
                      {"pattern", "leaf"});
  expectErrorMentions(
      loadError(dir, sceneText(R"({"generator": "leaf_cards", "alpha_texture": {"pattern": "leaf", "size": 2}})")),
      {"size"});
}

}  // namespace

TEST(Animation, GltfNodeAnimationsMoveTheirMeshesThroughTheHierarchy) {
  TempDir dir;
  writeAnimatedGltf(dir);
  Scene scene = vs::loadScene(dir.write("scene.json", gltfMotionScene(R"({"entry": "rig", "gltf_animation": "Slide"})")));
  ASSERT_TRUE(scene.animation.movesGeometry());
  EXPECT_NE(scene.animation.describe().find("geometry 'rig' (glTF animation 'Slide')"), std::string::npos)
      << scene.animation.describe();
  // The morph-weight channel is left out with a warning naming it.
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].find("morph-target weights"), std::string::npos) << scene.warnings[0];
  // Rest pose: the quad 1 unit along x, the entry's placement 5 along z.
  EXPECT_NEAR(glm::distance(scene.meshes[0].positions[0], glm::vec3(1, 0, 5)), 0.0f, 1e-5f);
  // t = 0.5: raised 0.5 (linear), not yet turned (step).
  Scene half = vs::sceneAt(scene, 0.5);
  EXPECT_NEAR(glm::distance(half.meshes[0].positions[0], glm::vec3(1, 0.5f, 5)), 0.0f, 1e-5f);
  // t = 1: raised 1, turned 90 degrees about +y: (1, 0, 0) -> (0, 0, -1); the placement after it.
  Scene one = vs::sceneAt(scene, 1.0);
  EXPECT_NEAR(glm::distance(one.meshes[0].positions[0], glm::vec3(0, 1, 4)), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::distance(one.meshes[0].positions[1], glm::vec3(0, 1, 3)), 0.0f, 1e-5f);
  // The quad's normal turns with it; the ball does not move.
  const glm::vec3 n0 = scene.meshes[0].normals[0];
  EXPECT_NEAR(glm::distance(one.meshes[0].normals[0], glm::vec3(n0.z, n0.y, -n0.x)), 0.0f, 1e-5f);
  EXPECT_EQ(one.meshes[1].positions, scene.meshes[1].positions);
  // By index, and CUBICSPLINE outputs count three values per key.
  Scene byIndex = vs::loadScene(dir.write("index.json", gltfMotionScene(R"({"entry": 0, "gltf_animation": 0})")));
  EXPECT_NEAR(glm::distance(vs::sceneAt(byIndex, 2.0).meshes[0].positions[0], glm::vec3(0, 2, 4)), 0.0f, 1e-5f);
  writeAnimatedGltf(dir, "CUBICSPLINE");
  expectErrorMentions(loadError(dir, gltfMotionScene(R"({"entry": "rig", "gltf_animation": "Slide"})")),
                      {"geometry[0].gltf", "animation 0 ('Slide') channel 0", "2 output values for 2 key times", "3 per key"});
}

TEST(Animation, BadGltfAnimationReferencesAreOneLineErrors) {
  TempDir dir;
  writeAnimatedGltf(dir);
  expectErrorMentions(loadError(dir, gltfMotionScene(R"({"entry": "rig", "gltf_animation": "Slid"})")),
                      {"animation.geometry[0].gltf_animation", "'Slid'", "Slide"});
  expectErrorMentions(loadError(dir, gltfMotionScene(R"({"entry": "rig", "gltf_animation": 2})")),
                      {"animation.geometry[0].gltf_animation"});
  expectErrorMentions(loadError(dir, gltfMotionScene(R"({"entry": "ball", "gltf_animation": 0})")),
                      {"animation.geometry[0].gltf_animation", "no glTF animation"});
  expectErrorMentions(loadError(dir, gltfMotionScene(R"({"entry": "rig", "gltf_animation": 0, "scale": {"times": [0], "values": [2]}})")),
                      {"animation.geometry[0].scale", "glTF animation or its own tracks"});
}
