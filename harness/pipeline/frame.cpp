#include "harness/pipeline/frame.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace vs {

// ---- cameras

VS_STD140_MIRROR(FrameUniforms, "FrameUniformBlock", VS_STD140_FIELD(FrameUniforms, viewProj), VS_STD140_FIELD(FrameUniforms, invViewProj), VS_STD140_FIELD(FrameUniforms, view), VS_STD140_FIELD(FrameUniforms, proj), VS_STD140_FIELD(FrameUniforms, lightViewProj), VS_STD140_FIELD(FrameUniforms, lightView), VS_STD140_FIELD(FrameUniforms, eye), VS_STD140_FIELD(FrameUniforms, cameraForward), VS_STD140_FIELD(FrameUniforms, lightPos), VS_STD140_FIELD(FrameUniforms, lightDir), VS_STD140_FIELD(FrameUniforms, lightColor), VS_STD140_FIELD(FrameUniforms, shadowParams), VS_STD140_FIELD(FrameUniforms, medium), VS_STD140_FIELD(FrameUniforms, cameraClip), VS_STD140_FIELD(FrameUniforms, viewport), VS_STD140_FIELD(FrameUniforms, lightEmission));
VS_STD140_MIRROR(VolumeUniforms, "VolumeBlock", VS_STD140_FIELD(VolumeUniforms, count), VS_STD140_FIELD(VolumeUniforms, boxLo), VS_STD140_FIELD(VolumeUniforms, boxHi), VS_STD140_FIELD(VolumeUniforms, coeff), VS_STD140_FIELD(VolumeUniforms, scattering), VS_STD140_FIELD(VolumeUniforms, extinction));

