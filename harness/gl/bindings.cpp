#include "harness/gl/bindings.hpp"

#include <algorithm>
#include <map>
#include <mutex>

#include "harness/gl/gl.hpp"

namespace vs::bind {

const char* kindName(Kind kind) {
  switch (kind) {
    case Kind::TextureUnit: return "texture unit";
    case Kind::ImageUnit: return "image unit";
    case Kind::UniformBlock: return "uniform-block binding";
    case Kind::StorageBlock: return "storage-block binding";
  }
  return "?";
}

Range methodRange(Kind kind) {
  switch (kind) {
    case Kind::TextureUnit: return kMethodTextureUnits;
    case Kind::ImageUnit: return kMethodImageUnits;
    case Kind::UniformBlock: return kMethodUniformBlocks;
    case Kind::StorageBlock: return kMethodStorageBlocks;
  }
  return {0, 0};
}

const std::vector<SharedSlot>& sharedSlots() {
  static const std::vector<SharedSlot> slots = {
      {Kind::TextureUnit, kShadowMap2D, "shadowMap2D", "VS_UNIT_SHADOW_MAP_2D"},
      {Kind::TextureUnit, kShadowMapCube, "shadowMapCube", "VS_UNIT_SHADOW_MAP_CUBE"},
      {Kind::TextureUnit, kLightTexture, "lightTexture", "VS_UNIT_LIGHT_TEXTURE"},
      {Kind::TextureUnit, kGPosition, "gPosition", "VS_UNIT_G_POSITION"},
      {Kind::TextureUnit, kGNormal, "gNormal", "VS_UNIT_G_NORMAL"},
      {Kind::TextureUnit, kGAlbedo, "gAlbedo", "VS_UNIT_G_ALBEDO"},
      {Kind::TextureUnit, kDirect, "directRadiance", "VS_UNIT_DIRECT"},
      {Kind::TextureUnit, kInscatter, "inscatter", "VS_UNIT_INSCATTER"},
      {Kind::TextureUnit, kShadowDepth2D, "shadowDepth2D", "VS_UNIT_SHADOW_DEPTH_2D"},
      {Kind::TextureUnit, kShadowDepthCube, "shadowDepthCube", "VS_UNIT_SHADOW_DEPTH_CUBE"},
      {Kind::TextureUnit, kVolumeDensity0, "volumeDensity", "VS_UNIT_VOLUME_DENSITY0"},
      {Kind::TextureUnit, kVolumeTransmittance, "volumeTransmittance", "VS_UNIT_VOLUME_TRANSMITTANCE"},
      {Kind::TextureUnit, kAlphaTexture, "alphaTexture", "VS_UNIT_ALPHA_TEXTURE"},
      {Kind::ImageUnit, kWorkCounters, "workCounters", "VS_IMAGE_WORK_COUNTERS"},
      {Kind::ImageUnit, kTransmittanceHeads, "transmittanceHeads", "VS_IMAGE_TRANSMITTANCE_HEADS"},
      {Kind::UniformBlock, kFrameUniforms, "FrameUniformBlock", "VS_BLOCK_FRAME"},
      {Kind::UniformBlock, kVolumeUniforms, "VolumeBlock", "VS_BLOCK_VOLUMES"},
      {Kind::UniformBlock, kTransmittanceUniforms, "TransmittanceBlock", "VS_BLOCK_TRANSMITTANCE"},
      {Kind::StorageBlock, kTransmittanceNodes, "TransmittanceNodes", "VS_STORAGE_TRANSMITTANCE_NODES"},
      {Kind::StorageBlock, kTransmittanceCounter, "TransmittanceCounter", "VS_STORAGE_TRANSMITTANCE_COUNTER"},
  };
  return slots;
}

std::string glslDefines() {
  std::string out;
  for (const SharedSlot& s : sharedSlots()) out += "#define " + std::string(s.macro) + " " + std::to_string(s.index) + "\n";
  return out;
}

}  // namespace vs::bind

