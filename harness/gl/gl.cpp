#include "harness/gl/gl.hpp"
#include "scenes/content_hash.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <fstream>
#include <cstdio>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>

namespace vs {
const std::map<std::string, std::string>& embeddedShaderFiles();  // generated at build time
}

namespace vs::gl {

void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void deleteProgram(GLuint id) { glDeleteProgram(id); }
void deleteQuery(GLuint id) { glDeleteQueries(1, &id); }
void deleteSampler(GLuint id) { glDeleteSamplers(1, &id); }

Buffer createBuffer(size_t bytes, const void* data, GLbitfield flags) {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  glNamedBufferStorage(id, GLsizeiptr(bytes > 0 ? bytes : 4), data, flags);
  return Buffer(id);
}

Texture createTexture2D(GLenum internalFormat, int width, int height, int levels) {
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  glTextureStorage2D(id, levels, internalFormat, width, height);
  Texture t(id);
  setFilter(id, GL_NEAREST, GL_NEAREST);
  return t;
}

Texture createTextureCube(GLenum internalFormat, int size) {
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &id);
  glTextureStorage2D(id, 1, internalFormat, size, size);
  Texture t(id);
  setFilter(id, GL_NEAREST, GL_NEAREST);
  return t;
}

Texture createTexture3D(GLenum internalFormat, int width, int height, int depth) {
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &id);
  glTextureStorage3D(id, 1, internalFormat, width, height, depth);
  Texture t(id);
  setFilter(id, GL_LINEAR, GL_LINEAR);
  glTextureParameteri(id, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  return t;
}

void setFilter(GLuint texture, GLenum minFilter, GLenum magFilter, GLenum wrap) {
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GLint(minFilter));
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GLint(magFilter));
  glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GLint(wrap));
  glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GLint(wrap));
  glTextureParameteri(texture, GL_TEXTURE_WRAP_R, GLint(wrap));
}

Framebuffer createFramebuffer(std::initializer_list<std::pair<GLenum, GLuint>> attachments) {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  Framebuffer fbo(id);
  std::vector<GLenum> drawBuffers;
  for (auto [attachment, texture] : attachments) {
    glNamedFramebufferTexture(id, attachment, texture, 0);
    if (attachment >= GL_COLOR_ATTACHMENT0 && attachment <= GL_COLOR_ATTACHMENT15)
      drawBuffers.push_back(attachment);
  }
  if (drawBuffers.empty())
    glNamedFramebufferDrawBuffer(id, GL_NONE);
  else
    glNamedFramebufferDrawBuffers(id, GLsizei(drawBuffers.size()), drawBuffers.data());
  return fbo;
}

void checkFramebuffer(GLuint fbo, const char* what) {
  GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "framebuffer '%s' incomplete (status 0x%04x)", what, status);
    throw GlError(buf);
  }
}

// ---- shaders

const std::map<std::string, std::string>& shaderFiles() { return embeddedShaderFiles(); }

// The embedded text, or the file under $VSHADOW_SHADER_DIR when that is set and has it (for
// editing shaders without rebuilding).
static std::string shaderText(const std::string& path) {
  auto it = shaderFiles().find(path);
  if (it == shaderFiles().end()) throw GlError("shader file not found in the binary: " + path);
  if (const char* dir = std::getenv("VSHADOW_SHADER_DIR")) {
    std::ifstream in(std::string(dir) + "/" + path, std::ios::binary);
    if (in) {
      std::stringstream text;
      text << in.rdbuf();
      return text.str();
    }
  }
  return it->second;
}