static glm::vec3 safeUp(glm::vec3 forward, glm::vec3 up) {
  if (glm::length(glm::cross(forward, up)) > 1e-6f * glm::length(up)) return up;
  return std::fabs(forward.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
}

static glm::vec3 safeDirection(glm::vec3 d, glm::vec3 fallback) {
  float len = glm::length(d);
  return len > 1e-20f && std::isfinite(len) ? d / len : fallback;
}

glm::mat4 cameraView(const Camera& c) {
  glm::vec3 forward = safeDirection(c.target - c.position, {0, 0, -1});
  return glm::lookAt(c.position, c.position + forward, safeUp(forward, c.up));
}

glm::mat4 cameraProjection(const Camera& c, float aspect) {
  return glm::perspective(glm::radians(c.fovYDeg), aspect, c.nearZ, c.farZ);
}

std::string sceneDefines(const Effects& effects) {
  return "#define VS_TRANSLUCENT " + std::to_string(effects.semiTransparent ? 1 : 0) + "\n#define VS_VOLUMES " +
         std::to_string(effects.volumeData ? effects.volumeCount : 0) + "\n#define VS_LIGHT_TYPE " +
         std::to_string(lightTypeCode(effects.light)) + "\n#define VS_LIGHT_TEXTURE " +
         std::to_string(effects.lightTexture ? 1 : 0) + "\n#define VS_HG_PHASE " +
         std::to_string(effects.anisotropic ? 1 : 0) + "\n#define VS_COSINE_LOBE " +
         std::to_string(effects.cosineLobe || isAreaLight(effects.light) ? 1 : 0) + "\n";
}

glm::mat4 cubeFaceViewProj(const glm::vec3& position, int face, float nearZ, float farZ) {
  static const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  glm::mat4 proj = glm::perspective(glm::radians(90.0f), 1.0f, nearZ, farZ);
  return proj * glm::lookAt(position, position + axes[face], ups[face]);
}

bool isSharedPass(const std::string& pass) {
  for (const char* shared : kSharedPasses)
    if (pass == shared) return true;
  return false;
}

// ---- volumes

std::string volumeLimitProblem(const Scene& scene, const gl::Limits& limits) {
  if (scene.volumes.empty()) return "";
  if (scene.volumes.size() > size_t(kMaxVolumes))
    return "the scene has " + std::to_string(scene.volumes.size()) + " volumes; at most " + std::to_string(kMaxVolumes) +
           " are supported";
  int units = std::min(limits.maxFragmentTextureUnits, limits.maxComputeTextureUnits);
  int needed = std::max(int(bind::kVolumeDensity0) + kMaxVolumes, int(bind::kVolumeTransmittance) + 1);
  if (units < needed)
    return "volume data needs " + std::to_string(needed) +
           " texture units; this GL implementation has " + std::to_string(units);
  for (const Volume& v : scene.volumes)
    for (int k = 0; k < 3; ++k)
      if (v.dims[k] > limits.maxTexture3DSize)
        return "volume '" + v.name + "' has " + std::to_string(v.dims[k]) +
               " voxels along an axis; GL_MAX_3D_TEXTURE_SIZE is " + std::to_string(limits.maxTexture3DSize);
  return "";
}

VolumesGpu::VolumesGpu(const Scene& scene) {
  count = std::min(int(scene.volumes.size()), kMaxVolumes);
  uniforms.count = glm::ivec4(count, 0, 0, 0);
  for (int i = 0; i < count; ++i) {
    const Volume& v = scene.volumes[size_t(i)];
    density[i] = gl::createTexture3D(GL_R32F, v.dims[0], v.dims[1], v.dims[2]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage3D(density[i].id(), 0, 0, 0, 0, v.dims[0], v.dims[1], v.dims[2], GL_RED, GL_FLOAT, v.density.data());
    glm::vec3 voxel = (v.boxHi - v.boxLo) / glm::vec3(v.dims[0], v.dims[1], v.dims[2]);
    uniforms.boxLo[i] = glm::vec4(v.boxLo, 0.0f);
    uniforms.boxHi[i] = glm::vec4(v.boxHi, 0.0f);
    glm::vec3 s = v.sigmaS * v.densityScale, t = v.sigmaT() * v.densityScale;
    uniforms.coeff[i] = glm::vec4((s.x + s.y + s.z) / 3.0f, (t.x + t.y + t.z) / 3.0f, v.maxDensity(),
                                  std::min({voxel.x, voxel.y, voxel.z}));
    uniforms.scattering[i] = glm::vec4(s, 0.0f);
    uniforms.extinction[i] = glm::vec4(t, 0.0f);
  }
  ubo = gl::createBuffer(sizeof(VolumeUniforms), &uniforms);
}

void VolumesGpu::bind() const {
  glBindBufferBase(GL_UNIFORM_BUFFER, bind::kVolumeUniforms, ubo.id());
  for (int i = 0; i < count; ++i) glBindTextureUnit(bind::kVolumeDensity0 + GLuint(i), density[i].id());
}

// ---- scene upload

namespace {
constexpr int kVertexFloats = 17;

int alphaTextureOf(const Scene& scene, const Mesh& mesh) {
  return mesh.alphaTexture >= 0 && size_t(mesh.alphaTexture) < scene.alphaTextures.size() ? mesh.alphaTexture : -1;
}

// Every uploaded mesh's vertices, interleaved as the vertex array reads them.
std::vector<float> vertexRecords(const Scene& scene) {
  size_t vertices = 0;
  for (const Mesh& mesh : scene.meshes) vertices += mesh.opacity > 0.0f ? mesh.positions.size() : 0;
  std::vector<float> vertexData;
  vertexData.reserve(vertices * kVertexFloats);
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.opacity <= 0.0f) continue;  // cut out: neither seen nor casting shadows
    const int texture = alphaTextureOf(scene, mesh);
    const glm::vec3 c = mesh.transmittanceColor;
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const glm::vec3& p = mesh.positions[i];
      glm::vec3 n = i < mesh.normals.size() ? mesh.normals[i] : glm::vec3(0, 1, 0);
      glm::vec2 uv = i < mesh.uvs.size() ? mesh.uvs[i] : glm::vec2(0.0f);
      vertexData.insert(vertexData.end(), {p.x, p.y, p.z, n.x, n.y, n.z, mesh.albedo.r, mesh.albedo.g, mesh.albedo.b,
                                           c.r, c.g, c.b, uv.x, uv.y, float(texture), mesh.alphaCutoff, mesh.opacity});
    }
  }
  return vertexData;
}
}  // namespace

