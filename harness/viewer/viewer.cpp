// vshadow view: one GLFW window over the harness's own Runner (the frame pipeline of `vshadow
// run`), PassTimer, reference and error map; a Dear ImGui panel; keys and scripted input.
#include "harness/viewer/viewer.hpp"

#include "harness/gl/gl.hpp"  // GL prototypes first; GLFW must not include another GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "harness/cli/app.hpp"
#include "harness/cli/scene_load.hpp"
#include "harness/evaluation/metrics.hpp"
#include "harness/io/results.hpp"
#include "harness/pipeline/runner.hpp"
#include "scenes/builtin_scenes.hpp"
#include "scenes/content_hash.hpp"
#include "harness/viewer/viewer_input.hpp"

namespace vs {

namespace fs = std::filesystem;
using json = nlohmann::json;

bool viewerAvailable() { return true; }

namespace {

constexpr int kPanelWidth = 360;
constexpr double kLookDegPerPixel = 0.25, kLightDegPerPixel = 0.5;

std::string g_glfwError = "unknown error";
void onGlfwError(int, const char* text) { g_glfwError = text ? text : "unknown error"; }

std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

// GLFW and one window whose OpenGL 4.5 core debug context is current on this thread.
class Window {
 public:
  Window(int width, int height, const std::string& title) {
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit())
      throw std::runtime_error("cannot open a window: " + g_glfwError +
                               " (vshadow view needs an X server; without a display: xvfb-run -a vshadow view ...)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
      std::string error = g_glfwError;
      glfwTerminate();
      throw std::runtime_error("cannot create a window with an OpenGL 4.5 core context: " + error);
    }
    glfwMakeContextCurrent(window_);
  }
  ~Window() {
    gl::releaseSharedObjects();
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
  GLFWwindow* get() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

// Dear ImGui on the window: GLFW input (chained after the viewer's callbacks), OpenGL 3 renderer.
class Gui {
 public:
  explicit Gui(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // writes no imgui.ini
    ImGui::StyleColorsDark();
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true) || !ImGui_ImplOpenGL3_Init("#version 450 core"))
      throw std::runtime_error("cannot initialise Dear ImGui on the window");
  }
  ~Gui() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  Gui(const Gui&) = delete;
  Gui& operator=(const Gui&) = delete;
};

GLuint compileStage(GLenum type, const char* source) {
  GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw gl::GlError("viewer display shader: " + oneLine(log));
  }
  return shader;
}

// Shows a linear image (exposure, clamp, sRGB, as the PNGs) or an already display-coded one.
gl::Program displayProgram() {
  static const char* vertex = R"(#version 450 core
out vec2 uv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  uv = p;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
})";
  static const char* fragment = R"(#version 450 core
layout(binding = 0) uniform sampler2D image;
layout(location = 0) uniform float exposure;
layout(location = 1) uniform int tonemap;
in vec2 uv;
out vec4 colour;
float srgb(float c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055; }
void main() {
  vec3 c = texture(image, vec2(uv.x, 1.0 - uv.y)).rgb;  // row 0 of the upload is the top row
  if (any(isnan(c)) || any(isinf(c))) { colour = vec4(1.0, 0.0, 1.0, 1.0); return; }
  if (tonemap == 1) {
    c = clamp(c * exposure, 0.0, 1.0);
    c = vec3(srgb(c.r), srgb(c.g), srgb(c.b));
  }
  colour = vec4(c, 1.0);
})";
  GLuint vs = compileStage(GL_VERTEX_SHADER, vertex), fs = compileStage(GL_FRAGMENT_SHADER, fragment);
  gl::Program program(glCreateProgram());
  glAttachShader(program.id(), vs);
  glAttachShader(program.id(), fs);
  glLinkProgram(program.id());
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetProgramInfoLog(program.id(), sizeof log, nullptr, log);
    throw gl::GlError("viewer display program: " + oneLine(log));
  }
  return program;
}

size_t countNonFinite(const Image& img) {
  size_t n = 0;
  for (float v : img.rgb) n += std::isfinite(v) ? 0 : 1;
  return n;
}

// Reads one layer (Value) or one bit slice (Bits) of a method's buffer into an image, row 0 = top.
Image readDebugView(const DebugView& view, int layer, int level) {
  GLint target = 0, width = 0, height = 0, depthBits = 0;
  glGetTextureParameteriv(view.texture, GL_TEXTURE_TARGET, &target);
  glGetTextureLevelParameteriv(view.texture, level, GL_TEXTURE_WIDTH, &width);
  glGetTextureLevelParameteriv(view.texture, level, GL_TEXTURE_HEIGHT, &height);
  glGetTextureLevelParameteriv(view.texture, level, GL_TEXTURE_DEPTH_SIZE, &depthBits);
  if (width <= 0 || height <= 0) return {};
  bool layered = target != GL_TEXTURE_2D;
  Image img(width, height);
  size_t texels = size_t(width) * size_t(height);
  if (view.kind == DebugView::Kind::Bits) {
    int z = layered ? layer / 128 : 0, bit = layer % 128;
    std::vector<uint32_t> words(texels * 4);
    glGetTextureSubImage(view.texture, level, 0, 0, z, width, height, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                         GLsizei(words.size() * sizeof(uint32_t)), words.data());
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        uint32_t word = words[(size_t(height - 1 - y) * width + x) * 4 + size_t(bit / 32)];
        float on = (word >> (bit % 32)) & 1u ? 1.0f : 0.0f;
        float* p = img.at(x, y);
        p[0] = p[1] = p[2] = on;
      }
    return img;
  }
  int z = layered ? layer : 0;
  std::vector<float> values(texels * 4);
  if (depthBits > 0) {
    std::vector<float> depth(texels);
    glGetTextureSubImage(view.texture, level, 0, 0, z, width, height, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                         GLsizei(depth.size() * sizeof(float)), depth.data());
    for (size_t i = 0; i < texels; ++i) values[i * 4] = depth[i];
  } else {
    glGetTextureSubImage(view.texture, level, 0, 0, z, width, height, 1, GL_RGBA, GL_FLOAT,
                         GLsizei(values.size() * sizeof(float)), values.data());
  }
  int channels = depthBits > 0 ? 1 : std::clamp(view.channels, 1, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float* v = &values[(size_t(height - 1 - y) * width + x) * 4];
      float* p = img.at(x, y);
      if (channels == 1) p[0] = p[1] = p[2] = v[0];
      else for (int c = 0; c < 3; ++c) p[c] = c < channels ? v[c] : 0.0f;
    }
  return img;
}