namespace vs::gl {

namespace {

std::vector<Std140Mirror>& mirrorRegistry() {
  static std::vector<Std140Mirror> mirrors;
  return mirrors;
}
std::mutex g_checkedMutex;
std::set<std::string> g_checked;

bool isSamplerType(GLenum t) {
  switch (t) {
    case GL_SAMPLER_1D: case GL_SAMPLER_2D: case GL_SAMPLER_3D: case GL_SAMPLER_CUBE:
    case GL_SAMPLER_1D_SHADOW: case GL_SAMPLER_2D_SHADOW: case GL_SAMPLER_1D_ARRAY: case GL_SAMPLER_2D_ARRAY:
    case GL_SAMPLER_1D_ARRAY_SHADOW: case GL_SAMPLER_2D_ARRAY_SHADOW: case GL_SAMPLER_2D_MULTISAMPLE:
    case GL_SAMPLER_2D_MULTISAMPLE_ARRAY: case GL_SAMPLER_CUBE_SHADOW: case GL_SAMPLER_BUFFER:
    case GL_SAMPLER_2D_RECT: case GL_SAMPLER_2D_RECT_SHADOW: case GL_SAMPLER_CUBE_MAP_ARRAY:
    case GL_SAMPLER_CUBE_MAP_ARRAY_SHADOW:
    case GL_INT_SAMPLER_1D: case GL_INT_SAMPLER_2D: case GL_INT_SAMPLER_3D: case GL_INT_SAMPLER_CUBE:
    case GL_INT_SAMPLER_1D_ARRAY: case GL_INT_SAMPLER_2D_ARRAY: case GL_INT_SAMPLER_2D_MULTISAMPLE:
    case GL_INT_SAMPLER_2D_MULTISAMPLE_ARRAY: case GL_INT_SAMPLER_BUFFER: case GL_INT_SAMPLER_2D_RECT:
    case GL_INT_SAMPLER_CUBE_MAP_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_1D: case GL_UNSIGNED_INT_SAMPLER_2D: case GL_UNSIGNED_INT_SAMPLER_3D:
    case GL_UNSIGNED_INT_SAMPLER_CUBE: case GL_UNSIGNED_INT_SAMPLER_1D_ARRAY: case GL_UNSIGNED_INT_SAMPLER_2D_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE: case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_BUFFER: case GL_UNSIGNED_INT_SAMPLER_2D_RECT:
    case GL_UNSIGNED_INT_SAMPLER_CUBE_MAP_ARRAY:
      return true;
    default:
      return false;
  }
}

bool isImageType(GLenum t) {
  switch (t) {
    case GL_IMAGE_1D: case GL_IMAGE_2D: case GL_IMAGE_3D: case GL_IMAGE_2D_RECT: case GL_IMAGE_CUBE:
    case GL_IMAGE_BUFFER: case GL_IMAGE_1D_ARRAY: case GL_IMAGE_2D_ARRAY: case GL_IMAGE_CUBE_MAP_ARRAY:
    case GL_IMAGE_2D_MULTISAMPLE: case GL_IMAGE_2D_MULTISAMPLE_ARRAY:
    case GL_INT_IMAGE_1D: case GL_INT_IMAGE_2D: case GL_INT_IMAGE_3D: case GL_INT_IMAGE_2D_RECT:
    case GL_INT_IMAGE_CUBE: case GL_INT_IMAGE_BUFFER: case GL_INT_IMAGE_1D_ARRAY: case GL_INT_IMAGE_2D_ARRAY:
    case GL_INT_IMAGE_CUBE_MAP_ARRAY: case GL_INT_IMAGE_2D_MULTISAMPLE: case GL_INT_IMAGE_2D_MULTISAMPLE_ARRAY:
    case GL_UNSIGNED_INT_IMAGE_1D: case GL_UNSIGNED_INT_IMAGE_2D: case GL_UNSIGNED_INT_IMAGE_3D:
    case GL_UNSIGNED_INT_IMAGE_2D_RECT: case GL_UNSIGNED_INT_IMAGE_CUBE: case GL_UNSIGNED_INT_IMAGE_BUFFER:
    case GL_UNSIGNED_INT_IMAGE_1D_ARRAY: case GL_UNSIGNED_INT_IMAGE_2D_ARRAY:
    case GL_UNSIGNED_INT_IMAGE_CUBE_MAP_ARRAY: case GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE:
    case GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE_ARRAY:
      return true;
    default:
      return false;
  }
}

std::string resourceName(GLuint program, GLenum interface, GLuint index) {
  GLint length = 0;
  GLenum prop = GL_NAME_LENGTH;
  glGetProgramResourceiv(program, interface, index, 1, &prop, 1, nullptr, &length);
  std::string name(size_t(std::max(length, 1)), '\0');
  glGetProgramResourceName(program, interface, index, length, nullptr, name.data());
  name.resize(std::char_traits<char>::length(name.c_str()));
  return name;
}

// "Block.member[0]" -> "member"; "sampler[0]" -> "sampler".
std::string plainName(std::string name) {
  size_t dot = name.rfind('.');
  if (dot != std::string::npos) name = name.substr(dot + 1);
  if (name.size() > 3 && name.compare(name.size() - 3, 3, "[0]") == 0) name.resize(name.size() - 3);
  return name;
}

// One active sampler, image or block of a program, spanning `count` slots from `index`.
struct Resource {
  bind::Kind kind;
  GLuint index;
  GLuint count;
  std::string name;
};

std::vector<Resource> activeResources(GLuint program) {
  std::vector<Resource> out;
  for (auto [interface, kind] : {std::pair{GLenum(GL_UNIFORM_BLOCK), bind::Kind::UniformBlock},
                                 std::pair{GLenum(GL_SHADER_STORAGE_BLOCK), bind::Kind::StorageBlock}}) {
    GLint n = 0;
    glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &n);
    for (GLint i = 0; i < n; ++i) {
      GLenum prop = GL_BUFFER_BINDING;
      GLint binding = 0;
      glGetProgramResourceiv(program, interface, GLuint(i), 1, &prop, 1, nullptr, &binding);
      out.push_back({kind, GLuint(binding), 1, plainName(resourceName(program, interface, GLuint(i)))});
    }
  }
  GLint n = 0;
  glGetProgramInterfaceiv(program, GL_UNIFORM, GL_ACTIVE_RESOURCES, &n);
  for (GLint i = 0; i < n; ++i) {
    const GLenum props[] = {GL_TYPE, GL_ARRAY_SIZE, GL_LOCATION, GL_BLOCK_INDEX};
    GLint v[4] = {0, 0, -1, -1};
    glGetProgramResourceiv(program, GL_UNIFORM, GLuint(i), 4, props, 4, nullptr, v);
    GLenum type = GLenum(v[0]);
    bool sampler = isSamplerType(type), image = isImageType(type);
    if (v[3] != -1 || v[2] < 0 || !(sampler || image)) continue;
    GLint unit = 0;
    glGetUniformiv(program, v[2], &unit);
    out.push_back({sampler ? bind::Kind::TextureUnit : bind::Kind::ImageUnit, GLuint(unit), GLuint(std::max(v[1], 1)),
                   plainName(resourceName(program, GL_UNIFORM, GLuint(i)))});
  }
  return out;
}

size_t roundUp16(size_t bytes) { return (bytes + 15) / 16 * 16; }

// Compares uniform block `blockIndex` (named `block`) with its mirrors; appends problems.
void checkBlockLayout(GLuint program, GLuint blockIndex, const std::string& block, std::vector<std::string>& problems) {
  std::vector<const Std140Mirror*> mirrors;
  for (const Std140Mirror& m : mirrorRegistry())
    if (m.block == block) mirrors.push_back(&m);
  if (mirrors.empty()) {
    problems.push_back("uniform block " + block + " has no C++ std140 mirror (VS_STD140_MIRROR)");
    return;
  }
  GLenum sizeProp = GL_BUFFER_DATA_SIZE;
  GLint dataSize = 0;
  glGetProgramResourceiv(program, GL_UNIFORM_BLOCK, blockIndex, 1, &sizeProp, 1, nullptr, &dataSize);
  // The block's members, by name: offset and extent (arrays: stride x size).
  std::map<std::string, std::pair<GLint, GLint>> members;
  GLint n = 0;
  glGetProgramInterfaceiv(program, GL_UNIFORM, GL_ACTIVE_RESOURCES, &n);
  for (GLint i = 0; i < n; ++i) {
    const GLenum props[] = {GL_BLOCK_INDEX, GL_OFFSET, GL_ARRAY_SIZE, GL_ARRAY_STRIDE};
    GLint v[4] = {-1, 0, 0, 0};
    glGetProgramResourceiv(program, GL_UNIFORM, GLuint(i), 4, props, 4, nullptr, v);
    if (v[0] != GLint(blockIndex)) continue;
    members[plainName(resourceName(program, GL_UNIFORM, GLuint(i)))] = {v[1], v[2] > 1 ? v[2] * v[3] : 0};
  }
  for (const Std140Mirror* m : mirrors) {
    std::string who = m->cppType + " (" + m->source + ")";
    if (roundUp16(m->bytes) != roundUp16(size_t(dataSize)))
      problems.push_back(block + " is " + std::to_string(dataSize) + " bytes in GLSL, " + who + " " +
                         std::to_string(m->bytes));
    for (const auto& [name, layout] : members) {
      auto f = std::find_if(m->fields.begin(), m->fields.end(), [&](const Std140Field& x) { return x.glsl == name; });
      if (f == m->fields.end()) {
        problems.push_back(block + "." + name + " is not in " + who);
        continue;
      }
      if (size_t(layout.first) != f->offset)
        problems.push_back(block + "." + name + " is at offset " + std::to_string(layout.first) + " in GLSL, " +
                           std::to_string(f->offset) + " in " + who);
      if (layout.second > 0 && size_t(layout.second) != f->bytes)
        problems.push_back(block + "." + name + " spans " + std::to_string(layout.second) + " bytes in GLSL, " +
                           std::to_string(f->bytes) + " in " + who);
    }
    for (const Std140Field& f : m->fields)
      if (!members.count(f.glsl)) problems.push_back(who + " has " + f.glsl + ", which " + block + " lacks");
  }
  std::lock_guard<std::mutex> lock(g_checkedMutex);
  g_checked.insert(block);
}

}  // namespace