SceneGpu::SceneGpu(const Scene& scene) {
  std::vector<float> vertexData = vertexRecords(scene);
  std::vector<uint32_t> opaque;  // then the semi-transparent meshes' indices after them
  size_t indexTotal = 0;
  for (const Mesh& mesh : scene.meshes) indexTotal += mesh.opacity > 0.0f ? mesh.indices.size() : 0;
  opaque.reserve(indexTotal);
  struct Pending {
    std::vector<uint32_t> indices;
    int texture;
  };
  std::vector<Pending> translucent;
  uint32_t base = 0;  // the mesh's first vertex in vertexData
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.opacity <= 0.0f) continue;
    const int texture = alphaTextureOf(scene, mesh);
    if (mesh.isOpaque()) {
      for (uint32_t index : mesh.indices) opaque.push_back(base + index);
    } else {
      Pending pending{{}, texture};
      for (uint32_t index : mesh.indices) pending.indices.push_back(base + index);
      translucent.push_back(std::move(pending));
    }
    base += uint32_t(mesh.positions.size());
  }
  for (const AlphaTexture& t : scene.alphaTextures) {
    gl::Texture texture = gl::createTexture2D(GL_R32F, t.width, t.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture.id(), 0, 0, 0, t.width, t.height, GL_RED, GL_FLOAT, t.alpha.data());
    gl::setFilter(texture.id(), GL_LINEAR, GL_LINEAR, GL_REPEAT);
    alphaTextures_.push_back(std::move(texture));
  }
  opaqueIndexCount = GLsizei(opaque.size());
  for (const Pending& p : translucent) {
    translucent_.push_back({GLsizei(opaque.size()), GLsizei(p.indices.size()),
                            p.texture >= 0 ? alphaTextures_[size_t(p.texture)].id() : 0});
    opaque.insert(opaque.end(), p.indices.begin(), p.indices.end());
  }
  indexCount = GLsizei(opaque.size());
  // Dynamic storage: a scene whose geometry moves rewrites it every frame (updateVertices).
  vertexFloats_ = vertexData.size();
  vertices = gl::createBuffer(vertexData.size() * sizeof(float), vertexData.empty() ? nullptr : vertexData.data(),
                              scene.animation.movesGeometry() ? GLbitfield(GL_DYNAMIC_STORAGE_BIT) : 0);
  indices = gl::createBuffer(opaque.size() * sizeof(uint32_t), opaque.empty() ? nullptr : opaque.data(), 0);
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  vao = gl::VertexArray(id);
  glVertexArrayVertexBuffer(id, 0, vertices.id(), 0, kVertexFloats * sizeof(float));
  glVertexArrayElementBuffer(id, indices.id());
  const GLint sizes[6] = {3, 3, 3, 3, 2, 3};
  GLuint offset = 0;
  for (GLuint a = 0; a < 6; ++a) {
    glEnableVertexArrayAttrib(id, a);
    glVertexArrayAttribFormat(id, a, sizes[a], GL_FLOAT, GL_FALSE, offset * sizeof(float));
    glVertexArrayAttribBinding(id, a, 0);
    offset += GLuint(sizes[a]);
  }
  scene.bounds(boundsLo, boundsHi);
}

void SceneGpu::updateVertices(const Scene& scene) {
  std::vector<float> vertexData = vertexRecords(scene);
  if (vertexData.size() != vertexFloats_)
    throw std::logic_error("updateVertices: the scene's meshes changed size (only their poses may move)");
  if (!vertexData.empty()) glNamedBufferSubData(vertices.id(), 0, GLsizeiptr(vertexData.size() * sizeof(float)), vertexData.data());
}

void SceneGpu::draw() const {
  drawOpaque();
  drawTranslucent();
}

void SceneGpu::drawOpaque() const {
  if (opaqueIndexCount == 0) return;
  glBindVertexArray(vao.id());
  glDrawElements(GL_TRIANGLES, opaqueIndexCount, GL_UNSIGNED_INT, nullptr);
}

void SceneGpu::drawTranslucent() const {
  if (translucent_.empty()) return;
  glBindVertexArray(vao.id());
  for (const Range& r : translucent_) {
    glBindTextureUnit(bind::kAlphaTexture, r.texture);
    glDrawElements(GL_TRIANGLES, r.count, GL_UNSIGNED_INT, reinterpret_cast<const void*>(size_t(r.first) * sizeof(uint32_t)));
  }
}

// ---- transmittance map

namespace {
// std140 mirror of TransmittanceBlock in common.glsl.
struct TransmittanceUniforms {
  glm::mat4 faceViewProj[6];
  glm::vec4 params;  // x size, y faces, z light type, w longest list
};
VS_STD140_MIRROR(TransmittanceUniforms, "TransmittanceBlock", VS_STD140_FIELD(TransmittanceUniforms, faceViewProj), VS_STD140_FIELD(TransmittanceUniforms, params));
}  // namespace