// Maps [lo, hi] (auto: the finite range of the image) to [0, 1]; non-finite values stay visible.
Image normalised(const Image& raw, float lo, float hi) {
  if (!(lo < hi)) {
    lo = INFINITY;
    hi = -INFINITY;
    for (float v : raw.rgb)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (!(lo < hi)) hi = lo + 1.0f;
    if (!std::isfinite(lo)) lo = 0.0f, hi = 1.0f;
  }
  Image out = raw;
  for (float& v : out.rgb)
    if (std::isfinite(v)) v = std::clamp((v - lo) / (hi - lo), 0.0f, 1.0f);
  return out;
}

// Non-finite values become 0 in files: they never reach an image on disk.
Image finiteCopy(const Image& img, size_t& replaced) {
  Image out = img;
  replaced = 0;
  for (float& v : out.rgb)
    if (!std::isfinite(v)) v = 0.0f, ++replaced;
  return out;
}

// Scene files get 7 significant digits (float precision), not 0.30000001192092896.
double shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", v);
  return std::stod(text);
}
json vec3Json(const glm::vec3& v) { return json::array({shortNumber(v.x), shortNumber(v.y), shortNumber(v.z)}); }

struct Slot {
  std::string name;
  std::vector<ParamSpec> specs;
  std::map<std::string, std::string> given;  // values as text, every parameter
  ParamValues params;
};

enum class ViewMode { Final, Inscatter, Reference, Error, Buffers };
const char* viewModeName(ViewMode m) {
  switch (m) {
    case ViewMode::Final: return "final image L";
    case ViewMode::Inscatter: return "L_s only";
    case ViewMode::Reference: return "reference";
    case ViewMode::Error: return "|error| vs reference";
    case ViewMode::Buffers: return "method buffers";
  }
  return "?";
}

// What the view shows: the linear image of the mode (written as EXR) and how it is displayed.
struct Shown {
  Image linear;                 // EXR: radiance, |ΔL| per channel, or the buffer's raw values
  Image display;                // shown with `exposure` through the PNG tonemap...
  std::vector<uint8_t> coded;   // ...or already display-coded (the false-colour map), 8-bit RGB
  float exposure = 1.0f;
  std::string label;
};