static std::string folderOf(const std::string& path) {
  auto slash = path.rfind('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// Includes are expanded inline without #line directives (drivers disagree on how they report
// source-string numbers); every output line remembers its file and line instead.
static void expand(const std::string& path, Preprocessed& out, std::set<std::string>& seen, bool top,
                   const std::string& defines) {
  if (seen.count(path)) return;  // every file is included once
  seen.insert(path);
  int index = int(out.files.size());
  out.files.push_back(path);
  std::istringstream in(shaderText(path));
  std::string line;
  int lineNo = 0;
  static const std::regex includeRe(R"(^\s*#\s*include\s+"([^"]+)\"\s*$)");
  auto emit = [&](const std::string& text, int file, int fileLine) {
    out.source += text + "\n";
    out.lines.emplace_back(file, fileLine);
  };
  while (std::getline(in, line)) {
    ++lineNo;
    std::smatch m;
    if (top && lineNo == 1 && line.rfind("#version", 0) == 0) {
      emit(line, index, lineNo);
      std::istringstream defs(bind::glslDefines() + defines);
      std::string def;
      while (std::getline(defs, def)) emit(def, -1, 0);
    } else if (std::regex_match(line, m, includeRe)) {
      std::string name = m[1];
      // Beside the including file, then from the source root ("methods/epipolar/shaders/..."),
      // then among the shared harness shaders.
      std::string candidate = folderOf(path) + name;
      if (!shaderFiles().count(candidate)) candidate = name;
      if (!shaderFiles().count(candidate)) candidate = "harness/shaders/" + name;
      if (!shaderFiles().count(candidate))
        throw GlError(path + ":" + std::to_string(lineNo) + ": cannot find include \"" + name + "\"");
      emit("", index, lineNo);
      expand(candidate, out, seen, false, defines);
    } else {
      emit(line, index, lineNo);
    }
  }
}

Preprocessed preprocess(const std::string& path, const std::string& defines) {
  Preprocessed out;
  std::set<std::string> seen;
  expand(path, out, seen, true, defines);
  return out;
}

std::string Preprocessed::locate(int outputLine) const {
  if (outputLine < 1 || size_t(outputLine) > lines.size()) return "";
  auto [file, line] = lines[size_t(outputLine - 1)];
  if (file < 0) return "(defines):" + std::to_string(outputLine);
  return files[size_t(file)] + ":" + std::to_string(line);
}

// Rewrites driver log locations ("0:12(3):" Mesa, "0(12) :" NVIDIA, "ERROR: 0:12:" AMD) to file:line.
static std::string nameLogLocations(const std::string& log, const Preprocessed& pre) {
  static const std::regex locRe(R"((\d+)(?::(\d+)\(\d+\)|\((\d+)\)|:(\d+)))");
  std::string out;
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, locRe)) {
      std::string lineNo = m[2].matched ? m[2].str() : m[3].matched ? m[3].str() : m[4].str();
      std::string where = pre.locate(std::stoi(lineNo));
      if (!where.empty()) line = m.prefix().str() + where + m.suffix().str();
    }
    if (!line.empty()) out += line + "\n";
  }
  return out;
}

// Linked programs of this process by their full source text, so a sweep that sets a method up
// again (another parameter set, another scene state) relinks from the driver's binary.
struct ProgramBinary {
  GLenum format = 0;
  std::vector<uint8_t> bytes;
};
static std::map<std::string, ProgramBinary> g_programBinaries;

static Program fromBinary(const ProgramBinary& binary) {
  GLuint program = glCreateProgram();
  Program owner(program);
  glProgramBinary(program, binary.format, binary.bytes.data(), GLsizei(binary.bytes.size()));
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  return ok ? std::move(owner) : Program();
}

static void rememberBinary(GLuint program, const std::string& key) {
  GLint formats = 0, length = 0;
  glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
  glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
  if (formats <= 0 || length <= 0) return;
  ProgramBinary binary;
  binary.bytes.resize(size_t(length));
  glGetProgramBinary(program, length, nullptr, &binary.format, binary.bytes.data());
  g_programBinaries[key] = std::move(binary);
}

Program buildProgram(const std::vector<ShaderStage>& stages, const std::string& defines) {
  std::vector<Preprocessed> sources;
  std::string key;
  for (const auto& s : stages) {
    sources.push_back(preprocess(s.path, defines));
    key += std::to_string(s.stage) + '\0' + sources.back().source + '\0';
  }
  auto cached = g_programBinaries.find(key);
  if (cached != g_programBinaries.end()) {
    Program program = fromBinary(cached->second);
    if (program) return program;
    g_programBinaries.erase(cached);  // the driver refused its own binary: compile again
  }
  GLuint program = glCreateProgram();
  Program owner(program);
  glProgramParameteri(program, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
  std::vector<GLuint> shaders;
  std::string names;
  for (size_t i = 0; i < stages.size(); ++i) {
    const ShaderStage& s = stages[i];
    const Preprocessed& pre = sources[i];
    GLuint shader = glCreateShader(s.stage);
    const char* text = pre.source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      GLint length = 0;
      glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
      std::string log(size_t(std::max(length, 1)), '\0');
      glGetShaderInfoLog(shader, length, nullptr, log.data());
      glDeleteShader(shader);
      for (GLuint sh : shaders) glDeleteShader(sh);
      std::string named = nameLogLocations(log.c_str(), pre);
      std::string first = named.substr(0, named.find('\n'));
      throw GlError("shader compile failed: " + first);
    }
    glAttachShader(program, shader);
    shaders.push_back(shader);
    names += (names.empty() ? "" : " + ") + s.path;
  }
  glLinkProgram(program);
  for (GLuint sh : shaders) {
    glDetachShader(program, sh);
    glDeleteShader(sh);
  }
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    std::string first = std::string(log.c_str()).substr(0, std::string(log.c_str()).find('\n'));
    throw GlError("shader link failed (" + names + "): " + first);
  }
  bool methodProgram = std::any_of(stages.begin(), stages.end(),
                                   [](const ShaderStage& s) { return s.path.rfind("methods/", 0) == 0; });
  checkProgramInterface(program, names, methodProgram);
  rememberBinary(program, key);
  return owner;
}