TransmittanceMap::TransmittanceMap(const SceneGpu& geometry) : geometry_(geometry) {
  build_ = gl::buildProgram({{GL_VERTEX_SHADER, "harness/shaders/transmittance.vert"},
                             {GL_FRAGMENT_SHADER, "harness/shaders/transmittance.frag"}});
  counter_ = gl::createBuffer(2 * sizeof(uint32_t));
  ubo_ = gl::createBuffer(sizeof(TransmittanceUniforms));
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  fbo_ = gl::Framebuffer(id);
}

void TransmittanceMap::resize(const ShadowMap& shadow) {
  int faces = shadow.type == LightType::Point ? 6 : 1;
  if (shadow.size != size_ || faces != faces_) {
    size_ = shadow.size;
    faces_ = faces;
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
    heads_ = gl::Texture(id);
    glTextureStorage3D(id, 1, GL_R32UI, size_, size_, faces_);
    gl::setFilter(id, GL_NEAREST, GL_NEAREST);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
    lengths_ = gl::Texture(id);
    glTextureStorage3D(id, 1, GL_R32UI, size_, size_, faces_);
    gl::setFilter(id, GL_NEAREST, GL_NEAREST);
    glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, size_);
    glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, size_);
    if (capacity_ == 0) capacity_ = size_t(size_) * size_ * 2;
    nodeBuffer_ = gl::createBuffer(capacity_ * 32);
  }
}