class Viewer {
 public:
  Viewer(GLFWwindow* window, Scene scene, std::string sceneText, std::vector<Slot> slots, const MethodRegistry& registry,
         const gl::Limits& limits, RunOptions options, const ViewRequest& request)
      : window_(window),
        scene_(std::move(scene)),
        sceneText_(std::move(sceneText)),
        loadedCamera_(scene_.camera),
        loadedLight_(scene_.light),
        loadedHash_(scene_.contentHash),
        slots_(std::move(slots)),
        registry_(registry),
        limits_(limits),
        options_(options),
        request_(request) {
    runner_ = std::make_unique<Runner>(scene_, limits_, options_);
    display_ = displayProgram();
    GLuint id = 0;
    glCreateSamplers(1, &id);
    sampler_ = gl::Sampler(id);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glm::vec3 lo, hi;
    scene_.bounds(lo, hi);
    pivot_ = 0.5f * (lo + hi);
    sceneRadius_ = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
      auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(w));
      if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
      try {
        self->key(key, mods);
      } catch (const std::exception& e) {  // never through GLFW's C frames: shown in the panel
        self->statusText_ = oneLine(e.what());
      }
    });
  }

  bool closing() const { return glfwWindowShouldClose(window_) || quit_; }
  bool failed() const { return anyFailure_; }

  // One frame: input, the method's frame through the runner, the view, the panel, swap.
  void frame() {
    glfwPollEvents();
    pollContinuousInput();
    renderMethod();
    present();
  }

  void key(int key, int mods) {
    (void)mods;
    if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) {
      selectMethod(key - GLFW_KEY_1);
      return;
    }
    switch (key) {
      case GLFW_KEY_F: mode_ = ViewMode::Final; break;
      case GLFW_KEY_L: mode_ = ViewMode::Inscatter; break;
      case GLFW_KEY_R: mode_ = ViewMode::Reference; break;
      case GLFW_KEY_E: mode_ = ViewMode::Error; break;
      case GLFW_KEY_B:
        if (mode_ == ViewMode::Buffers) ++debugIndex_;
        mode_ = ViewMode::Buffers;
        debugLayer_ = debugLevel_ = 0;
        break;
      case GLFW_KEY_COMMA: debugLayer_ = std::max(debugLayer_ - 1, 0); break;
      case GLFW_KEY_PERIOD: ++debugLayer_; break;
      case GLFW_KEY_X: autoExpose(); break;
      case GLFW_KEY_H: panel_ = !panel_; break;
      case GLFW_KEY_P: screenshot(nextName(".png")); break;
      case GLFW_KEY_J: saveScene(nextName(".json")); break;
      case GLFW_KEY_ESCAPE: quit_ = true; break;
      case GLFW_KEY_K: playing_ = !playing_; break;
      case GLFW_KEY_RIGHT: step(1); break;
      case GLFW_KEY_LEFT: step(-1); break;
      case GLFW_KEY_HOME:
        if (moves()) seek(0);
        break;
      default: break;
    }
    shownValid_ = false;
  }

  // Turns the camera as a mouse drag of (dx, dy) pixels.
  void look(double dx, double dy) {
    Camera& c = scene_.camera;
    glm::vec3 up = glm::normalize(c.up);
    glm::vec3 offset = c.target - c.position;
    float distance = std::max(glm::length(offset), 1e-4f);
    glm::vec3 forward = offset / distance;
    forward = glm::angleAxis(float(glm::radians(-dx * kLookDegPerPixel)), up) * forward;
    glm::vec3 right = glm::cross(forward, up);
    if (glm::length(right) > 1e-6f) {
      right = glm::normalize(right);
      glm::vec3 pitched = glm::angleAxis(float(glm::radians(-dy * kLookDegPerPixel)), right) * forward;
      if (std::fabs(glm::dot(pitched, up)) < 0.995f) forward = pitched;  // never over the pole
    }
    c.target = c.position + glm::normalize(forward) * distance;
    viewChanged();
  }

  // Flies the camera by (forward, right, up) scene units.
  void move(double forward, double right, double up) {
    Camera& c = scene_.camera;
    glm::vec3 f = glm::normalize(c.target - c.position), u = glm::normalize(c.up);
    glm::vec3 r = glm::cross(f, u);
    r = glm::length(r) > 1e-6f ? glm::normalize(r) : glm::vec3(1, 0, 0);
    glm::vec3 step = f * float(forward) + r * float(right) + u * float(up);
    c.position += step;
    c.target += step;
    viewChanged();
  }

  // Orbits the light about the scene's centre as a right-button drag of (dx, dy) pixels; spot,
  // directional and area lights turn with it.
  void dragLight(double dx, double dy) {
    Light& l = scene_.light;
    glm::vec3 up = glm::normalize(scene_.camera.up);
    glm::quat yaw = glm::angleAxis(float(glm::radians(-dx * kLightDegPerPixel)), up);
    glm::vec3 arm = l.type == LightType::Directional ? -l.direction : l.position - pivot_;
    glm::vec3 right = glm::cross(arm, up);
    glm::quat pitch = glm::length(right) > 1e-6f
                          ? glm::angleAxis(float(glm::radians(dy * kLightDegPerPixel)), glm::normalize(right))
                          : glm::quat(1, 0, 0, 0);
    glm::vec3 pitchedArm = pitch * arm;
    if (glm::length(glm::cross(pitchedArm, up)) < 0.02f * glm::length(pitchedArm)) pitch = glm::quat(1, 0, 0, 0);
    glm::quat rotation = yaw * pitch;
    l.position = pivot_ + rotation * (l.position - pivot_);
    l.direction = glm::normalize(rotation * l.direction);
    l.tangent = rotation * l.tangent;
    lightMoved_ = true;
    viewChanged();
  }

  // Sets a parameter of the current method; UsageError for an unknown key or a bad value.
  void setParam(const std::string& key, const std::string& value) {
    Slot& s = slots_[size_t(current_)];
    auto given = s.given;
    given[key] = value;
    s.params = ParamValues::parse(s.name, s.specs, given);
    s.given = given;
    needsSetup_ = true;
  }

  // A moving scene's playback: the frame of the sequence shown, playing or paused. seek and step
  // pause; UsageError for a frame outside the sequence or a scene that does not move.
  void seek(int frame) {
    if (!moves()) throw UsageError("seek: scene " + scene_.name + " does not move");
    const int frames = scene_.animation.frameCount();
    if (frame < 0 || frame >= frames)
      throw UsageError("seek " + std::to_string(frame) + ": the sequence has frames 0 to " + std::to_string(frames - 1));
    playing_ = false;
    showFrame(uint32_t(frame));
  }
  void step(int delta) {
    if (!moves()) return;
    const int frames = scene_.animation.frameCount();
    playing_ = false;
    showFrame(uint32_t(((int(sequenceFrame_) + delta) % frames + frames) % frames));
  }

  void selectMethod(int index) {
    if (index < 0 || index >= int(slots_.size()) || index == current_) return;
    current_ = index;
    needsSetup_ = true;
    debugIndex_ = debugLayer_ = debugLevel_ = 0;
  }

  // FILE.png (what the view shows) and FILE.exr (its linear image), written atomically.
  void screenshot(const std::string& path) {
    fs::path p(path);
    std::string ext = p.extension().string();
    if (ext != ".png" && ext != ".exr") throw UsageError("screenshot " + path + ": expected a .png or .exr file name");
    const Shown& s = shown();
    if (s.linear.empty())
      throw std::runtime_error("screenshot " + path + ": nothing to save (" +
                               (!failure_.empty() ? failure_ : !unsupported_.empty() ? unsupported_ : "no image") + ")");
    std::string stem = (p.parent_path() / p.stem()).string();
    if (!p.parent_path().empty()) fs::create_directories(p.parent_path());
    size_t replaced = 0;
    writeExr(stem + ".exr", finiteCopy(s.linear, replaced));
    if (!s.coded.empty()) writePng8(stem + ".png", s.linear.width, s.linear.height, s.coded);
    else writePngTonemapped(stem + ".png", s.display, s.exposure);
    if (replaced > 0) std::fprintf(stderr, "vshadow view: %zu non-finite values written as 0 in %s.exr\n", replaced, stem.c_str());
    std::fprintf(stderr, "vshadow view: wrote %s.png and %s.exr (%s)\n", stem.c_str(), stem.c_str(), s.label.c_str());
  }

  // The scene file with the current camera and light: a view becomes a benchmark scene.
  void saveScene(const std::string& path) {
    json doc = json::parse(sceneText_);
    const Camera& c = scene_.camera;
    json camera = doc.value("camera", json::object());
    camera["position"] = vec3Json(c.position);
    camera["target"] = vec3Json(c.target);
    camera["up"] = vec3Json(c.up);
    doc["camera"] = camera;
    const Light& l = scene_.light;
    json light = doc.contains("light") ? doc["light"] : json{{"type", lightTypeName(l.type)}, {"intensity", l.intensity},
                                                            {"color", vec3Json(l.color)}};
    light.erase("target");
    if (l.type == LightType::Directional) {
      light.erase("position");
    } else {
      light["position"] = vec3Json(l.position);
    }
    if (l.type != LightType::Point) light["direction"] = vec3Json(l.direction);
    if (l.type == LightType::Rect && light.contains("tangent")) light["tangent"] = vec3Json(l.tangent);
    doc["light"] = light;
    // Relative file names are relative to the scene file: keep them pointing at the same files.
    bool fromFile = scene_.source.rfind("builtin:", 0) != 0;
    fs::path outDir = fs::absolute(fs::path(path)).parent_path();
    auto rebase = [&](json& holder, const char* key) {
      if (!fromFile || !holder.is_object() || !holder.contains(key) || !holder[key].is_string()) return;
      fs::path file(holder[key].get<std::string>());
      if (file.is_absolute()) return;
      fs::path original = fs::absolute(fs::path(scene_.source).parent_path() / file);
      holder[key] = fs::relative(original, outDir).generic_string();
    };
    if (doc.contains("geometry") && doc["geometry"].is_array())
      for (json& g : doc["geometry"]) rebase(g, "gltf"), rebase(g, "obj");
    if (doc.contains("volumes") && doc["volumes"].is_array())
      for (json& v : doc["volumes"]) rebase(v, "raw");
    rebase(doc["light"], "texture");
    if (!outDir.empty()) fs::create_directories(outDir);
    writeFileAtomic(path, doc.dump(2) + "\n");
    std::fprintf(stderr, "vshadow view: wrote %s (camera and light of the view)\n", path.c_str());
  }

 private:
  Slot& slot() { return slots_[size_t(current_)]; }
  bool moves() const { return scene_.animation.moves(); }
  void showFrame(uint32_t frame) {
    if (frame == sequenceFrame_) return;
    sequenceFrame_ = frame;
    viewChanged();  // the reference is that of the frame's time
  }

  void viewChanged() {
    reference_.reset();
    shownValid_ = false;
  }

  std::string nextName(const std::string& ext) {
    for (int i = 1;; ++i) {
      char name[64];
      std::snprintf(name, sizeof name, "view-%03d", i);
      fs::path p = fs::path(request_.out) / (scene_.name + "-" + name + ext);
      if (!fs::exists(p)) return p.string();
    }
  }

  void autoExpose() {
    if (reference_) exposure_ = autoExposure(reference_->final);
    else if (!final_.empty()) exposure_ = autoExposure(final_);
    exposureSet_ = true;
  }

  // Fresh instance, set up for the current parameters, light and shadow-map size (as run does).
  void setUp() {
    needsSetup_ = false;
    method_.reset();
    failure_.clear();
    unsupported_.clear();
    final_ = inscatter_ = Image();
    shownValid_ = false;
    timer_ = std::make_unique<PassTimer>(options_.timer);
    frameIndex_ = 0;
    Slot& s = slot();
    auto method = createMethod(registry_, s.name);
    unsupported_ = runner_->unsupportedReason(*method, s.params);
    if (!unsupported_.empty()) return;
    gl::resetDebugErrorCount();
    try {
      setupMs_ = runner_->setUp(*method, s.params);
      if (gl::debugErrorCount() > 0) throw std::runtime_error("GL error: " + gl::lastDebugError());
      method_ = std::move(method);
    } catch (const std::exception& e) {
      fail(std::string("setup: ") + e.what());
    }
  }

  void fail(const std::string& reason) {
    failure_ = oneLine(reason);
    anyFailure_ = true;
    method_.reset();
    std::fprintf(stderr, "vshadow view: %s %s failed: %s\n", slot().name.c_str(), slot().params.canonical().c_str(),
                 failure_.c_str());
  }

  void renderMethod() {
    if (lightMoved_) {
      lightMoved_ = false;
      runner_->shared().lightMoved();
      needsSetup_ = true;  // methods build light-space structures in setup
    }
    if (needsSetup_) setUp();
    if (!method_) return;
    // A moving scene plays its sequence, one frame of it per rendered frame, the frames numbered as
    // `vshadow run` numbers them; paused, the same frame is rendered again.
    if (moves() && playing_ && renderedFrames_ > 0)
      showFrame((sequenceFrame_ + 1) % uint32_t(scene_.animation.frameCount()));
    const uint32_t index = moves() ? sequenceFrame_ : frameIndex_++;
    gl::resetDebugErrorCount();
    try {
      runner_->renderFrame(*method_, *timer_, index);
      ++renderedFrames_;
      gl::checkErrors("frame");
      final_ = runner_->shared().readFinal();
      inscatter_ = runner_->shared().readInscatter();
      if (gl::debugErrorCount() > 0) throw std::runtime_error("GL error: " + gl::lastDebugError());
      nonFinite_ = countNonFinite(final_) + countNonFinite(inscatter_);
      if (!exposureSet_) autoExpose();
      shownValid_ = false;
    } catch (const std::exception& e) {
      fail(e.what());
    }
    if (timer_->samples().count(PassTimer::kFrame) && timer_->samples().at(PassTimer::kFrame).size() > 10000)
      timer_ = std::make_unique<PassTimer>(options_.timer);  // bounded memory in long sessions
  }

  // The reference for the current view: cached on disk by the scene's hash, which covers the
  // camera and light once they differ from the file's.
  const Reference& reference() {
    if (reference_) return *reference_;
    const Camera& c0 = loadedCamera_;
    bool moved = scene_.camera.position != c0.position || scene_.camera.target != c0.target ||
                 scene_.camera.up != c0.up || scene_.light.position != loadedLight_.position ||
                 scene_.light.direction != loadedLight_.direction || scene_.light.tangent != loadedLight_.tangent;
    scene_.contentHash = loadedHash_;
    if (moved) {
      ContentHasher hasher;
      hasher.addBlock(loadedHash_);
      const Camera& c = scene_.camera;
      const Light& l = scene_.light;
      const float values[] = {c.position.x, c.position.y, c.position.z, c.target.x,    c.target.y,   c.target.z,
                              c.up.x,       c.up.y,       c.up.z,       l.position.x,  l.position.y, l.position.z,
                              l.direction.x, l.direction.y, l.direction.z, l.tangent.x, l.tangent.y, l.tangent.z};
      hasher.addBlock(values, sizeof values);
      scene_.contentHash = hasher.hex();
    }
    int sm = 64;
    for (const Slot& s : slots_) sm = std::max(sm, s.params.getInt("sm"));
    const std::string cacheDir = request_.cacheDir.empty() ? defaultCacheDir() : request_.cacheDir;
    if (moves()) {
      const double t = scene_.animation.timeOf(sequenceFrame_);
      std::fprintf(stderr, "vshadow view: computing the reference for frame %u (t = %g s)...\n", sequenceFrame_, t);
      reference_ = obtainReference(sceneAt(scene_, t), limits_, options_, sm, cacheDir, registry_);
    } else {
      std::fprintf(stderr, "vshadow view: computing the reference for this view...\n");
      reference_ = obtainReference(scene_, limits_, options_, sm, cacheDir, registry_);
    }
    referenceExposure_ = autoExposure(reference_->final);
    if (!exposureManual_) exposure_ = referenceExposure_, exposureSet_ = true;
    return *reference_;
  }

  std::vector<DebugView> debugViews() const {
    std::vector<DebugView> views;
    if (!method_) return views;
    if (!runner_->effects().scattering || method_->needsSharedShadowMap()) {
      const ShadowMap& sm = runner_->shared().shadowMap();
      DebugView v;
      v.name = "shadow map (shared)";
      v.texture = sm.depth.id();
      v.layers = sm.type == LightType::Point ? 6 : 1;
      views.push_back(v);
    }
    for (DebugView& v : method_->debugViews()) views.push_back(std::move(v));
    return views;
  }

  const Shown& shown() {
    if (shownValid_) return shown_;
    shownValid_ = true;
    shown_ = Shown();
    if (final_.empty() && mode_ != ViewMode::Reference) return shown_;
    switch (mode_) {
      case ViewMode::Final:
        shown_.linear = final_;
        break;
      case ViewMode::Inscatter:
        shown_.linear = inscatter_;
        break;
      case ViewMode::Reference:
        shown_.linear = reference().final;
        break;
      case ViewMode::Error: {
        const Image& ref = reference().final;
        shown_.coded = falseColourError(final_, ref, 0.1f / std::max(referenceExposure_, 1e-20f));
        shown_.linear = final_;
        for (size_t i = 0; i < shown_.linear.rgb.size(); ++i)
          shown_.linear.rgb[i] = std::fabs(final_.rgb[i] - ref.rgb[i]);
        ErrorMetrics m = compareImages(final_, ref);
        ErrorMetrics ls = compareImages(inscatter_, reference().inscatter);
        errorText_ = (moves() ? "frame " + std::to_string(sequenceFrame_) + ": " : std::string()) + "L_s rmse " +
                     num(ls.rmse) + "  relmse " + num(ls.relmse) + "; L rmse " + num(m.rmse) + "  psnr " + num(m.psnr) +
                     " dB  ssim " + num(m.ssim);
        break;
      }
      case ViewMode::Buffers: {
        auto views = debugViews();
        if (views.empty()) {
          shown_.label = "no buffers";
          return shown_;
        }
        debugIndex_ = ((debugIndex_ % int(views.size())) + int(views.size())) % int(views.size());
        const DebugView& v = views[size_t(debugIndex_)];
        debugLayer_ = std::clamp(debugLayer_, 0, std::max(v.layers - 1, 0));
        debugLevel_ = std::clamp(debugLevel_, 0, std::max(v.levels - 1, 0));
        shown_.linear = readDebugView(v, debugLayer_, debugLevel_);
        shown_.display = normalised(shown_.linear, v.lo, v.hi);
        shown_.exposure = 1.0f;
        shown_.label = v.name + " layer " + std::to_string(debugLayer_) + " level " + std::to_string(debugLevel_);
        return shown_;
      }
    }
    shown_.display = shown_.linear;
    shown_.exposure = exposure_;
    shown_.label = std::string(viewModeName(mode_));
    return shown_;
  }

  void pollContinuousInput() {
    auto now = std::chrono::steady_clock::now();
    double dt = std::min(std::chrono::duration<double>(now - lastPoll_).count(), 0.1);
    lastPoll_ = now;
    ImGuiIO& io = ImGui::GetIO();
    if (!io.WantCaptureKeyboard) {
      auto down = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS ? 1.0 : 0.0; };
      double speed = 0.5 * sceneRadius_ * dt * (down(GLFW_KEY_LEFT_SHIFT) ? 4.0 : 1.0);
      double f = down(GLFW_KEY_W) - down(GLFW_KEY_S), r = down(GLFW_KEY_D) - down(GLFW_KEY_A);
      double u = down(GLFW_KEY_SPACE) - down(GLFW_KEY_C);
      if (f != 0 || r != 0 || u != 0) move(f * speed, r * speed, u * speed);
    }
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if ((left || right) && !dragging_ && !io.WantCaptureMouse) dragging_ = true;
    if (!left && !right) dragging_ = false;
    if (dragging_ && (x != cursorX_ || y != cursorY_)) {
      if (left) look(x - cursorX_, y - cursorY_);
      else if (right) dragLight(x - cursorX_, y - cursorY_);
    }
    cursorX_ = x;
    cursorY_ = y;
  }

  void upload(const Shown& s) {
    int w = s.linear.width, h = s.linear.height;
    if (w == 0) return;
    if (w != textureW_ || h != textureH_) {
      texture_ = gl::createTexture2D(GL_RGBA32F, w, h);
      textureW_ = w;
      textureH_ = h;
    }
    std::vector<float> rgba(size_t(w) * h * 4, 1.0f);
    for (size_t i = 0; i < size_t(w) * h; ++i)
      for (int c = 0; c < 3; ++c)
        rgba[i * 4 + c] = s.coded.empty() ? s.display.rgb[i * 3 + c] : float(s.coded[i * 3 + c]) / 255.0f;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture_.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
  }

  void present() {
    try {
      bool fresh = !shownValid_;
      const Shown& s = shown();
      if (fresh) upload(s);
    } catch (const std::exception& e) {
      statusText_ = oneLine(e.what());  // e.g. the reference failed: shown in the panel
      mode_ = ViewMode::Final;
      shownValid_ = false;
    }
    int fbW = 0, fbH = 0;
    glfwGetFramebufferSize(window_, &fbW, &fbH);
    gl::resetPipelineState();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fbW, fbH);
    glClearColor(0.12f, 0.12f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    int left = panel_ ? kPanelWidth : 0;
    if (texture_ && !shown_.linear.empty() && fbW > left && fbH > 0) {
      double scale = std::min(double(fbW - left) / textureW_, double(fbH) / textureH_);
      int w = std::max(1, int(textureW_ * scale)), h = std::max(1, int(textureH_ * scale));
      glViewport(left + (fbW - left - w) / 2, (fbH - h) / 2, w, h);
      glUseProgram(display_.id());
      glBindTextureUnit(0, texture_.id());
      glBindSampler(0, sampler_.id());
      glUniform1f(0, shown_.exposure);
      glUniform1i(1, shown_.coded.empty() ? 1 : 0);
      gl::drawFullscreenTriangle();
      glBindSampler(0, 0);
      glViewport(0, 0, fbW, fbH);
    }
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (panel_) drawPanel(fbH);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(window_);
    gl::resetPipelineState();
  }

  // The panel, top to bottom: what is shown, playback, status, timings, parameters, camera and
  // light, the save buttons.
  void drawPanel(int height) {
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(height)));
    ImGui::Begin("vshadow", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::Text("scene %s  %dx%d", scene_.name.c_str(), options_.width, options_.height);
    ImGui::TextWrapped("effects: %s", runner_->effects().describe().c_str());
    drawMethodAndMode();
    if (mode_ == ViewMode::Buffers) drawBufferChoice();
    if (moves()) drawPlayback();
    if (ImGui::SliderFloat("exposure", &exposure_, 1e-4f, 1e4f, "%.4g", ImGuiSliderFlags_Logarithmic)) {
      exposureManual_ = exposureSet_ = true;
      shownValid_ = false;
    }
    drawStatus();
    if (ImGui::CollapsingHeader("timings (median of the last 30 frames)", ImGuiTreeNodeFlags_DefaultOpen) && timer_)
      drawTimings();
    if (ImGui::CollapsingHeader("parameters", ImGuiTreeNodeFlags_DefaultOpen)) drawParams();
    if (ImGui::CollapsingHeader("camera and light")) drawCameraAndLight();
    try {
      if (ImGui::Button("screenshot (P)")) screenshot(nextName(".png"));
      ImGui::SameLine();
      if (ImGui::Button("save scene (J)")) saveScene(nextName(".json"));
    } catch (const std::exception& e) {
      statusText_ = oneLine(e.what());
    }
    ImGui::End();
  }

  // The method (keys 1-9) and the view mode (F, L, R, E, B).
  void drawMethodAndMode() {
    if (ImGui::BeginCombo("method", (std::to_string(current_ + 1) + " " + slot().name).c_str())) {
      for (int i = 0; i < int(slots_.size()); ++i)
        if (ImGui::Selectable((std::to_string(i + 1) + " " + slots_[size_t(i)].name).c_str(), i == current_)) selectMethod(i);
      ImGui::EndCombo();
    }
    int mode = int(mode_);
    const char* modes[] = {"final (F)", "L_s (L)", "reference (R)", "|error| (E)", "buffers (B)"};
    for (int i = 0; i < 5; ++i) {
      if (ImGui::RadioButton(modes[i], &mode, i)) {
        mode_ = ViewMode(mode);
        shownValid_ = false;
      }
      if (i % 3 != 2 && i != 4) ImGui::SameLine();
    }
  }

  // Which of the method's buffers, its layer (or bit) and level; then what is shown.
  void drawBufferChoice() {
    auto views = debugViews();
    if (!views.empty()) {
      int index = ((debugIndex_ % int(views.size())) + int(views.size())) % int(views.size());
      if (ImGui::BeginCombo("buffer", views[size_t(index)].name.c_str())) {
        for (int i = 0; i < int(views.size()); ++i)
          if (ImGui::Selectable(views[size_t(i)].name.c_str(), i == index)) debugIndex_ = i, debugLayer_ = debugLevel_ = 0, shownValid_ = false;
        ImGui::EndCombo();
      }
      const DebugView& v = views[size_t(index)];
      if (v.layers > 1 && ImGui::SliderInt(v.kind == DebugView::Kind::Bits ? "bit (,/.)" : "layer (,/.)", &debugLayer_, 0, v.layers - 1))
        shownValid_ = false;
      if (v.levels > 1 && ImGui::SliderInt("level", &debugLevel_, 0, v.levels - 1)) shownValid_ = false;
    }
    ImGui::TextWrapped("%s", shown_.label.c_str());
  }

  // A moving scene's frame and time, play/pause, step and seek.
  void drawPlayback() {
    const int frames = scene_.animation.frameCount();
    ImGui::Text("frame %u of %d, t = %.3f s  %s", sequenceFrame_, frames, scene_.animation.timeOf(sequenceFrame_),
                playing_ ? "playing" : "paused");
    if (ImGui::Button(playing_ ? "pause (K)" : "play (K)")) playing_ = !playing_;
    ImGui::SameLine();
    if (ImGui::Button("<")) step(-1);
    ImGui::SameLine();
    if (ImGui::Button(">")) step(1);
    ImGui::SameLine();
    int frame = int(sequenceFrame_);
    if (ImGui::SliderInt("##frame", &frame, 0, frames - 1, "frame %d", ImGuiSliderFlags_AlwaysClamp)) seek(frame);
  }

  // The error against the reference, then what went wrong, each only when there is something.
  void drawStatus() {
    if (mode_ == ViewMode::Error && reference_) ImGui::TextWrapped("%s", errorText_.c_str());
    if (!unsupported_.empty()) ImGui::TextColored(ImVec4(1, 0.7f, 0.3f, 1), "unsupported: %s", unsupported_.c_str());
    if (!failure_.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "failed: %s", failure_.c_str());
    if (nonFinite_ > 0) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%zu non-finite values (magenta)", nonFinite_);
    if (!statusText_.empty()) ImGui::TextWrapped("%s", statusText_.c_str());
  }

  // Each pass's median over the last 30 frames; * marks the passes of the scattering time.
  void drawTimings() {
    ImGui::Text("timer %s, setup %.1f ms", timerStrategyName(timer_->strategy()), setupMs_);
    const std::vector<std::string> surface = method_ ? method_->surfacePasses() : std::vector<std::string>{};
    for (const std::string& pass : timer_->passOrder()) {
      const auto& all = timer_->samples().at(pass);
      std::vector<double> last(all.end() - std::min<ptrdiff_t>(30, ptrdiff_t(all.size())), all.end());
      if (last.empty()) continue;
      TimingStats s = summarise(last);
      ImGui::Text("%-22s %9.2f ms%s", pass.c_str(), s.medianMs, isScatteringPass(pass, surface) ? " *" : "");
    }
  }

  void drawCameraAndLight() {
    const Camera& c = scene_.camera;
    const Light& l = scene_.light;
    ImGui::Text("eye    %.3f %.3f %.3f", c.position.x, c.position.y, c.position.z);
    ImGui::Text("target %.3f %.3f %.3f", c.target.x, c.target.y, c.target.z);
    ImGui::Text("light  %s %.3f %.3f %.3f", lightTypeName(l.type), l.position.x, l.position.y, l.position.z);
    ImGui::TextWrapped("WASD/Space/C fly (Shift fast), left drag look, right drag moves the light");
    if (moves()) ImGui::TextWrapped("K play/pause, Left/Right step a frame, Home first frame");
  }

  // One widget per ParamSpec, within its range; applied when the edit is finished.
  void drawParams() {
    Slot& s = slot();
    for (const ParamSpec& p : s.specs) {
      std::string value = s.given.count(p.name) ? s.given.at(p.name) : p.defaultValue;
      std::string next = value;
      bool commit = false;
      ImGui::PushID(p.name.c_str());
      switch (p.kind) {
        case ParamSpec::Kind::Bool: {
          bool on = value == "1" || value == "true";
          if (ImGui::Checkbox(p.name.c_str(), &on)) next = on ? "1" : "0", commit = true;
          break;
        }
        case ParamSpec::Kind::Choice: {
          if (ImGui::BeginCombo(p.name.c_str(), value.c_str())) {
            for (const std::string& c : p.choices)
              if (ImGui::Selectable(c.c_str(), c == value)) next = c, commit = true;
            ImGui::EndCombo();
          }
          break;
        }
        case ParamSpec::Kind::Int: {
          int lo = int(p.min), hi = int(p.max);
          if (p.powerOfTwo) {
            int e = int(std::lround(std::log2(std::max(1.0, std::stod(value)))));
            int elo = int(std::ceil(std::log2(std::max(1, lo)))), ehi = int(std::floor(std::log2(std::max(1, hi))));
            ImGui::SliderInt(p.name.c_str(), &e, elo, ehi, std::to_string(1 << std::clamp(e, elo, ehi)).c_str(),
                             ImGuiSliderFlags_AlwaysClamp);
            next = std::to_string(1 << std::clamp(e, elo, ehi));
          } else {
            int v = std::stoi(value);
            ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp;
            if (lo > 0 && hi / std::max(lo, 1) > 100) flags |= ImGuiSliderFlags_Logarithmic;
            ImGui::SliderInt(p.name.c_str(), &v, lo, hi, "%d", flags);
            next = std::to_string(std::clamp(v, lo, hi));
          }
          commit = ImGui::IsItemDeactivatedAfterEdit();
          break;
        }
        case ParamSpec::Kind::Float: {
          float v = std::stof(value), lo = float(p.min), hi = float(p.max);
          ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp;
          if (lo > 0 && hi / lo > 100) flags |= ImGuiSliderFlags_Logarithmic;
          ImGui::SliderFloat(p.name.c_str(), &v, lo, hi, "%.4g", flags);
          std::ostringstream text;
          text << std::clamp(v, lo, hi);
          next = text.str();
          commit = ImGui::IsItemDeactivatedAfterEdit();
          break;
        }
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s (%s)", p.description.c_str(), p.rangeText().c_str());
      ImGui::PopID();
      if (commit && next != value) {
        try {
          setParam(p.name, next);
          statusText_.clear();
        } catch (const UsageError& e) {
          statusText_ = e.what();
        }
      }
    }
  }

  GLFWwindow* window_;
  Scene scene_;
  std::string sceneText_;
  Camera loadedCamera_;
  Light loadedLight_;
  std::string loadedHash_;
  std::vector<Slot> slots_;
  const MethodRegistry& registry_;
  const gl::Limits& limits_;
  RunOptions options_;
  const ViewRequest& request_;
  std::unique_ptr<Runner> runner_;
  std::unique_ptr<Method> method_;
  std::unique_ptr<PassTimer> timer_;
  int current_ = 0;
  bool needsSetup_ = true, lightMoved_ = false, quit_ = false, anyFailure_ = false, panel_ = true;
  uint32_t frameIndex_ = 0;         // a still scene's frames
  uint32_t sequenceFrame_ = 0;      // a moving scene's frame shown
  uint64_t renderedFrames_ = 0;
  bool playing_ = true;
  double setupMs_ = 0;
  std::string failure_, unsupported_, statusText_, errorText_;
  Image final_, inscatter_;
  size_t nonFinite_ = 0;
  std::optional<Reference> reference_;
  float referenceExposure_ = 1.0f, exposure_ = 1.0f;
  bool exposureSet_ = false, exposureManual_ = false;
  ViewMode mode_ = ViewMode::Final;
  int debugIndex_ = 0, debugLayer_ = 0, debugLevel_ = 0;
  Shown shown_;
  bool shownValid_ = false;
  glm::vec3 pivot_{0};
  float sceneRadius_ = 1.0f;
  std::chrono::steady_clock::time_point lastPoll_ = std::chrono::steady_clock::now();
  double cursorX_ = 0, cursorY_ = 0;
  bool dragging_ = false;
  gl::Program display_;
  gl::Sampler sampler_;
  gl::Texture texture_;
  int textureW_ = 0, textureH_ = 0;
};

