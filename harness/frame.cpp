#include "frame.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace vs {

// ---- cameras

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
  return "#define VS_LIGHT_TYPE " + std::to_string(lightTypeCode(effects.light)) + "\n#define VS_LIGHT_TEXTURE " +
         std::to_string(effects.lightTexture ? 1 : 0) + "\n#define VS_HG_PHASE " +
         std::to_string(effects.anisotropic ? 1 : 0) + "\n";
}

// ---- scene upload

SceneGpu::SceneGpu(const Scene& scene) {
  std::vector<float> vertexData;
  std::vector<uint32_t> indexData;
  for (const Mesh& mesh : scene.meshes) {
    uint32_t base = uint32_t(vertexData.size() / 9);
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const glm::vec3& p = mesh.positions[i];
      glm::vec3 n = i < mesh.normals.size() ? mesh.normals[i] : glm::vec3(0, 1, 0);
      vertexData.insert(vertexData.end(), {p.x, p.y, p.z, n.x, n.y, n.z, mesh.albedo.r, mesh.albedo.g, mesh.albedo.b});
    }
    for (uint32_t index : mesh.indices) indexData.push_back(base + index);
  }
  indexCount = GLsizei(indexData.size());
  vertices = gl::createBuffer(vertexData.size() * sizeof(float), vertexData.empty() ? nullptr : vertexData.data(), 0);
  indices = gl::createBuffer(indexData.size() * sizeof(uint32_t), indexData.empty() ? nullptr : indexData.data(), 0);
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  vao = gl::VertexArray(id);
  glVertexArrayVertexBuffer(id, 0, vertices.id(), 0, 9 * sizeof(float));
  glVertexArrayElementBuffer(id, indices.id());
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(id, a);
    glVertexArrayAttribFormat(id, a, 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
    glVertexArrayAttribBinding(id, a, 0);
  }
  scene.bounds(boundsLo, boundsHi);
}

void SceneGpu::draw() const {
  if (indexCount == 0) return;
  glBindVertexArray(vao.id());
  glDrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, nullptr);
}

// ---- shared passes

SharedPasses::SharedPasses(const Scene& scene, const SceneGpu& geometry, const Effects& effects, int width, int height)
    : scene_(scene), geometry_(geometry), effects_(effects), width_(width), height_(height) {
  ubo_ = gl::createBuffer(sizeof(FrameUniforms));
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
  inscatterFbo_ = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, inscatter_.id()}});
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

void SharedPasses::buildShadowMap(int size) {
  ShadowMap& s = shadow_;
  s = ShadowMap{};
  s.type = scene_.light.type;
  s.size = size;
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

  GLuint id = 0;
  if (s.type == LightType::Point) {
    s.depth = gl::createTextureCube(GL_DEPTH_COMPONENT32F, size);
    glm::mat4 proj = glm::perspective(glm::radians(90.0f), 1.0f, s.nearZ, s.farZ);
    const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    for (int f = 0; f < 6; ++f) {
      s.faceViewProj[f] = proj * glm::lookAt(light.position, light.position + axes[f], ups[f]);
      glCreateFramebuffers(1, &id);
      s.fbos[f] = gl::Framebuffer(id);
      glNamedFramebufferTextureLayer(id, GL_DEPTH_ATTACHMENT, s.depth.id(), 0, f);
      glNamedFramebufferDrawBuffer(id, GL_NONE);
      glNamedFramebufferReadBuffer(id, GL_NONE);
      gl::checkFramebuffer(id, "shadow cube face");
    }
  } else {
    s.depth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, size, size);
    glm::mat4 view, proj;
    if (s.type == LightType::Directional) {
      glm::vec3 dir = safeDirection(light.direction, {0, -1, 0});
      view = glm::lookAt(center - dir * (2.0f * radius), center, safeUp(dir, {0, 1, 0}));
      proj = glm::ortho(-radius, radius, -radius, radius, 0.5f * radius, 3.5f * radius);
      s.orthoHalfExtent = radius;
      s.nearZ = 0.5f * radius;
      s.farZ = 3.5f * radius;
    } else {
      glm::vec3 dir = safeDirection(light.direction, {0, -1, 0});
      float fov = std::min(2.0f * light.spotOuterDeg, 170.0f);
      view = glm::lookAt(light.position, light.position + dir, safeUp(dir, {0, 1, 0}));
      proj = glm::perspective(glm::radians(fov), 1.0f, s.nearZ, s.farZ);
    }
    s.viewProj = proj * view;
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
  f.lightDir = glm::vec4(safeDirection(light.direction, {0, -1, 0}), std::cos(glm::radians(light.spotOuterDeg)));
  f.lightColor = glm::vec4(light.color * light.intensity, std::cos(glm::radians(light.spotInnerDeg)));
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
}

Frame SharedPasses::frame() const {
  return Frame{scene_,          geometry_,          effects_,          uniforms_,         shadow_,
               width_,          height_,            frameIndex_,       seed_,             gPosition_.id(),
               gNormal_.id(),   gAlbedo_.id(),      depth_.id(),       inscatter_.id(),   inscatterFbo_.id(),
               direct_.id(),    directFbo_.id(),    lightTexture_.id(), ubo_.id()};
}

void SharedPasses::renderShadowMap(PassTimer& timer) {
  auto scope = timer.scope("Shadow Map");
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
    if (shadowCasters_) geometry_.draw();
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
}

void SharedPasses::renderGBuffer(PassTimer& timer) {
  auto scope = timer.scope("G Buffer");
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
  auto scope = timer.scope("Direct Lighting");
  drawFullscreen(directFbo_.id(), directProgram_.id());
}

void SharedPasses::clearShadowMap() {
  const float one = 1.0f;
  int faces = shadow_.type == LightType::Point ? 6 : 1;
  for (int f = 0; f < faces; ++f) glClearNamedFramebufferfv(shadow_.fbos[f].id(), GL_DEPTH, 0, &one);
}

void SharedPasses::clearInscatter() {
  const float nothing[4] = {0, 0, 0, 1};  // no L_s, transmittance 1
  glClearNamedFramebufferfv(inscatterFbo_.id(), GL_COLOR, 0, nothing);
}

void SharedPasses::composite(PassTimer& timer) {
  auto scope = timer.scope("Composite");
  glBindTextureUnit(bind::kDirect, direct_.id());
  glBindTextureUnit(bind::kInscatter, inscatter_.id());
  drawFullscreen(finalFbo_.id(), compositeProgram_.id());
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