void TransmittanceMap::clear(const ShadowMap& shadow) {
  resize(shadow);
  const GLuint none = 0xFFFFFFFFu;
  glClearTexImage(heads_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
  TransmittanceUniforms empty{};  // longest list 0: every lookup is 1
  glNamedBufferSubData(ubo_.id(), 0, sizeof empty, &empty);
  nodes_ = 0;
  longest_ = 0;
}

void TransmittanceMap::render(const ShadowMap& shadow, const glm::vec3& lightPos, const glm::vec3& lightDir,
                              int lightType) {
  resize(shadow);
  int faces = faces_;
  TransmittanceUniforms tu{};
  for (int f = 0; f < 6; ++f) tu.faceViewProj[f] = faces == 6 ? shadow.faceViewProj[f] : shadow.viewProj;
  tu.params = glm::vec4(float(size_), float(faces_), float(lightType), 0.0f);
  glNamedBufferSubData(ubo_.id(), 0, sizeof tu, &tu);

  // Appends every crossing; when the buffer was too small, grows it and appends again.
  for (int attempt = 0; attempt < 2; ++attempt) {
    const GLuint none = 0xFFFFFFFFu, zero[2] = {0, 0};
    glClearTexImage(heads_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
    glClearTexImage(lengths_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero[0]);
    glNamedBufferSubData(counter_.id(), 0, sizeof zero, zero);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, size_, size_);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glUseProgram(build_.id());
    glBindImageTexture(0, heads_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(1, lengths_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, bind::kTransmittanceNodes, nodeBuffer_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, bind::kTransmittanceCounter, counter_.id());
    glUniform3fv(1, 1, &lightPos.x);
    glUniform3fv(2, 1, &lightDir.x);
    glUniform1i(3, lightType);
    glUniform1ui(4, GLuint(capacity_));
    for (int f = 0; f < faces_; ++f) {
      glUniformMatrix4fv(0, 1, GL_FALSE, &tu.faceViewProj[f][0][0]);
      glUniform1i(5, f);
      geometry_.drawTranslucent();
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    GLuint counts[2] = {0, 0};  // crossings appended, longest list
    glGetNamedBufferSubData(counter_.id(), 0, sizeof counts, counts);
    GLuint appended = counts[0];
    nodes_ = appended;
    longest_ = int(counts[1]);
    if (longest_ > gl::kShaderLoopBudget / 2)
      throw std::runtime_error(std::to_string(longest_) + " semi-transparent layers over one light texel; at most " +
                               std::to_string(gl::kShaderLoopBudget / 2) + " can be looked up (shader loop budget)");
    tu.params.w = float(counts[1]);
    if (appended <= capacity_) break;
    capacity_ = size_t(appended) + appended / 2;
    nodeBuffer_ = gl::createBuffer(capacity_ * 32);
  }
  glNamedBufferSubData(ubo_.id(), 0, sizeof tu, &tu);
}

void TransmittanceMap::bind() const {
  glBindImageTexture(bind::kTransmittanceHeads, heads_.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_R32UI);
  glBindBufferBase(GL_UNIFORM_BUFFER, bind::kTransmittanceUniforms, ubo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, bind::kTransmittanceNodes, nodeBuffer_.id());
}

// ---- shared passes

SharedPasses::SharedPasses(const Scene& scene, const SceneGpu& geometry, const Effects& effects, int width, int height)
    : scene_(scene), geometry_(geometry), effects_(effects), width_(width), height_(height) {
  ubo_ = gl::createBuffer(sizeof(FrameUniforms));
  if (effects_.volumeData) volumes_ = std::make_unique<VolumesGpu>(scene_);
  if (effects_.semiTransparent) transmittance_ = std::make_unique<TransmittanceMap>(geometry_);
  const std::string defines = sceneDefines(effects_);
  shadowProgram_ = gl::buildProgram({{GL_VERTEX_SHADER, "harness/shaders/shadow.vert"},
                                     {GL_FRAGMENT_SHADER, "harness/shaders/shadow.frag"}});
  gbufferProgram_ = gl::buildProgram({{GL_VERTEX_SHADER, "harness/shaders/gbuffer.vert"},
                                      {GL_FRAGMENT_SHADER, "harness/shaders/gbuffer.frag"}},
                                     defines);
  skyProgram_ = gl::buildFullscreen("harness/shaders/sky.frag", defines);
  directProgram_ = gl::buildFullscreen("harness/shaders/direct.frag", defines);
  compositeProgram_ = gl::buildFullscreen("harness/shaders/composite.frag", defines);

  gPosition_ = gl::createTexture2D(GL_RGBA32F, width, height);
  gNormal_ = gl::createTexture2D(GL_RGBA16F, width, height);
  gAlbedo_ = gl::createTexture2D(GL_RGBA8, width, height);
  depth_ = gl::createTexture2D(GL_DEPTH_COMPONENT32F, width, height);
  direct_ = gl::createTexture2D(GL_RGBA32F, width, height);
  inscatter_ = gl::createTexture2D(GL_RGBA32F, width, height);
  final_ = gl::createTexture2D(GL_RGBA32F, width, height);
  gbufferFbo_ = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, gPosition_.id()},
                                       {GL_COLOR_ATTACHMENT1, gNormal_.id()},
                                       {GL_COLOR_ATTACHMENT2, gAlbedo_.id()},
                                       {GL_DEPTH_ATTACHMENT, depth_.id()}});
  directFbo_ = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, direct_.id()}});
  if (effects_.volumeData) {
    // Methods write L_s and the camera ray's rgb transmittance through the volumes in one pass.
    volumeTransmittance_ = gl::createTexture2D(GL_RGBA32F, width, height);
    inscatterFbo_ = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, inscatter_.id()},
                                           {GL_COLOR_ATTACHMENT1, volumeTransmittance_.id()}});
    const GLenum targets[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(inscatterFbo_.id(), 2, targets);
  } else {
    inscatterFbo_ = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, inscatter_.id()}});
  }
  finalFbo_ = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, final_.id()}});
  gl::checkFramebuffer(gbufferFbo_.id(), "G buffer");
  gl::checkFramebuffer(directFbo_.id(), "direct lighting");
  gl::checkFramebuffer(inscatterFbo_.id(), "in-scatter");
  gl::checkFramebuffer(finalFbo_.id(), "composite");

  if (effects_.lightTexture) {
    const Light& l = scene_.light;
    lightTexture_ = gl::createTexture2D(GL_RGB32F, l.textureWidth, l.textureHeight);
    glTextureSubImage2D(lightTexture_.id(), 0, 0, 0, l.textureWidth, l.textureHeight, GL_RGB, GL_FLOAT,
                        l.textureRGB.data());
    gl::setFilter(lightTexture_.id(), GL_LINEAR, GL_LINEAR,
                  l.type == LightType::Point ? GL_REPEAT : GL_CLAMP_TO_EDGE);
  }
}

static LightType shadowMapType(const Light& light) {
  // Area lights share a cube map around their centre (the surface term's approximation).
  return isAreaLight(light.type) ? LightType::Point : light.type;
}

