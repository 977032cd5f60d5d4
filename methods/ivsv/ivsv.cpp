#include "ivsv.hpp"
#include "registry.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "harness/pipeline/vpl.hpp"

namespace vs {

static constexpr const char* kVplSampling = "VPL Sampling";
static constexpr const char* kIsm = "Imperfect Shadow Maps";
static constexpr const char* kVoxelize = "Voxelize";
static constexpr const char* kScan = "Scan";
static constexpr const char* kGather = "Final Gather";
static constexpr int kPhiBits = 128;  // kPhiBits in shaders/ivsv.glsl

// std430 mirror of Vpl.
struct VplGpu {
  glm::vec4 position, axis, e1, e2;
};

VS_STD140_MIRROR(ivsv::Uniforms, "IvsvBlock", VS_STD140_FIELD(ivsv::Uniforms, dims), VS_STD140_FIELD(ivsv::Uniforms, counts), VS_STD140_FIELD(ivsv::Uniforms, tangent), VS_STD140_FIELD(ivsv::Uniforms, bitangent), VS_STD140_FIELD(ivsv::Uniforms, normal), VS_STD140_FIELD(ivsv::Uniforms, weight));

namespace ivsv {

std::vector<glm::vec4> samplePointCloud(const Scene& scene, size_t count, uint32_t seed, float alphaTest) {
  struct Tri {
    glm::vec3 a, b, c;
    const Mesh* mesh;
    uint32_t i0, i1, i2;
  };
  // Opaque meshes always; alpha-tested runs add the semi-transparent ones that block at the
  // threshold (textured ones texel by texel, below).
  auto blocks = [&](const Mesh& m) {
    if (m.isOpaque()) return true;
    if (alphaTest < 0.0f || m.opacity <= 0.0f) return false;
    return m.alphaTexture >= 0 || m.opacityAt(1.0f) >= alphaTest;
  };
  std::vector<Tri> tris;
  std::vector<double> cumulative;
  double total = 0.0;
  for (const Mesh& mesh : scene.meshes) {
    if (!blocks(mesh)) continue;
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      Tri t{mesh.positions[mesh.indices[i]], mesh.positions[mesh.indices[i + 1]], mesh.positions[mesh.indices[i + 2]],
            &mesh, mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
      double area = 0.5 * glm::length(glm::cross(glm::dvec3(t.b - t.a), glm::dvec3(t.c - t.a)));
      if (!(area > 0.0) || !std::isfinite(area)) continue;
      total += area;
      tris.push_back(t);
      cumulative.push_back(total);
    }
  }
  std::vector<glm::vec4> points;
  if (tris.empty() || count == 0) return points;
  points.reserve(count);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  // A point on a textured mesh whose texel does not block is drawn again (a bounded number of times:
  // a texture that blocks nowhere leaves fewer points).
  for (size_t i = 0, attempts = 0; i < count && attempts < 16 * count; ++attempts) {
    double pick = uniform(rng) * total;
    size_t index = size_t(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    const Tri& t = tris[std::min(index, tris.size() - 1)];
    double u = uniform(rng), v = uniform(rng);
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const Mesh& m = *t.mesh;
    if (!m.isOpaque() && m.alphaTexture >= 0 && size_t(m.alphaTexture) < scene.alphaTextures.size() &&
        std::max({t.i0, t.i1, t.i2}) < m.uvs.size()) {
      glm::vec2 uv = m.uvs[t.i0] + float(u) * (m.uvs[t.i1] - m.uvs[t.i0]) + float(v) * (m.uvs[t.i2] - m.uvs[t.i0]);
      if (m.opacityAt(scene.alphaTextures[size_t(m.alphaTexture)].sample(uv)) < alphaTest) continue;
    }
    glm::vec3 p = t.a + float(u) * (t.b - t.a) + float(v) * (t.c - t.a);
    points.emplace_back(p, 1.0f);
    ++i;
  }
  return points;
}

glm::vec2 paraboloid(const glm::vec3& d, const glm::vec3& t, const glm::vec3& b, const glm::vec3& normal) {
  float z = std::max(glm::dot(d, normal), 0.0f);
  return glm::vec2(glm::dot(d, t), glm::dot(d, b)) / (1.0f + z);
}

}  // namespace ivsv

std::string IvsvMethod::description() const {
  return "imperfect voxelized shadow volumes: area light as VPLs, coarse epipolar VSV grids from imperfect shadow "
         "maps, one packed prefix-OR scan, interpolated final gather";
}

Capabilities IvsvMethod::capabilities() const {
  Capabilities c;
  c.areaLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  c.alphaTestedOccluders = true;  // ISM points only where the occluder blocks at alpha_test
  return c;
}

std::vector<std::string> IvsvMethod::passes() const { return {kVplSampling, kIsm, kVoxelize, kScan, kGather}; }

std::vector<ParamSpec> IvsvMethod::params() const {
  return {ParamSpec::integer("lights", 64, 1, 1024, "virtual point lights on the area light (the paper: 256)"),
          ParamSpec::integer("grid", 128, 16, 512, "N_alpha = N_theta of each VPL's grid (N_phi is 128 bits; the paper: 128^3)"),
          ParamSpec::integer("points", 4096, 16, 65536, "ISM points splatted per VPL"),
          ParamSpec::integer("ism", 64, 16, 512, "ISM tile texels per side (paraboloid over the lit hemisphere)").pow2(),
          ParamSpec::integer("pullpush", 3, 0, 9, "pull-push levels that fill the ISM's holes (0: none)"),
          ParamSpec::real("bias", 2.0, 0.0, 16.0, "ISM depth bias along the light ray, in texel angles of the ISM"),
          ParamSpec::flag("interp", true, "interpolate visibility bilinearly in (alpha, theta) in the final gather"),
          ParamSpec::integer("steps", 16, 1, 4096, "final-gather steps along the camera ray, equiangular around each VPL"),
          ParamSpec::flag("jitter", true, "stratified jitter of the gather steps")};
}

std::vector<std::string> IvsvMethod::qualityLadder() const {
  return {"lights=16:grid=64:points=1024:ism=32:steps=8", "lights=64:grid=128:points=4096:ism=64:steps=16",
          "lights=256:grid=128:points=4096:ism=64:steps=16", "lights=256:grid=128:points=8192:ism=64:steps=32"};
}

std::string IvsvMethod::unsupportedReason(const Scene& scene, const ParamValues& params) const {
  std::string base = Method::unsupportedReason(scene, params);
  if (!base.empty()) return base;
  if (scene.light.twoSided) return "two-sided area lights are not supported (one paraboloid ISM per VPL)";
  if (params.getInt("pullpush") > int(std::log2(double(params.getInt("ism")))))
    return "pullpush exceeds log2(ism) levels";
  return "";
}

void IvsvMethod::setup(const SetupContext& context, const ParamValues& params) {
  count_ = params.getInt("lights");
  grid_ = params.getInt("grid");
  pointsPerLight_ = params.getInt("points");
  ismRes_ = params.getInt("ism");
  pullPushLevels_ = std::min(params.getInt("pullpush"), int(std::log2(double(ismRes_))));
  interpolate_ = params.getBool("interp");
  bias_ = float(params.getFloat("bias"));
  steps_ = params.getInt("steps");
  jitter_ = params.getBool("jitter");
  const Light& light = context.scene.light;
  positions_ = virtualPointLightPositions(light, count_);
  normal_ = glm::normalize(light.direction);
  tangent_ = light.tangent - normal_ * glm::dot(light.tangent, normal_);
  if (glm::length(tangent_) < 1e-6f) tangent_ = std::fabs(normal_.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  tangent_ = glm::normalize(tangent_ - normal_ * glm::dot(tangent_, normal_));
  bitangent_ = glm::cross(normal_, tangent_);
  glm::vec3 lo = context.geometry.boundsLo, hi = context.geometry.boundsHi;
  far_ = std::max(1.01f * (glm::length(hi - lo) + glm::length(light.position - 0.5f * (lo + hi)) +
                           std::max({light.width, light.height, light.radius})),
                  1e-3f);
  minDistance_ = std::max(1e-4f * far_, context.scene.camera.nearZ);

  tiles_ = int(std::ceil(std::sqrt(double(count_))));
  int atlas = tiles_ * ismRes_;
  if (atlas > context.limits.maxTextureSize)
    throw std::runtime_error("ivsv: ISM atlas " + std::to_string(atlas) + "^2 exceeds the GL limits");
  GLint maxLayers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (count_ > maxLayers) throw std::runtime_error("ivsv: more VPLs than GL_MAX_ARRAY_TEXTURE_LAYERS");
  double gridBytes = double(grid_) * grid_ * 16.0 * count_;
  if (gridBytes > double(1u << 30)) throw std::runtime_error("ivsv: packed grids over 1 GiB");

  std::vector<glm::vec4> cloud =
      ivsv::samplePointCloud(context.scene, size_t(pointsPerLight_) * size_t(count_), 0x1f5e3u, context.alphaTest);
  if (cloud.empty()) cloud.emplace_back(0.0f, 0.0f, 0.0f, 1.0f);  // no occluders: one point behind nothing
  points_ = gl::createBuffer(cloud.size() * sizeof(glm::vec4), cloud.data(), 0);
  pointsTotal_ = cloud.size() == size_t(pointsPerLight_) * size_t(count_) ? GLsizei(cloud.size()) : 0;
  lights_ = gl::createBuffer(sizeof(VplGpu) * size_t(count_));
  ubo_ = gl::createBuffer(sizeof(ivsv::Uniforms));

  ism_ = gl::createTexture2D(GL_R32F, atlas, atlas, pullPushLevels_ + 1);
  gl::setFilter(ism_.id(), GL_NEAREST_MIPMAP_NEAREST, GL_NEAREST);
  splats_ = gl::createTexture2D(GL_R32UI, atlas, atlas);
  gl::setFilter(splats_.id(), GL_NEAREST, GL_NEAREST);
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
  grids_ = gl::Texture(id);
  glTextureStorage3D(id, 1, GL_RGBA32UI, grid_, grid_, count_);
  gl::setFilter(id, GL_NEAREST, GL_NEAREST);  // integer textures are incomplete otherwise
  scan_ = std::make_unique<epipolar::Scan>();

  voxelizeRows_ = std::clamp(1024 / grid_, 1, 8);  // 16 KiB of shared words per workgroup
  const std::string defines = sceneDefines(context.effects) + "#define IVSV_GRID " + std::to_string(grid_) +
                              "\n#define IVSV_ROWS " + std::to_string(voxelizeRows_) + "\n#define IVSV_BIAS " +
                              std::to_string(bias_) +
                              "\n#define IVSV_INTERPOLATE " + (interpolate_ ? "1" : "0") + "\n";
  splat_ = gl::buildCompute("methods/ivsv/shaders/ism_splat.comp", defines);
  resolve_ = gl::buildCompute("methods/ivsv/shaders/ism_resolve.comp");
  pullPush_ = gl::buildCompute("methods/ivsv/shaders/pullpush.comp");
  voxelize_ = gl::buildCompute("methods/ivsv/shaders/voxelize.comp", defines);
  gather_ = gl::buildFullscreen("methods/ivsv/shaders/gather.frag", defines);
  // llvmpipe's loop budget (harness/gl/gl.hpp): a gather pass takes as many VPLs as fit.
  lightsPerGatherPass_ = std::clamp((gl::kShaderLoopBudget - 64) / (steps_ + 2), 1, count_);
}

void IvsvMethod::sampleLights(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kVplSampling);
  const Light& light = frame.scene.light;
  glm::dvec3 eye(frame.scene.camera.position), forward(frame.uniforms.cameraForward);
  std::vector<VplGpu> gpu(static_cast<size_t>(count_));
  for (int k = 0; k < count_; ++k) {
    epipolar::EpipolarBasis b = epipolar::makeBasis(eye, glm::dvec3(positions_[size_t(k)]), forward, double(minDistance_));
    gpu[size_t(k)] = {glm::vec4(glm::vec3(b.light), 1.0f), glm::vec4(glm::vec3(b.axis), float(b.distance)),
                      glm::vec4(glm::vec3(b.e1), 0.0f), glm::vec4(glm::vec3(b.e2), 0.0f)};
  }
  glNamedBufferSubData(lights_.id(), 0, GLsizeiptr(gpu.size() * sizeof(VplGpu)), gpu.data());
  ivsv::Uniforms un{};
  un.dims = glm::ivec4(count_, grid_, tiles_, ismRes_);
  un.counts = glm::ivec4(pointsPerLight_, steps_, 0, count_);
  un.tangent = glm::vec4(tangent_, 0.0f);
  un.bitangent = glm::vec4(bitangent_, 0.0f);
  un.normal = glm::vec4(normal_, far_);
  un.weight = glm::vec4(light.color * light.intensity * light.area() / float(count_), jitter_ ? 1.0f : 0.0f);
  uniforms_ = un;
  glNamedBufferSubData(ubo_.id(), 0, sizeof un, &un);
  glBindBufferBase(GL_UNIFORM_BUFFER, 3, ubo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, points_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, lights_.id());
}

void IvsvMethod::renderImperfectShadowMaps(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kIsm);
  int atlas = tiles_ * ismRes_;
  // Splat: a compute scatter with atomicMin (points cost a triangle set-up each when rasterized).
  const GLuint empty = 0xffffffffu;
  glClearTexImage(splats_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &empty);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  glBindImageTexture(3, splats_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  if (frame.shadowCasters && pointsTotal_ > 0) {
    glUseProgram(splat_.id());
    glUniform1i(0, pointsTotal_);
    GLuint groups = GLuint((pointsTotal_ + 63) / 64), x = std::min<GLuint>(groups, 65535u);
    glDispatchCompute(x, (groups + x - 1) / x, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  glUseProgram(resolve_.id());
  glBindImageTexture(0, ism_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glDispatchCompute(GLuint((atlas + 7) / 8), GLuint((atlas + 7) / 8), 1);
  // Pull up the levels, then push back down into the holes.
  glUseProgram(pullPush_.id());
  for (int pass = 0; pass < 2; ++pass) {
    for (int step = 0; step < pullPushLevels_; ++step) {
      int level = pass == 0 ? step : pullPushLevels_ - 1 - step;  // fine level of this step
      glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
      glBindImageTexture(0, ism_.id(), level, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
      glBindImageTexture(1, ism_.id(), level + 1, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
      glUniform1i(0, pass);
      int size = std::max(atlas >> (pass == 0 ? level + 1 : level), 1);
      glDispatchCompute(GLuint((size + 7) / 8), GLuint((size + 7) / 8), 1);
    }
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void IvsvMethod::voxelize(PassTimer& timer) {
  {
    auto scope = timer.scope(kVoxelize);
    glUseProgram(voxelize_.id());
    glBindTextureUnit(bind::kFirstMethodUnit, ism_.id());
    glBindImageTexture(2, grids_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    glDispatchCompute(GLuint((grid_ + voxelizeRows_ - 1) / voxelizeRows_), GLuint(count_), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  }
  auto scope = timer.scope(kScan);
  scan_->run(grids_.id(), grid_, grid_, count_);  // every VPL's grid in one pass
}

void IvsvMethod::gather(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kGather);
  glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
  glViewport(0, 0, frame.width, frame.height);
  const float clear[4] = {0, 0, 0, 1};
  glClearNamedFramebufferfv(frame.inscatterFbo, GL_COLOR, 0, clear);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ZERO, GL_ONE);  // L_s adds up over passes; alpha stays 1
  glUseProgram(gather_.id());
  glBindTextureUnit(bind::kFirstMethodUnit + 1, grids_.id());
  for (int first = 0; first < count_; first += lightsPerGatherPass_) {
    ivsv::Uniforms un = uniforms_;
    un.counts.z = first;
    un.counts.w = std::min(lightsPerGatherPass_, count_ - first);
    glNamedBufferSubData(ubo_.id(), 0, sizeof un, &un);
    gl::drawFullscreenTriangle();
  }
  glDisable(GL_BLEND);
}

void IvsvMethod::render(const Frame& frame, PassTimer& timer) {
  frame.bindShared();
  sampleLights(frame, timer);
  renderImperfectShadowMaps(frame, timer);
  voxelize(timer);
  gather(frame, timer);
}

std::map<std::string, double> IvsvMethod::stats(const std::map<std::string, TimingStats>&) const {
  return {{"vpls", double(count_)},
          {"voxels", double(grid_) * grid_ * kPhiBits * count_},
          {"ism_points", double(pointsTotal_)}};
}

std::vector<DebugView> IvsvMethod::debugViews() const {
  if (!grids_) return {};
  return {{"ISM atlas (distance / far)", ism_.id(), DebugView::Kind::Value, 1, pullPushLevels_ + 1, 1, 0.0f, 1.0f},
          {"VPL 0 grid (phi slices)", grids_.id(), DebugView::Kind::Bits, kPhiBits}};
}

VS_REGISTER_METHOD(IvsvMethod, 50);

}  // namespace vs
