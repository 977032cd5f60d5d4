// Scene JSON parsing and loading (format: scenes/README.md).
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include "scenes/builtin_scenes.hpp"
#include "scenes/content_hash.hpp"
#include "scenes/gltf_loader.hpp"
#include "scenes/json_reader.hpp"
#include "scenes/obj_loader.hpp"
#include "scenes/mesh_utils.hpp"
#include "scenes/procedural.hpp"
#include "scenes/scene.hpp"
#include "scenes/volume.hpp"

namespace vs {

size_t Scene::triangleCount() const {
  size_t total = 0;
  for (const Mesh& mesh : meshes) total += mesh.triangleCount();
  return total;
}

size_t Scene::vertexCount() const {
  size_t total = 0;
  for (const Mesh& mesh : meshes) total += mesh.positions.size();
  return total;
}

size_t Scene::dataBytes() const {
  size_t total = light.textureRGB.size() * sizeof(float);
  for (const Mesh& mesh : meshes)
    total += (mesh.positions.size() + mesh.normals.size()) * sizeof(glm::vec3) + mesh.uvs.size() * sizeof(glm::vec2) +
             mesh.indices.size() * sizeof(uint32_t);
  for (const AlphaTexture& t : alphaTextures) total += t.alpha.size() * sizeof(float);
  for (const Volume& v : volumes) total += v.density.size() * sizeof(float);
  return total;
}

void Scene::bounds(glm::vec3& lo, glm::vec3& hi) const {
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = glm::vec3(std::numeric_limits<float>::lowest());
  bool any = false;
  for (const Mesh& mesh : meshes) {
    for (const glm::vec3& p : mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      any = true;
    }
  }
  if (hasMotionBounds && motionLo.x <= motionHi.x) {
    lo = glm::min(lo, motionLo);
    hi = glm::max(hi, motionHi);
    any = true;
  }
  for (const Volume& v : volumes) {
    lo = glm::min(lo, v.boxLo);
    hi = glm::max(hi, v.boxHi);
    any = true;
  }
  if (!any) {  // unit box (side 1) centred on the origin
    lo = glm::vec3(-0.5f);
    hi = glm::vec3(0.5f);
  }
}

namespace {

namespace fs = std::filesystem;

const char* const kBuiltinPrefix = "builtin:";

std::string resolvePath(const std::string& baseDir, const std::string& path) {
  fs::path p(path);
  if (p.is_absolute() || baseDir.empty()) return p.lexically_normal().string();
  return (fs::path(baseDir) / p).lexically_normal().string();
}

std::string lowercase(std::string text) {
  for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// Reads a light texture as linear RGB (row 0 = top). sRGB-encoded files are linearised.
void loadLightTexture(Light& light, const std::string& path, const JsonLocation& at, ContentHasher& hasher) {
  std::string bytes, error;
  if (!readFile(path, bytes, error)) at.fail("cannot open light texture '" + path + "': " + error);
  hasher.addBlock(bytes);
  auto input = OIIO::ImageInput::open(path);
  if (!input) at.fail("cannot read light texture '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec& spec = input->spec();
  const int width = spec.width, height = spec.height, channels = spec.nchannels;
  if (width <= 0 || height <= 0 || channels <= 0 || spec.depth > 1)
    at.fail("light texture '" + path + "' is not a 2D image");
  if (size_t(width) * size_t(height) > (size_t(1) << 26)) at.fail("light texture '" + path + "' is too large");
  std::vector<float> pixels(size_t(width) * size_t(height) * size_t(channels));
  if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data()))
    at.fail("cannot read light texture '" + path + "': " + input->geterror());
  std::string colorSpace = lowercase(spec.get_string_attribute("oiio:ColorSpace"));
  bool isSrgb = colorSpace == "srgb" || (colorSpace.empty() && spec.format == OIIO::TypeDesc::UINT8);

  light.textureWidth = width;
  light.textureHeight = height;
  light.textureRGB.resize(size_t(width) * size_t(height) * 3);
  for (size_t pixel = 0; pixel < size_t(width) * size_t(height); ++pixel) {
    for (int c = 0; c < 3; ++c) {
      float v = pixels[pixel * size_t(channels) + size_t(channels >= 3 ? c : 0)];  // grey: replicate
      if (!std::isfinite(v) || v < 0.0f)
        at.fail("light texture '" + path + "' has negative or non-finite pixel values");
      light.textureRGB[pixel * 3 + size_t(c)] = isSrgb ? srgbToLinear(v) : v;
    }
  }
}

Camera readCamera(ObjectReader camera) {
  Camera c;
  camera.declare({"position", "target", "up", "fov_y_deg", "near", "far"});
  c.position = camera.vec3("position", Range::any());
  c.target = camera.vec3("target", Range::any());
  c.up = camera.vec3("up", glm::vec3(0, 1, 0), Range::any());
  c.fovYDeg = float(camera.number("fov_y_deg", 60.0, Range::open(0.0, 180.0)));
  c.nearZ = float(camera.number("near", 0.1, Range::above(0.0)));
  c.farZ = float(camera.number("far", 100.0, Range::above(c.nearZ)));
  camera.finish();
  // A 32-bit depth buffer and float ray parameters have nothing left to resolve beyond this.
  if (double(c.farZ) / double(c.nearZ) > 1e9)
    camera.fail("far", "far / near must be at most 1e9 (got " + formatNumber(double(c.farZ) / double(c.nearZ)) + ")");
  glm::vec3 view = c.target - c.position;
  if (!(glm::length(view) > 0.0f)) camera.fail("target", "must differ from position");
  if (!(glm::length(c.up) > 0.0f)) camera.fail("up", "must not be zero");
  c.up = glm::normalize(c.up);
  if (glm::length(glm::cross(glm::normalize(view), c.up)) < 1e-4f)
    camera.fail("up", "must not be parallel to the viewing direction");
  return c;
}

// Direction from either "direction" or "target" (which then needs "position").
glm::vec3 readLightDirection(ObjectReader& light, const glm::vec3* position) {
  bool hasDirection = light.has("direction"), hasTarget = light.has("target");
  if (hasDirection && hasTarget) light.fail("target", "give either direction or target, not both");
  if (!hasDirection && !hasTarget) {
    light.failOnMisspellingOf("direction");
    light.failOnMisspellingOf("target");
    light.fail("direction", "missing required key (or give target)");
  }
  glm::vec3 direction;
  if (hasDirection) {
    direction = light.vec3("direction", Range::any());
    if (!(glm::length(direction) > 0.0f)) light.fail("direction", "must not be zero");
  } else {
    glm::vec3 target = light.vec3("target", Range::any());
    if (!position) light.fail("position", "missing required key (needed with target)");
    direction = target - *position;
    if (!(glm::length(direction) > 0.0f)) light.fail("target", "must differ from position");
  }
  return glm::normalize(direction);
}

Light readLight(ObjectReader light, const std::string& baseDir, ContentHasher& hasher) {
  Light l;
  light.declare({"type", "position", "direction", "target", "color", "intensity", "spot_inner_deg", "spot_outer_deg",
                 "texture", "width", "height", "radius", "tangent", "two_sided", "power"});
  light.required("type");
  std::string type = light.choice("type", {"point", "spot", "directional", "rect", "disk"}, "");
  for (LightType t : {LightType::Point, LightType::Spot, LightType::Directional, LightType::Rect, LightType::Disk})
    if (type == lightTypeName(t)) l.type = t;
  l.color = light.vec3("color", glm::vec3(1.0f), Range::atLeast(0.0));
  // Bounded so that intensity times any coefficient and 1/r^2 stays a finite float. Area lights may
  // give their power instead (converted below, once the area is known).
  bool byPower = isAreaLight(l.type) && light.has("power") && !light.has("intensity");
  if (!isAreaLight(l.type)) light.forbid("power", "only area lights take a power (give intensity)");
  if (isAreaLight(l.type) && light.has("power") && light.has("intensity"))
    light.fail("power", "give either intensity (radiance) or power, not both");
  l.intensity = byPower ? 0.0f : float(light.number("intensity", Range::closed(0.0, 1e20)));
  double power = byPower ? light.number("power", Range::closed(0.0, 1e20)) : 0.0;
  const std::string spotOnly = "only used by spot lights";
  if (l.type == LightType::Point) {
    l.position = light.vec3("position", Range::any());
    light.forbid("direction", "not used by point lights");
    light.forbid("target", "not used by point lights");
  } else if (l.type == LightType::Spot) {
    l.position = light.vec3("position", Range::any());
    l.direction = readLightDirection(light, &l.position);
    l.spotOuterDeg = float(light.number("spot_outer_deg", 30.0, Range::open(0.0, 90.0)));
    l.spotInnerDeg = float(light.number("spot_inner_deg", std::min(20.0, double(l.spotOuterDeg)),
                                        Range::closedOpen(0.0, 90.0)));
    if (l.spotInnerDeg > l.spotOuterDeg)
      light.fail("spot_inner_deg", "must be <= spot_outer_deg (" + formatNumber(l.spotOuterDeg) + ")");
  } else if (isAreaLight(l.type)) {
    l.position = light.vec3("position", Range::any());
    l.direction = readLightDirection(light, &l.position);
    if (l.type == LightType::Rect) {
      l.width = float(light.number("width", Range::above(0.0)));
      l.height = float(light.number("height", Range::above(0.0)));
      light.forbid("radius", "only used by disk lights");
    } else {
      l.radius = float(light.number("radius", Range::above(0.0)));
      light.forbid("width", "only used by rect lights");
      light.forbid("height", "only used by rect lights");
    }
    // The tangent is made perpendicular to the normal; by default any perpendicular axis.
    glm::vec3 fallback = std::fabs(l.direction.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    glm::vec3 tangent = light.vec3("tangent", glm::cross(l.direction, fallback), Range::any());
    tangent -= l.direction * glm::dot(tangent, l.direction);
    if (!(glm::length(tangent) > 1e-6f)) light.fail("tangent", "must not be zero or parallel to the light's direction");
    l.tangent = glm::normalize(tangent);
    l.twoSided = light.boolean("two_sided", false);
    // Lambertian emitter: power = pi L A one-sided, 2 pi L A two-sided.
    if (byPower) l.intensity = float(power / ((l.twoSided ? 2.0 : 1.0) * 3.14159265358979323846 * double(l.area())));
    if (light.has("texture")) light.fail("texture", "area lights take no texture");
  } else {
    glm::vec3 position;
    bool hasPosition = light.has("target") && light.has("position");
    if (hasPosition) position = light.vec3("position", Range::any());
    else light.forbid("position", "directional lights have no position (it is only used together with target)");
    l.direction = readLightDirection(light, hasPosition ? &position : nullptr);
  }
  if (l.type != LightType::Spot) {
    light.forbid("spot_inner_deg", spotOnly);
    light.forbid("spot_outer_deg", spotOnly);
  }
  if (!isAreaLight(l.type)) {
    for (const char* key : {"width", "height", "radius", "tangent", "two_sided"}) light.forbid(key, "only used by area (rect, disk) lights");
  }
  const bool hasTexture = light.has("texture");
  std::string texture = light.string("texture", "");
  if (hasTexture && texture.empty()) light.fail("texture", "must not be empty");
  light.finish();
  if (hasTexture) {
    l.texturePath = resolvePath(baseDir, texture);
    loadLightTexture(l, l.texturePath, light.locationOf("texture"), hasher);
  }
  return l;
}

Medium readMedium(ObjectReader medium) {
  Medium m;
  medium.declare({"sigma_s", "sigma_a", "phase", "g"});
  m.sigmaS = float(medium.number("sigma_s", Range::closed(0.0, 1e6)));
  m.sigmaA = float(medium.number("sigma_a", Range::closed(0.0, 1e6)));
  std::string phase = medium.choice("phase", {"isotropic", "hg"}, "isotropic");
  m.phase = phase == "hg" ? Phase::HenyeyGreenstein : Phase::Isotropic;
  if (m.phase == Phase::HenyeyGreenstein) m.g = float(medium.number("g", 0.0, Range::open(-1.0, 1.0)));
  else medium.forbid("g", "only used with \"phase\": \"hg\"");
  medium.finish();
  return m;
}

// Translation * rotation about Y * uniform scale.
glm::mat4 placement(const glm::vec3& translate, float scale, float rotateYDeg) {
  float angle = glm::radians(rotateYDeg), c = std::cos(angle), s = std::sin(angle);
  glm::mat4 m(1.0f);
  m[0] = glm::vec4(c * scale, 0, -s * scale, 0);
  m[1] = glm::vec4(0, scale, 0, 0);
  m[2] = glm::vec4(s * scale, 0, c * scale, 0);
  m[3] = glm::vec4(translate, 1.0f);
  return m;
}

// translate / scale / rotate_y_deg of a file entry (glTF or OBJ), and the keys such entries refuse.
glm::mat4 readFilePlacement(ObjectReader& entry, const std::string& materialKeys) {
  glm::vec3 translate = entry.vec3("translate", glm::vec3(0.0f), Range::any());
  float scale = float(entry.number("scale", 1.0, Range::above(0.0)));
  float rotateYDeg = float(entry.number("rotate_y_deg", 0.0, Range::any()));
  entry.forbid("params", "only used by generator entries");
  entry.forbid("albedo", "this entry takes the albedo from its materials (" + materialKeys + ")");
  entry.forbid("opacity", "this entry takes the opacity from its materials (" + materialKeys + ")");
  entry.forbid("transmittance_color", "only used by generator entries");
  entry.finish();
  return placement(translate, scale, rotateYDeg);
}

struct GeometryResult {
  std::vector<Mesh> meshes;
  std::vector<int> meshNode;             // per mesh: its glTF node (-1: not from glTF)
  std::shared_ptr<const GltfRig> rig;    // the last glTF entry's node animations (null: none)
  std::vector<AlphaTexture> alphaTextures;
  bool usedGenerator = false;
  bool hasGltfLight = false;
  Light gltfLight;
  std::vector<std::string> warnings;
};

void readGeometryEntry(ObjectReader entry, const std::string& baseDir, ContentHasher& hasher, GeometryResult& out,
                       const LoadProgress& progress) {
  const std::string& origin = entry.location().origin;
  entry.declare({"name", "generator", "params", "albedo", "gltf", "obj", "translate", "scale", "rotate_y_deg", "opacity",
                 "transmittance_color", "alpha_texture"});
  bool isGenerator = entry.has("generator"), isGltf = entry.has("gltf"), isObj = entry.has("obj");
  std::string name = entry.string("name", "");
  const std::string gltfOnly = "only used by glTF and OBJ entries";
  if (int(isGenerator) + int(isGltf) + int(isObj) > 1)
    entry.fail(isObj ? "obj" : "gltf", "an entry has one of 'generator', 'gltf' or 'obj'");
  if (isGenerator) {
    std::string generator = entry.string("generator");
    const Json* params = entry.optional("params");
    glm::vec3 albedo = entry.vec3("albedo", Mesh().albedo, Range::closed(0.0, 1.0));
    float opacity = float(entry.number("opacity", 1.0, Range::closed(0.0, 1.0)));
    glm::vec3 transmittanceColor = entry.vec3("transmittance_color", glm::vec3(0.0f), Range::closed(0.0, 1.0));
    // A procedural alpha texture (BLEND: opacity x texel alpha) over the generator's texture coordinates.
    int alphaTexture = -1;
    if (const Json* texture = entry.optional("alpha_texture")) {
      ObjectReader t(*texture, entry.locationOf("alpha_texture"));
      t.choice("pattern", {"leaf"}, "leaf");
      int size = int(t.integer("size", 64, 4, 4096));
      t.finish();
      if (generator != "leaf_cards")
        entry.fail("alpha_texture", "needs texture coordinates: only the leaf_cards generator has them");
      alphaTexture = int(out.alphaTextures.size());
      out.alphaTextures.push_back(makeLeafAlphaTexture(size));
    }
    for (const char* key : {"translate", "scale", "rotate_y_deg"}) entry.forbid(key, gltfOnly);
    entry.forbid("obj", "an entry has one of 'generator', 'gltf' or 'obj'");
    entry.finish();
    if (progress) progress("generating " + generator, 0.0);
    std::vector<Mesh> meshes = generateMeshes(generator, params ? *params : Json::object(), origin,
                                              entry.locationOf("generator").path, entry.locationOf("params").path);
    for (Mesh& mesh : meshes) {
      mesh.albedo = albedo;
      mesh.opacity = opacity;
      mesh.transmittanceColor = transmittanceColor;
      mesh.alphaTexture = alphaTexture;
      if (!name.empty()) mesh.name = name;
      out.meshes.push_back(std::move(mesh));
    }
    out.usedGenerator = true;
    return;
  }
  if (isGltf) {
    std::string file = entry.string("gltf");
    glm::mat4 where = readFilePlacement(entry, "baseColorFactor, alphaMode");
    GltfContent content;
    try {
      content = loadGltf(resolvePath(baseDir, file), where, &hasher, progress);
    } catch (const SceneError& e) {
      entry.fail("gltf", e.what());
    }
    int textureBase = int(out.alphaTextures.size());
    for (AlphaTexture& t : content.alphaTextures) out.alphaTextures.push_back(std::move(t));
    for (size_t k = 0; k < content.meshes.size(); ++k) {
      Mesh& mesh = content.meshes[k];
      if (mesh.alphaTexture >= 0) mesh.alphaTexture += textureBase;
      if (!name.empty()) mesh.name = name + "/" + mesh.name;
      out.meshes.push_back(std::move(mesh));
      out.meshNode.push_back(k < content.meshNode.size() ? content.meshNode[k] : -1);
    }
    out.rig = content.rig;
    for (std::string& w : content.warnings) out.warnings.push_back(std::move(w));
    if (content.hasLight && !out.hasGltfLight) {
      out.hasGltfLight = true;
      out.gltfLight = content.light;
    }
    return;
  }
  if (isObj) {
    std::string file = entry.string("obj");
    glm::mat4 where = readFilePlacement(entry, "Kd, d or Tr");
    std::vector<Mesh> meshes;
    try {
      meshes = loadObj(resolvePath(baseDir, file), where, &hasher, &out.warnings, progress);
    } catch (const SceneError& e) {
      entry.fail("obj", e.what());
    }
    for (Mesh& mesh : meshes) {
      if (!name.empty()) mesh.name = name + "/" + mesh.name;
      out.meshes.push_back(std::move(mesh));
    }
    return;
  }
  entry.finish();  // reports a misspelt "generator"/"gltf"/"obj" first
  entry.location().fail("needs a 'generator', 'gltf' or 'obj' key");
}

// ---- animation (format: scenes/README.md, "Animation")

// A track: {"times": [...], "values": [...], "interpolation": "linear" | "step" | "catmull-rom"}.
template <typename T, typename ReadValue>
Track<T> readTrack(ObjectReader track, double duration, ReadValue readValue) {
  Track<T> out;
  track.declare({"times", "values", "interpolation"});
  const Json& times = track.required("times");
  const Json& values = track.required("values");
  JsonLocation timesAt = track.locationOf("times"), valuesAt = track.locationOf("values");
  if (!times.is_array()) timesAt.fail("expected an array of key times, got " + std::string(times.type_name()));
  if (!values.is_array()) valuesAt.fail("expected an array of key values, got " + std::string(values.type_name()));
  if (times.empty()) timesAt.fail("a track needs at least one key");
  if (values.size() != times.size())
    valuesAt.fail("has " + std::to_string(values.size()) + " values for " + std::to_string(times.size()) + " key times");
  for (size_t i = 0; i < times.size(); ++i) {
    float t = float(readNumber(times[i], timesAt.item(i), Range::closed(0.0, duration)));
    if (i > 0 && !(t > out.times.back()))
      timesAt.item(i).fail("key times must increase strictly (" + formatNumber(t) + " after " +
                           formatNumber(out.times.back()) + ")");
    out.times.push_back(t);
    out.values.push_back(readValue(values[i], valuesAt.item(i)));
  }
  std::string mode = track.choice("interpolation", {"linear", "step", "catmull-rom"}, "linear");
  out.mode = mode == "step" ? Interpolation::Step : mode == "catmull-rom" ? Interpolation::CatmullRom : Interpolation::Linear;
  track.finish();
  return out;
}

Track<glm::vec3> vec3Track(ObjectReader& owner, const std::string& key, double duration) {
  const Json* value = owner.optional(key);
  if (!value) return {};
  return readTrack<glm::vec3>(ObjectReader(*value, owner.locationOf(key)), duration,
                              [](const Json& v, const JsonLocation& at) { return readVec3(v, at, Range::any()); });
}

Track<float> numberTrack(ObjectReader& owner, const std::string& key, double duration, Range range) {
  const Json* value = owner.optional(key);
  if (!value) return {};
  return readTrack<float>(ObjectReader(*value, owner.locationOf(key)), duration,
                          [range](const Json& v, const JsonLocation& at) { return float(readNumber(v, at, range)); });
}

void readCameraTracks(ObjectReader camera, Animation& a) {
  camera.declare({"position", "target", "fov_y_deg"});
  a.cameraPosition = vec3Track(camera, "position", a.duration);
  a.cameraTarget = vec3Track(camera, "target", a.duration);
  a.cameraFov = numberTrack(camera, "fov_y_deg", a.duration, Range::open(0.0, 180.0));
  camera.finish();
}

void readLightTracks(ObjectReader light, const Light& still, Animation& a) {
  light.declare({"position", "direction", "target", "intensity", "width", "height", "radius", "tangent"});
  const LightType type = still.type;
  const bool hasPosition = type != LightType::Directional, hasDirection = type != LightType::Point;
  const std::string name = lightTypeName(type);
  if (!hasPosition) light.forbid("position", "a directional light has no position to move");
  if (!hasDirection) {
    light.forbid("direction", "a point light has no direction to move");
    light.forbid("target", "a point light has no direction to move");
  }
  if (light.has("direction") && light.has("target")) light.fail("target", "give either direction or target, not both");
  if (type != LightType::Rect) {
    light.forbid("width", "only rect lights have a width (this one is " + name + ")");
    light.forbid("height", "only rect lights have a height (this one is " + name + ")");
  }
  if (type != LightType::Disk) light.forbid("radius", "only disk lights have a radius (this one is " + name + ")");
  if (!isAreaLight(type)) light.forbid("tangent", "only area lights have a tangent");
  a.lightPosition = vec3Track(light, "position", a.duration);
  a.lightDirection = vec3Track(light, "direction", a.duration);
  a.lightTarget = vec3Track(light, "target", a.duration);
  a.lightTangent = vec3Track(light, "tangent", a.duration);
  a.lightIntensity = numberTrack(light, "intensity", a.duration, Range::closed(0.0, 1e20));
  a.lightWidth = numberTrack(light, "width", a.duration, Range::above(0.0));
  a.lightHeight = numberTrack(light, "height", a.duration, Range::above(0.0));
  a.lightRadius = numberTrack(light, "radius", a.duration, Range::above(0.0));
  light.finish();
}

// Every frame of the sequence must be a valid still scene: the camera looks somewhere, the light
// has a direction. Checked at load, so no frame fails (or divides by zero) half way through a run.
void checkEveryFrame(const Scene& scene, const JsonLocation& at) {
  const Animation& a = scene.animation;
  for (int i = 0; i < a.frameCount(); ++i) {
    const double t = a.timeOf(uint32_t(i));
    Camera camera = scene.camera;
    Light light = scene.light;
    a.apply(t, camera, light);
    const std::string when = "at t = " + formatNumber(t) + " s (frame " + std::to_string(i) + "): ";
    glm::vec3 view = camera.target - camera.position;
    if (!(glm::length(view) > 1e-6f)) at.child("camera").fail(when + "the camera's target coincides with its position");
    if (glm::length(glm::cross(glm::normalize(view), camera.up)) < 1e-4f)
      at.child("camera").fail(when + "the camera looks along its up vector");
    for (size_t g = 0; g < a.geometry.size(); ++g)
      if (!a.geometry[g].scale.empty() && !(a.geometry[g].scale.at(t) > 0.0f))
        at.child("geometry").item(g).child("scale").fail(when + "the scale is not positive (the interpolation overshoots)");
    if (a.lightDirection.empty() && a.lightTarget.empty()) continue;
    glm::vec3 direction = a.lightTarget.empty() ? a.lightDirection.at(t) : a.lightTarget.at(t) - light.position;
    if (!(glm::length(direction) > 1e-6f)) at.child("light").fail(when + "the light's direction is zero");
  }
}

// The geometry entries of a scene file, for the animation's references to them.
struct GeometryEntries {
  std::vector<std::string> names;          // "" for an entry without a name
  std::vector<std::vector<size_t>> meshes; // per entry, its meshes in Scene::meshes
  std::vector<std::vector<int>> meshNodes; // per entry, per mesh: its glTF node (-1: none)
  std::vector<std::shared_ptr<const GltfRig>> rigs;  // per entry: its glTF animations (null: none)
};

// {"entry": ..., "gltf_animation": NAME or INDEX}: a glTF entry plays one of its animations.
void readGltfAnimation(ObjectReader& item, size_t index, const GeometryEntries& entries, GeometryMotion& g) {
  const JsonLocation at = item.locationOf("gltf_animation");
  for (const char* key : {"pivot", "axis", "translate", "angle_deg", "scale"})
    item.forbid(key, "a motion plays either its glTF animation or its own tracks");
  const std::shared_ptr<const GltfRig>& rig = entries.rigs[index];
  if (!rig || rig->clips.empty()) at.fail("geometry entry " + g.entry + " has no glTF animation to play");
  const Json& clip = item.required("gltf_animation");
  if (clip.is_string()) {
    const std::string name = clip.get<std::string>();
    std::vector<std::string> names;
    for (const GltfRig::Clip& c : rig->clips) names.push_back(c.name);
    auto it = std::find(names.begin(), names.end(), name);
    if (name.empty() || it == names.end()) at.fail("the glTF file has no animation named '" + name + "'" + didYouMean(name, names));
    g.clip = int(it - names.begin());
  } else {
    g.clip = int(readInteger(clip, at, 0, int64_t(rig->clips.size()) - 1));
  }
  g.rig = rig;
  g.meshNodes = entries.meshNodes[index];
  for (size_t k = 0; k < g.meshes.size(); ++k) {
    const glm::mat4 rest = rig->worldAt(g.meshNodes[k], -1, 0.0);
    if (!(std::fabs(glm::determinant(glm::mat3(rest))) > 1e-30f))
      at.fail("node " + std::to_string(g.meshNodes[k]) + " has a singular rest transform: its mesh cannot be moved");
    g.restInverse.push_back(glm::inverse(rest));
  }
}

// {"entry": NAME or INDEX, "pivot": [x, y, z], "axis": [x, y, z], "translate": TRACK,
//  "angle_deg": TRACK, "scale": TRACK}
GeometryMotion readGeometryMotion(ObjectReader item, const Scene& scene, const GeometryEntries& entries,
                                  double duration) {
  GeometryMotion g;
  item.declare({"entry", "pivot", "axis", "translate", "angle_deg", "scale", "gltf_animation"});
  const Json& entry = item.required("entry");
  const JsonLocation entryAt = item.locationOf("entry");
  size_t index = 0;
  if (entry.is_string()) {
    const std::string name = entry.get<std::string>();
    auto it = std::find(entries.names.begin(), entries.names.end(), name);
    if (name.empty() || it == entries.names.end()) {
      std::vector<std::string> named;
      for (const std::string& n : entries.names)
        if (!n.empty()) named.push_back(n);
      entryAt.fail("no geometry entry is named '" + name + "'" + didYouMean(name, named));
    }
    index = size_t(it - entries.names.begin());
    g.entry = "'" + name + "'";
  } else if (entry.is_number()) {
    index = size_t(readInteger(entry, entryAt, 0, int64_t(entries.names.size()) - 1));
    g.entry = entries.names[index].empty() ? "#" + std::to_string(index) : "'" + entries.names[index] + "'";
  } else {
    entryAt.fail("expected a geometry entry's name or index, got " + std::string(entry.type_name()));
  }
  g.meshes = entries.meshes[index];
  if (g.meshes.empty()) entryAt.fail("geometry entry " + g.entry + " has no triangles to move");
  if (item.has("gltf_animation")) {
    readGltfAnimation(item, index, entries, g);
    item.finish();
    return g;
  }
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (size_t m : g.meshes)
    for (const glm::vec3& p : scene.meshes[m].positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  g.pivot = item.vec3("pivot", 0.5f * (lo + hi), Range::closed(-1e6, 1e6));
  glm::vec3 axis = item.vec3("axis", glm::vec3(0, 1, 0), Range::closed(-1e6, 1e6));
  if (!(glm::length(axis) > 1e-6f)) item.fail("axis", "the rotation axis must not be zero");
  g.axis = glm::normalize(axis);
  g.translate = vec3Track(item, "translate", duration);
  g.angleDeg = numberTrack(item, "angle_deg", duration, Range::closed(-1e6, 1e6));
  g.scale = numberTrack(item, "scale", duration, Range::open(0.0, 1e6));
  item.finish();
  if (g.translate.empty() && g.angleDeg.empty() && g.scale.empty())
    item.location().fail("a geometry motion needs a 'translate', 'angle_deg' or 'scale' track, or 'gltf_animation'");
  return g;
}

Animation readAnimation(ObjectReader animation, const Scene& scene, const GeometryEntries& entries) {
  Animation a;
  animation.declare({"duration", "fps", "camera", "light", "geometry"});
  a.duration = animation.number("duration", Range::open(0.0, 3600.0));
  a.fps = animation.number("fps", 24.0, Range::closed(1.0, 1000.0));
  if (a.duration * a.fps > 100000.0)
    animation.fail("duration", "the sequence has more than 100,000 frames (duration x fps)");
  if (const Json* camera = animation.optional("camera")) readCameraTracks(ObjectReader(*camera, animation.locationOf("camera")), a);
  if (const Json* light = animation.optional("light"))
    readLightTracks(ObjectReader(*light, animation.locationOf("light")), scene.light, a);
  if (const Json* geometry = animation.optional("geometry")) {
    const JsonLocation at = animation.locationOf("geometry");
    if (!geometry->is_array()) at.fail("expected an array of geometry motions, got " + std::string(geometry->type_name()));
    std::vector<size_t> moved;
    for (size_t i = 0; i < geometry->size(); ++i) {
      a.geometry.push_back(readGeometryMotion(ObjectReader((*geometry)[i], at.item(i)), scene, entries, a.duration));
      if (std::find(moved.begin(), moved.end(), a.geometry.back().meshes.front()) != moved.end())
        at.item(i).child("entry").fail("geometry entry " + a.geometry.back().entry + " already has a motion");
      moved.push_back(a.geometry.back().meshes.front());
    }
  }
  animation.finish();
  if (!a.movesCamera() && !a.movesLight() && !a.movesGeometry())
    animation.fail("camera", "an animation needs at least one track (camera, light or geometry)");
  return a;
}

std::string sceneNameFromOrigin(const std::string& origin) {
  if (origin.rfind(kBuiltinPrefix, 0) == 0) return origin.substr(std::string(kBuiltinPrefix).size());
  return fs::path(origin).stem().string();
}

}  // namespace

Scene parseSceneJson(const std::string& text, const std::string& baseDir, const std::string& origin,
                     const LoadProgress& progress) {
  Json document = parseJsonStrict(text, origin);
  ObjectReader root(document, JsonLocation{origin, ""});
  for (const char* key : {"description", "geometry", "camera", "light", "medium", "volumes", "animation"}) root.has(key);
  root.finish();  // catch misspelt top-level keys before any heavy work

  Scene scene;
  scene.name = sceneNameFromOrigin(origin);
  scene.source = origin;
  ContentHasher hasher;
  hasher.addBlock(std::string("vshadow-scene-v1"));
  hasher.addBlock(text);

  scene.description = root.string("description", "");
  if (scene.description.find_first_of("\r\n") != std::string::npos) root.fail("description", "must be a single line");
  scene.camera = readCamera(ObjectReader(root.required("camera"), root.locationOf("camera")));
  if (const Json* medium = root.optional("medium")) scene.medium = readMedium(ObjectReader(*medium, root.locationOf("medium")));

  const Json& geometry = root.required("geometry");
  JsonLocation geometryAt = root.locationOf("geometry");
  if (!geometry.is_array()) geometryAt.fail("expected an array, got " + std::string(geometry.type_name()));
  GeometryResult result;
  std::vector<size_t> meshEntry;  // per mesh of result.meshes: the geometry entry it came from
  std::vector<std::shared_ptr<const GltfRig>> entryRigs(geometry.size());
  for (size_t i = 0; i < geometry.size(); ++i) {
    result.rig.reset();
    readGeometryEntry(ObjectReader(geometry[i], geometryAt.item(i)), baseDir, hasher, result, progress);
    meshEntry.resize(result.meshes.size(), i);
    result.meshNode.resize(result.meshes.size(), -1);
    entryRigs[i] = result.rig;
  }

  if (const Json* volumes = root.optional("volumes")) {
    JsonLocation volumesAt = root.locationOf("volumes");
    if (!volumes->is_array()) volumesAt.fail("expected an array, got " + std::string(volumes->type_name()));
    for (size_t i = 0; i < volumes->size(); ++i)
      scene.volumes.push_back(readVolume(ObjectReader((*volumes)[i], volumesAt.item(i)), baseDir, hasher));
  }

  // The scene JSON's light wins over a light found in its glTF files.
  if (const Json* light = root.optional("light")) {
    scene.light = readLight(ObjectReader(*light, root.locationOf("light")), baseDir, hasher);
  } else if (result.hasGltfLight) {
    scene.light = result.gltfLight;
  } else {
    root.fail("light", "missing required key (and no glTF file in the scene has a KHR_lights_punctual light)");
  }

  scene.alphaTextures = std::move(result.alphaTextures);
  scene.warnings = std::move(result.warnings);
  GeometryEntries entries;
  entries.meshes.resize(geometry.size());
  entries.meshNodes.resize(geometry.size());
  entries.rigs = entryRigs;
  for (size_t i = 0; i < geometry.size(); ++i) {
    const Json& name = geometry[i].is_object() && geometry[i].contains("name") ? geometry[i]["name"] : Json();
    entries.names.push_back(name.is_string() ? name.get<std::string>() : "");
  }
  const std::string cleaning = "cleaning meshes";
  size_t trianglesToClean = 0, trianglesCleaned = 0;
  for (const Mesh& mesh : result.meshes) trianglesToClean += mesh.triangleCount();
  for (size_t i = 0; i < result.meshes.size(); ++i) {
    Mesh& mesh = result.meshes[i];
    if (progress) progress(cleaning, trianglesToClean ? double(trianglesCleaned) / double(trianglesToClean) : 0.0);
    trianglesCleaned += mesh.triangleCount();
    scene.droppedTriangles += sanitizeMesh(mesh);
    if (mesh.triangleCount() == 0) continue;
    entries.meshes[meshEntry[i]].push_back(scene.meshes.size());
    entries.meshNodes[meshEntry[i]].push_back(result.meshNode[i]);
    scene.meshes.push_back(std::move(mesh));
  }

  if (const Json* animation = root.optional("animation")) {
    scene.animation = readAnimation(ObjectReader(*animation, root.locationOf("animation")), scene, entries);
    checkEveryFrame(scene, root.locationOf("animation"));
    if (scene.animation.movesGeometry()) {
      sequenceBounds(scene, scene.motionLo, scene.motionHi);
      scene.hasMotionBounds = true;
    }
  }
  if (result.usedGenerator) hasher.addBlock(std::string(kProceduralVersion));
  scene.contentHash = hasher.hex();
  return scene;
}

Scene loadScene(const std::string& nameOrPath, const LoadProgress& progress) {
  for (const auto& [name, text] : builtinSceneSources()) {
    if (name != nameOrPath) continue;
    return parseSceneJson(text, "", kBuiltinPrefix + name, progress);
  }
  std::string text, error;
  if (!readFile(nameOrPath, text, error)) {
    std::string hint;
    bool looksLikeName = nameOrPath.find('/') == std::string::npos && fs::path(nameOrPath).extension() != ".json";
    if (looksLikeName) {
      std::vector<std::string> names;
      for (const auto& source : builtinSceneSources()) names.push_back(source.first);
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      hint = "; it is not a built-in scene either" + didYouMean(nameOrPath, names) + " (built-in: " + list + ")";
    }
    throwSceneError(nameOrPath, "", "cannot open scene file: " + error + hint);
  }
  return parseSceneJson(text, fs::path(nameOrPath).parent_path().string(), nameOrPath, progress);
}

std::vector<BuiltinSceneInfo> builtinScenes() {
  std::vector<BuiltinSceneInfo> scenes;
  for (const auto& [name, text] : builtinSceneSources()) {
    Json document = parseJsonStrict(text, kBuiltinPrefix + name);
    const Json* description = document.is_object() && document.contains("description") ? &document["description"] : nullptr;
    scenes.push_back({name, description && description->is_string() ? description->get<std::string>() : ""});
  }
  return scenes;
}

}  // namespace vs