void SharedPasses::fitShadowProjection() {
  ShadowMap& s = shadow_;
  const Light& light = scene_.light;
  glm::vec3 lo = geometry_.boundsLo, hi = geometry_.boundsHi;
  glm::vec3 center = 0.5f * (lo + hi);
  float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);

  // Light projection range: everything in the scene bounds.
  float farthest = 0.0f;
  for (int i = 0; i < 8; ++i) {
    glm::vec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    farthest = std::max(farthest, glm::length(corner - light.position));
  }
  s.farZ = std::max(farthest * 1.01f, 1e-3f);
  s.nearZ = std::max(s.farZ * 1e-4f, 1e-5f);
  if (s.type == LightType::Point) {
    for (int f = 0; f < 6; ++f) s.faceViewProj[f] = cubeFaceViewProj(light.position, f, s.nearZ, s.farZ);
    return;
  }
  glm::mat4 view, proj;
  glm::vec3 dir = safeDirection(light.direction, {0, -1, 0});
  if (s.type == LightType::Directional) {
    view = glm::lookAt(center - dir * (2.0f * radius), center, safeUp(dir, {0, 1, 0}));
    proj = glm::ortho(-radius, radius, -radius, radius, 0.5f * radius, 3.5f * radius);
    s.orthoHalfExtent = radius;
    s.nearZ = 0.5f * radius;
    s.farZ = 3.5f * radius;
  } else {
    float fov = std::min(2.0f * light.spotOuterDeg, 170.0f);
    view = glm::lookAt(light.position, light.position + dir, safeUp(dir, {0, 1, 0}));
    proj = glm::perspective(glm::radians(fov), 1.0f, s.nearZ, s.farZ);
  }
  s.viewProj = proj * view;
}

void SharedPasses::buildShadowMap(int size) {
  ShadowMap& s = shadow_;
  s = ShadowMap{};
  transmittanceCleared_ = false;  // the transmittance map follows the shadow map's size and faces
  s.type = shadowMapType(scene_.light);
  s.size = size;
  fitShadowProjection();

  GLuint id = 0;
  if (s.type == LightType::Point) {
    s.depth = gl::createTextureCube(GL_DEPTH_COMPONENT32F, size);
    for (int f = 0; f < 6; ++f) {
      glCreateFramebuffers(1, &id);
      s.fbos[f] = gl::Framebuffer(id);
      glNamedFramebufferTextureLayer(id, GL_DEPTH_ATTACHMENT, s.depth.id(), 0, f);
      glNamedFramebufferDrawBuffer(id, GL_NONE);
      glNamedFramebufferReadBuffer(id, GL_NONE);
      gl::checkFramebuffer(id, "shadow cube face");
    }
  } else {
    s.depth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, size, size);
    glCreateFramebuffers(1, &id);
    s.fbos[0] = gl::Framebuffer(id);
    glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, s.depth.id(), 0);
    glNamedFramebufferDrawBuffer(id, GL_NONE);
    glNamedFramebufferReadBuffer(id, GL_NONE);
    gl::checkFramebuffer(id, "shadow map");
  }
  // Two samplers over the same depth: hardware-compared (PCF) and plain depth reads.
  glCreateSamplers(1, &id);
  s.compareSampler = gl::Sampler(id);
  glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glSamplerParameteri(id, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glCreateSamplers(1, &id);
  s.plainSampler = gl::Sampler(id);
  for (GLuint sampler : {s.compareSampler.id(), s.plainSampler.id()}) {
    GLint filter = sampler == s.compareSampler.id() ? GL_LINEAR : GL_NEAREST;
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, filter);
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, filter);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  }
}

void SharedPasses::setShadowMapSize(int size) {
  if (shadow_.size != size) buildShadowMap(size);
}

void SharedPasses::setAlphaTest(float threshold) {
  alphaTest_ = effects_.semiTransparent ? threshold : -1.0f;
  transmittanceCleared_ = false;
  if (alphaTest_ >= 0.0f && !alphaShadowProgram_)
    alphaShadowProgram_ = gl::buildProgram({{GL_VERTEX_SHADER, "harness/shaders/shadow.vert"},
                                            {GL_FRAGMENT_SHADER, "harness/shaders/shadow_alpha.frag"}});
}

void SharedPasses::lightMoved() {
  if (shadow_.size <= 0) return;
  if (shadow_.type == shadowMapType(scene_.light)) fitShadowProjection();
  else buildShadowMap(shadow_.size);
}