Program buildFullscreen(const std::string& fragmentPath, const std::string& defines) {
  return buildProgram({{GL_VERTEX_SHADER, "harness/shaders/fullscreen.vert"}, {GL_FRAGMENT_SHADER, fragmentPath}},
                      defines);
}

std::string shaderSourcesHash() {
  ContentHasher hasher;
  for (const auto& entry : shaderFiles()) {
    hasher.addBlock(entry.first);
    hasher.addBlock(shaderText(entry.first));
  }
  hasher.addBlock(bind::glslDefines());
  return hasher.hex();
}

// ---- debug output

static std::atomic<int> g_errors{0};
static bool g_strict = false;
static std::mutex g_lastMutex;
static std::string g_lastError;

static void APIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei,
                                      const GLchar* message, const void*) {
  (void)source;
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  bool isError = type == GL_DEBUG_TYPE_ERROR;
  if (isError) {
    ++g_errors;
    std::lock_guard<std::mutex> lock(g_lastMutex);
    g_lastError = message;
  }
  std::fprintf(stderr, "GL %s [%u]: %s\n", isError ? "error" : "debug", id, message);
}

void installDebugOutput(bool strict) {
  g_strict = strict;
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(onDebugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
  // Performance chatter from some drivers is not an error and is not useful in a benchmark log.
  glDebugMessageControl(GL_DONT_CARE, GL_DEBUG_TYPE_PERFORMANCE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
  glDebugMessageControl(GL_DONT_CARE, GL_DEBUG_TYPE_OTHER, GL_DEBUG_SEVERITY_LOW, 0, nullptr, GL_FALSE);
}

int debugErrorCount() { return g_errors.load(); }
void resetDebugErrorCount() { g_errors = 0; }
std::string lastDebugError() {
  std::lock_guard<std::mutex> lock(g_lastMutex);
  return g_lastError;
}

void checkErrors(const char* where) {
  GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    ++g_errors;
    char buf[128];
    std::snprintf(buf, sizeof buf, "GL error 0x%04x at %s", e, where);
    std::lock_guard<std::mutex> lock(g_lastMutex);
    g_lastError = buf;
  }
  if (g_strict && g_errors > 0) throw GlError("GL error at " + std::string(where) + ": " + lastDebugError());
}

void resetPipelineState() {
  glDisable(GL_BLEND);
  glDisable(GL_COLOR_LOGIC_OP);
  glLogicOp(GL_COPY);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_RASTERIZER_DISCARD);
  glDisable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
  glBindVertexArray(0);
}

static VertexArray g_emptyVao;

void drawFullscreenTriangle() {
  if (!g_emptyVao) {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    g_emptyVao = VertexArray(id);
  }
  glBindVertexArray(g_emptyVao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

void releaseSharedObjects() {
  g_emptyVao.reset();
  g_programBinaries.clear();  // binaries belong to the context's driver
}

Limits queryLimits() {
  Limits l;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &l.maxTextureSize);
  glGetIntegerv(GL_MAX_CUBE_MAP_TEXTURE_SIZE, &l.maxCubeMapSize);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &l.maxRenderbufferSize);
  GLint dims[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
  l.maxViewportW = dims[0];
  l.maxViewportH = dims[1];
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &l.maxTexture3DSize);
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &l.maxDrawBuffers);
  glGetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &l.maxColorAttachments);
  glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &l.maxFragmentTextureUnits);
  glGetIntegerv(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, &l.maxComputeTextureUnits);
  return l;
}

}  // namespace vs::gl
