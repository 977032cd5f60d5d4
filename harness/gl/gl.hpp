// Shared OpenGL helpers: the one place every method gets GL objects, shaders and debug output from.
#pragma once
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/gl/bindings.hpp"

namespace vs::gl {

struct GlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Move-only owner of one GL name; Deleter frees it.
template <void (*Deleter)(GLuint)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(GLuint id) : id_(id) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  void reset() {
    if (id_) Deleter(id_);
    id_ = 0;
  }
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }

 private:
  GLuint id_ = 0;
};

void deleteBuffer(GLuint id);
void deleteTexture(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteProgram(GLuint id);
void deleteQuery(GLuint id);
void deleteSampler(GLuint id);

using Buffer = Handle<deleteBuffer>;
using Texture = Handle<deleteTexture>;
using Framebuffer = Handle<deleteFramebuffer>;
using VertexArray = Handle<deleteVertexArray>;
using Program = Handle<deleteProgram>;
using Query = Handle<deleteQuery>;
using Sampler = Handle<deleteSampler>;

Buffer createBuffer(size_t bytes, const void* data = nullptr, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
Texture createTexture2D(GLenum internalFormat, int width, int height, int levels = 1);
Texture createTextureCube(GLenum internalFormat, int size);
Texture createTexture3D(GLenum internalFormat, int width, int height, int depth);
Framebuffer createFramebuffer(std::initializer_list<std::pair<GLenum, GLuint>> attachments);
// Throws GlError naming `what` when the framebuffer is incomplete.
void checkFramebuffer(GLuint fbo, const char* what);
void setFilter(GLuint texture, GLenum minFilter, GLenum magFilter, GLenum wrap = GL_CLAMP_TO_EDGE);

// Shader sources compiled into the binary, keyed by path from the repository root
// (e.g. "harness/shaders/common.glsl"). `#include "x.glsl"` is resolved against the including
// file's folder, then harness/shaders/. Compile and link errors name file:line.
struct ShaderStage {
  GLenum stage;
  std::string path;
};
Program buildProgram(const std::vector<ShaderStage>& stages, const std::string& defines = "");
inline Program buildCompute(const std::string& path, const std::string& defines = "") {
  return buildProgram({{GL_COMPUTE_SHADER, path}}, defines);
}
// Vertex shader harness/shaders/fullscreen.vert + the given fragment shader.
Program buildFullscreen(const std::string& fragmentPath, const std::string& defines = "");
// A shader with its includes expanded; every output line knows the file and line it came from.
struct Preprocessed {
  std::string source;
  std::vector<std::string> files;
  std::vector<std::pair<int, int>> lines;  // per output line: (index into files or -1, line)
  std::string locate(int outputLine) const;  // "path:line" for a 1-based output line
};
Preprocessed preprocess(const std::string& path, const std::string& defines = "");
// Hash of every embedded shader, for cache keys.
std::string shaderSourcesHash();
const std::map<std::string, std::string>& shaderFiles();

// KHR_debug: messages of severity >= LOW go to stderr (notifications are dropped); GL errors are
// counted, and in strict mode a GL error throws GlError from the next checkErrors().
void installDebugOutput(bool strict);
int debugErrorCount();
void resetDebugErrorCount();
std::string lastDebugError();
void checkErrors(const char* where);

// Puts the fixed-function state every pass may assume back to its defaults (no blend, logic op,
// culling, scissor or polygon offset; depth and colour writes on). The runner calls it between
// passes it does not own, so one method's leftovers never change another's image.
void resetPipelineState();

// One empty VAO bound for attribute-less fullscreen triangles.
void drawFullscreenTriangle();
// Frees objects owned by this module; the context calls it before it is destroyed.
void releaseSharedObjects();

// Loop iterations one shader invocation may run in total, over all its loops. llvmpipe (gallivm)
// ends every loop of an invocation once 65,535 iterations have run in it altogether, silently;
// shaders with nested loops (a march inside a march) split their work into passes that stay under
// this budget (methods/raymarch/raymarch.cpp). Other drivers have no such limit; the passes cost
// them little.
constexpr int kShaderLoopBudget = 60000;

struct Limits {
  int maxTextureSize = 0, maxCubeMapSize = 0, maxRenderbufferSize = 0, maxViewportW = 0, maxViewportH = 0;
  int maxTexture3DSize = 0, maxDrawBuffers = 0, maxColorAttachments = 0;
  int maxFragmentTextureUnits = 0, maxComputeTextureUnits = 0;
};
Limits queryLimits();

}  // namespace vs::gl