void SharedPasses::updateUniforms(uint32_t frameIndex, uint32_t seed) {
  frameIndex_ = frameIndex;
  seed_ = seed;
  const Camera& cam = scene_.camera;
  const Light& light = scene_.light;
  FrameUniforms& f = uniforms_;
  f.view = cameraView(cam);
  f.proj = cameraProjection(cam, float(width_) / float(std::max(height_, 1)));
  f.viewProj = f.proj * f.view;
  f.invViewProj = glm::inverse(f.viewProj);
  f.lightViewProj = shadow_.viewProj;
  f.lightView = glm::mat4(1.0f);
  f.eye = glm::vec4(cam.position, 0.0f);
  glm::vec3 forward = safeDirection(cam.target - cam.position, {0, 0, -1});
  f.cameraForward = glm::vec4(forward, std::tan(glm::radians(cam.fovYDeg) * 0.5f));
  f.lightPos = glm::vec4(light.position, float(lightTypeCode(light.type)));
  // Area lights: the colour carries radiance x area (the on-axis intensity) and the emission is a
  // cosine lobe about the normal, as for a cosine-lobed point light (a virtual point light).
  bool area = isAreaLight(light.type);
  bool lobe = area || (light.type == LightType::Point && light.cosineLobe);
  f.lightDir = glm::vec4(safeDirection(light.direction, {0, -1, 0}),
                         area ? (light.twoSided ? 1.0f : 0.0f) : std::cos(glm::radians(light.spotOuterDeg)));
  f.lightEmission = glm::vec4(lobe ? 1.0f : 0.0f, light.twoSided ? 1.0f : 0.0f, 0.0f, 0.0f);
  f.lightColor = glm::vec4(light.color * light.intensity * (area ? light.area() : 1.0f),
                           std::cos(glm::radians(light.spotInnerDeg)));
  f.shadowParams = glm::vec4(shadow_.nearZ, shadow_.farZ, float(shadow_.size), effects_.lightTexture ? 1.0f : 0.0f);
  const Medium& m = scene_.medium;
  f.medium = glm::vec4(m.sigmaS, m.sigmaA, m.sigmaT(), m.phase == Phase::HenyeyGreenstein ? m.g : 0.0f);
  f.cameraClip = glm::vec4(cam.nearZ, cam.farZ, m.phase == Phase::HenyeyGreenstein ? 1.0f : 0.0f,
                           shadow_.orthoHalfExtent);
  f.viewport = glm::ivec4(width_, height_, int(frameIndex), int(seed));
  glNamedBufferSubData(ubo_.id(), 0, sizeof(FrameUniforms), &f);
}

void Frame::bindShared() const {
  glBindBufferBase(GL_UNIFORM_BUFFER, bind::kFrameUniforms, uboId);
  bool cube = shadowMap.type == LightType::Point;
  glBindTextureUnit(cube ? bind::kShadowMapCube : bind::kShadowMap2D, shadowMap.depth.id());
  glBindSampler(cube ? bind::kShadowMapCube : bind::kShadowMap2D, shadowMap.compareSampler.id());
  glBindTextureUnit(cube ? bind::kShadowDepthCube : bind::kShadowDepth2D, shadowMap.depth.id());
  glBindSampler(cube ? bind::kShadowDepthCube : bind::kShadowDepth2D, shadowMap.plainSampler.id());
  glBindTextureUnit(bind::kLightTexture, lightTexture);
  glBindTextureUnit(bind::kGPosition, gPosition);
  glBindTextureUnit(bind::kGNormal, gNormal);
  glBindTextureUnit(bind::kGAlbedo, gAlbedo);
  if (volumes) volumes->bind();
  if (transmittance) transmittance->bind();
}

Frame SharedPasses::frame() const {
  return Frame{scene_,          geometry_,          effects_,          uniforms_,         shadow_,
               width_,          height_,            frameIndex_,       seed_,             gPosition_.id(),
               gNormal_.id(),   gAlbedo_.id(),      depth_.id(),       inscatter_.id(),   inscatterFbo_.id(),
               volumeTransmittance_.id(), direct_.id(),    directFbo_.id(),    lightTexture_.id(), ubo_.id(),        volumes_.get(),
               transmittance_.get(), shadowCasters_};
}