bool registerStd140Mirror(Std140Mirror mirror) {
  // __FILE__ from the source root on ("methods/vsv/vsv.cpp").
  size_t root = std::string::npos;
  for (const char* folder : {"/methods/", "/harness/", "/tests/", "/scenes/"})
    root = std::min(root, mirror.source.find(folder));
  if (root != std::string::npos) mirror.source = mirror.source.substr(root + 1);
  mirrorRegistry().push_back(std::move(mirror));
  return true;
}

const std::vector<Std140Mirror>& std140Mirrors() { return mirrorRegistry(); }

std::set<std::string> checkedStd140Blocks() {
  std::lock_guard<std::mutex> lock(g_checkedMutex);
  return g_checked;
}

void checkProgramInterface(GLuint program, const std::string& what, bool methodProgram) {
  std::vector<std::string> problems;
  std::vector<Resource> resources = activeResources(program);
  std::map<std::pair<bind::Kind, GLuint>, std::string> taken;
  for (const Resource& r : resources) {
    const bind::SharedSlot* shared = nullptr;
    for (const bind::SharedSlot& s : bind::sharedSlots())
      if (s.kind == r.kind && r.name == s.resource) shared = &s;
    std::string where = std::string(bind::kindName(r.kind)) + " " + std::to_string(r.index);
    if (shared && r.index != shared->index) {
      problems.push_back(r.name + " is on " + where + "; the table puts it on " + std::to_string(shared->index) + " (" +
                         shared->macro + ")");
    } else if (!shared && methodProgram) {
      bind::Range range = bind::methodRange(r.kind);
      if (!range.contains(r.index) || !range.contains(r.index + r.count - 1))
        problems.push_back(r.name + " is on " + where + ", outside the method's " + bind::kindName(r.kind) + "s " +
                           std::to_string(range.first) + "-" + std::to_string(range.end - 1));
    }
    for (GLuint k = 0; k < r.count; ++k) {
      auto [it, fresh] = taken.emplace(std::pair{r.kind, r.index + k}, r.name);
      if (!fresh)
        problems.push_back(r.name + " and " + it->second + " share " + bind::kindName(r.kind) + " " +
                           std::to_string(r.index + k));
    }
  }
  GLint blocks = 0;
  glGetProgramInterfaceiv(program, GL_UNIFORM_BLOCK, GL_ACTIVE_RESOURCES, &blocks);
  for (GLint i = 0; i < blocks; ++i)
    checkBlockLayout(program, GLuint(i), resourceName(program, GL_UNIFORM_BLOCK, GLuint(i)), problems);
  if (problems.empty()) return;
  std::string message = what + ": ";
  for (size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
  throw GlError(message);
}

}  // namespace vs::gl