std::string sceneSourceText(const Scene& scene) {
  const std::string prefix = "builtin:";
  if (scene.source.rfind(prefix, 0) == 0) {
    for (const auto& [name, text] : builtinSceneSources())
      if (prefix + name == scene.source) return text;
  }
  std::ifstream in(scene.source, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void checkScreenshotName(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (ext != ".png" && ext != ".exr") throw UsageError("--screenshot " + path + ": expected a .png or .exr file name");
}

// What the view opens with, checked before a window opens.
struct ViewInput {
  int width = 0, height = 0;
  Scene scene;
  std::string sceneText;           // the scene file's text, for saving a view as a scene
  std::vector<std::string> specs;  // every registered method when none is given
  std::vector<ScriptCommand> script;
};

// Bad input is caught before a window opens: size, scene, methods and their parameters, script,
// screenshot name.
ViewInput checkedInput(const ViewRequest& req, const MethodRegistry& registry) {
  ViewInput in;
  parseSize(req.size, in.width, in.height);
  SceneLoad loaded;
  in.scene = loadSceneMeasured(req.scene, loaded);  // a bar on a terminal while a large scene loads
  in.specs = req.methods;
  if (in.specs.empty())
    for (const auto& info : registry) in.specs.push_back(info.name);
  for (const std::string& text : in.specs) {
    MethodSpec spec = parseMethodSpec(text);
    auto method = createMethod(registry, spec.method);
    ParamValues::parse(spec.method, allParams(*method, 16384), spec.params);
  }
  if (in.specs.size() > 9)
    throw UsageError("vshadow view takes at most 9 methods (keys 1-9); got " + std::to_string(in.specs.size()));
  if (!req.script.empty()) in.script = readScript(req.script);
  if (!req.screenshot.empty()) checkScreenshotName(req.screenshot);
  in.sceneText = sceneSourceText(in.scene);
  return in;
}

// What needs the window's context: the size and the scene's volumes within this GL's limits.
void checkLimits(const ViewRequest& req, const ViewInput& in, const gl::Limits& limits) {
  int maxSize = std::min({limits.maxTextureSize, limits.maxRenderbufferSize, limits.maxViewportW, limits.maxViewportH});
  if (in.width > maxSize || in.height > maxSize)
    throw UsageError("--size " + req.size + " exceeds this GL implementation's limit of " + std::to_string(maxSize) +
                     " pixels per side");
  std::string volumeProblem = volumeLimitProblem(in.scene, limits);
  if (!volumeProblem.empty()) throw UsageError(in.scene.source + ": " + volumeProblem);
}

// One slot per method (keys 1-9): its parameters resolved against the limits.
std::vector<Slot> methodSlots(const std::vector<std::string>& specs, const gl::Limits& limits,
                              const MethodRegistry& registry) {
  int maxShadow = std::min(limits.maxTextureSize, limits.maxCubeMapSize);
  std::vector<Slot> slots;
  for (const std::string& text : specs) {
    ResolvedSpec resolved = resolveSpec(text, limits, registry);
    Slot s;
    s.name = resolved.method;
    s.specs = allParams(*createMethod(registry, s.name), maxShadow);
    for (const auto& [k, v] : resolved.params.items()) s.given[k] = v;
    s.params = resolved.params;
    slots.push_back(std::move(s));
  }
  return slots;
}

RunOptions viewOptions(const ViewRequest& req, int width, int height) {
  RunOptions options;
  options.width = width;
  options.height = height;
  options.seed = uint32_t(req.seed);
  if (req.timer == "auto") options.timer = calibrateTimer().chosen;
  else options.timer = req.timer == "gpu" ? TimerStrategy::GpuTimestamp : TimerStrategy::WallClock;
  return options;
}

// One script command; false when it quits.
bool runScriptCommand(Viewer& viewer, const ScriptCommand& c) {
  switch (c.op) {
    case ScriptCommand::Op::Frames:
      for (int i = 0; i < c.count && !viewer.closing(); ++i) viewer.frame();
      break;
    case ScriptCommand::Op::Key:
      for (int key : c.keys) viewer.key(key, 0);
      break;
    case ScriptCommand::Op::Look: viewer.look(c.x, c.y); break;
    case ScriptCommand::Op::Light: viewer.dragLight(c.x, c.y); break;
    case ScriptCommand::Op::Move: viewer.move(c.x, c.y, c.z); break;
    case ScriptCommand::Op::Param: viewer.setParam(c.key, c.value); break;
    case ScriptCommand::Op::Seek: viewer.seek(c.count); break;
    case ScriptCommand::Op::Screenshot: viewer.screenshot(c.value); break;
    case ScriptCommand::Op::Scene: viewer.saveScene(c.value); break;
    case ScriptCommand::Op::Quit: return false;
  }
  return true;
}

// The script (an error names its line), then --frames and --screenshot. Returns the exit status.
int runAutomated(Viewer& viewer, const std::vector<ScriptCommand>& script, const ViewRequest& req) {
  for (const ScriptCommand& c : script) {
    if (viewer.closing()) break;
    try {
      if (!runScriptCommand(viewer, c)) return viewer.failed() ? 3 : 0;
    } catch (const UsageError& e) {
      throw UsageError(c.where + ": " + e.what());
    } catch (const std::exception& e) {
      throw std::runtime_error(c.where + ": " + e.what());
    }
  }
  for (int i = 0; i < req.frames && !viewer.closing(); ++i) viewer.frame();
  if (!req.screenshot.empty()) viewer.screenshot(req.screenshot);
  return viewer.failed() ? 3 : 0;
}

int viewChecked(const ViewRequest& req, const MethodRegistry& registry) {
  ViewInput in = checkedInput(req, registry);
  Window window(in.width + kPanelWidth, std::max(in.height, 600), "vshadow view: " + in.scene.name);
  gl::installDebugOutput(req.strictGl);
  gl::Limits limits = gl::queryLimits();
  checkLimits(req, in, limits);
  std::vector<Slot> slots = methodSlots(in.specs, limits, registry);
  RunOptions options = viewOptions(req, in.width, in.height);

  bool automated = !in.script.empty() || req.frames > 0;
  glfwSwapInterval(automated ? 0 : 1);
  // The viewer's callbacks first: Dear ImGui chains them after its own.
  Viewer viewer(window.get(), std::move(in.scene), std::move(in.sceneText), std::move(slots), registry, limits, options,
                req);
  Gui gui(window.get());
  if (automated) return runAutomated(viewer, in.script, req);
  while (!viewer.closing()) viewer.frame();
  return 0;
}

}  // namespace

int viewCommand(const ViewRequest& request, const MethodRegistry& registry) {
  return reportingErrors([&] { return viewChecked(request, registry); });
}

}  // namespace vs