void SharedPasses::renderShadowMap(PassTimer& timer, const char* pass) {
  auto scope = timer.scope(pass);
  const ShadowMap& s = shadow_;
  glUseProgram(shadowProgram_.id());
  glViewport(0, 0, s.size, s.size);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);  // thin and open geometry casts shadows from both sides
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  const float one = 1.0f;
  int faces = s.type == LightType::Point ? 6 : 1;
  for (int f = 0; f < faces; ++f) {
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbos[f].id());
    glClearNamedFramebufferfv(s.fbos[f].id(), GL_DEPTH, 0, &one);
    const glm::mat4& m = s.type == LightType::Point ? s.faceViewProj[f] : s.viewProj;
    glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(m));
    if (shadowCasters_) geometry_.drawOpaque();
  }
  if (alphaTest_ >= 0.0f && shadowCasters_) {
    glUseProgram(alphaShadowProgram_.id());
    glUniform1f(1, alphaTest_);
    for (int f = 0; f < faces; ++f) {
      glBindFramebuffer(GL_FRAMEBUFFER, s.fbos[f].id());
      const glm::mat4& m = s.type == LightType::Point ? s.faceViewProj[f] : s.viewProj;
      glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(m));
      geometry_.drawTranslucent();
    }
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  if (transmittance_ && alphaTest_ >= 0.0f) {
    // Alpha-tested: the occluders are in the shadow map; the transmittance map says T = 1.
    if (!transmittanceCleared_) transmittance_->clear(s);
    transmittanceCleared_ = true;
  } else if (transmittance_) {
    // Semi-transparent occluders: their crossings per light texel (an empty map without casters).
    auto scopeT = timer.scope(kTransmittanceMapPass);
    const Light& light = scene_.light;
    if (shadowCasters_) transmittance_->render(s, light.position, glm::vec3(uniforms_.lightDir), lightTypeCode(light.type));
    else transmittance_->clear(s);
  }
}

void SharedPasses::renderGBuffer(PassTimer& timer) {
  auto scope = timer.scope(kGBufferPass);
  Frame f = frame();
  f.bindShared();
  glBindFramebuffer(GL_FRAMEBUFFER, gbufferFbo_.id());
  glViewport(0, 0, width_, height_);
  const float one = 1.0f;
  glClearNamedFramebufferfv(gbufferFbo_.id(), GL_DEPTH, 0, &one);
  // Sky first (no depth test/write), then the geometry over it.
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glUseProgram(skyProgram_.id());
  gl::drawFullscreenTriangle();
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glUseProgram(gbufferProgram_.id());
  geometry_.draw();
  glDisable(GL_DEPTH_TEST);
}

void SharedPasses::drawFullscreen(GLuint fbo, GLuint program) const {
  frame().bindShared();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glUseProgram(program);
  gl::drawFullscreenTriangle();
}

void SharedPasses::renderDirect(PassTimer& timer) {
  auto scope = timer.scope(kDirectLightingPass);
  drawFullscreen(directFbo_.id(), directProgram_.id());
}

void SharedPasses::clearShadowMap() {
  const float one = 1.0f;
  int faces = shadow_.type == LightType::Point ? 6 : 1;
  for (int f = 0; f < faces; ++f) glClearNamedFramebufferfv(shadow_.fbos[f].id(), GL_DEPTH, 0, &one);
  if (transmittance_) transmittance_->clear(shadow_);
}

void SharedPasses::clearInscatter() {
  const float nothing[4] = {0, 0, 0, 1}, clear[4] = {1, 1, 1, 1};  // no L_s, transmittance 1
  glClearNamedFramebufferfv(inscatterFbo_.id(), GL_COLOR, 0, nothing);
  if (effects_.volumeData) glClearNamedFramebufferfv(inscatterFbo_.id(), GL_COLOR, 1, clear);
}

void SharedPasses::composite(PassTimer& timer) {
  auto scope = timer.scope(kCompositePass);
  glBindTextureUnit(bind::kDirect, direct_.id());
  glBindTextureUnit(bind::kInscatter, inscatter_.id());
  if (effects_.volumeData) glBindTextureUnit(bind::kVolumeTransmittance, volumeTransmittance_.id());
  drawFullscreen(finalFbo_.id(), compositeProgram_.id());
  if (effects_.volumeData) glBindTextureUnit(bind::kVolumeTransmittance, 0);  // the next frame renders into it
}

Image SharedPasses::readTexture(GLuint texture) const {
  std::vector<float> rgba(size_t(width_) * height_ * 4);
  glFinish();
  glGetTextureImage(texture, 0, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)), rgba.data());
  Image img(width_, height_);
  for (int y = 0; y < height_; ++y) {
    const float* row = &rgba[size_t(height_ - 1 - y) * width_ * 4];  // GL rows start at the bottom
    for (int x = 0; x < width_; ++x) {
      float* dst = img.at(x, y);
      for (int c = 0; c < 3; ++c) dst[c] = row[x * 4 + c];
    }
  }
  return img;
}

Image SharedPasses::readInscatter() const { return readTexture(inscatter_.id()); }
Image SharedPasses::readFinal() const { return readTexture(final_.id()); }
Image SharedPasses::readDirect() const { return readTexture(direct_.id()); }

}  // namespace vs
