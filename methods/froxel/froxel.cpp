#include "froxel.hpp"

#include <cmath>
#include <glm/glm.hpp>

#include "registry.hpp"

namespace vs {

static constexpr const char* kScatteringPass = "Froxel Scattering";
static constexpr const char* kIntegrationPass = "Froxel Integration";
static constexpr const char* kApplyPass = "Froxel Apply";
// Texture memory of the grid's four RGBA32F volumes, at most (a bad tile and slice pair fails the
// run with a reason instead of exhausting the device).
static constexpr double kMaxGridBytes = 1024.0 * 1024.0 * 1024.0;
static constexpr GLuint kScatteringUnit = 10, kExtinctionUnit = 11;
static constexpr GLuint kScatteringHistoryUnit = 12, kExtinctionHistoryUnit = 13;

// std140 mirror of FroxelBlock in shaders/froxel.glsl.
struct FroxelUniforms {
  glm::ivec4 grid;  // width, height, slices, tile
  glm::vec4 range;  // unused, exponential, samples, jitter offset
  glm::mat4 previousViewProj;
  glm::vec4 previousEye;  // w: weight of the history (0: none)
};
VS_STD140_MIRROR(FroxelUniforms, "FroxelBlock", VS_STD140_FIELD(FroxelUniforms, grid), VS_STD140_FIELD(FroxelUniforms, range), VS_STD140_FIELD(FroxelUniforms, previousViewProj), VS_STD140_FIELD(FroxelUniforms, previousEye));

std::string FroxelMethod::description() const {
  return "froxel: frustum-voxel volumetric fog (Wronski 2014, Hillaire 2015), in-scattering on a camera grid "
         "integrated front to back";
}

Capabilities FroxelMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = true;
  c.cosineLobe = true;  // area lights through the per-VPL wrapper (vpls=N)
  c.texturedLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  c.volumeData = true;
  c.semiTransparentOccluders = true;
  c.coloredShadows = true;
  return c;
}

std::vector<ParamSpec> FroxelMethod::params() const {
  return {ParamSpec::integer("tile", 8, 1, 64, "froxel width and height in pixels"),
          ParamSpec::integer("slices", 64, 4, 512, "depth slices between the eye and the camera's far distance"),
          ParamSpec::choice("dist", "exp", {"exp", "linear"},
                            "depth distribution of the slices: exponential (the last 256x deeper than the first) or linear"),
          ParamSpec::integer("samples", 1, 1, 16, "stratified samples per froxel along its slice"),
          ParamSpec::flag("jitter", false, "a new random offset of the samples in every frame (noise without temporal reprojection)"),
          ParamSpec::real("temporal", 0.0, 0.0, 0.98,
                          "temporal reprojection: weight of the previous frame's reprojected grid in each froxel, "
                          "with the samples jittered every frame (0: off)"),
          ParamSpec::integer("light_steps", 64, 1, 512, "volume data: steps per volume towards the light from each sample")};
}

std::vector<std::string> FroxelMethod::passes() const { return {kScatteringPass, kIntegrationPass, kApplyPass}; }

// From game settings (a 160x90x64 grid at 1280x720 is tile=8:slices=64) to fine grids.
std::vector<std::string> FroxelMethod::qualityLadder() const {
  return {"tile=16:slices=32", "tile=8:slices=64", "tile=4:slices=128", "tile=2:slices=256"};
}

// The grids without history, and the same grids as engines run them, with temporal reprojection.
std::vector<Method::QualitySeries> FroxelMethod::qualitySeries(const Effects& effects) const {
  (void)effects;
  QualitySeries temporal{"temporal", {}};
  for (const std::string& rung : qualityLadder()) temporal.rungs.push_back(rung + ":temporal=0.9");
  return {{"grid", qualityLadder()}, temporal};
}

std::vector<std::string> FroxelMethod::approximations() const {
  return {"in-scattering sampled on a froxel grid (one ray per tile), interpolated between froxels",
          "source and extinction constant within a froxel"};
}

// The grid's resolution is its error floor, and the hard cases render 64x48 images, where the
// default 8-pixel tile is an 8x6 grid: a point light inside a volume (the light in view, its 1/r^2
// sampled once per froxel) measured relMSE 0.16. Every other hard case stays under 0.05.
double FroxelMethod::declaredRelMseBound() const { return 0.2; }

void FroxelMethod::setup(const SetupContext& context, const ParamValues& params) {
  tile_ = params.getInt("tile");
  slices_ = params.getInt("slices");
  exponential_ = params.getString("dist") == "exp";
  samples_ = params.getInt("samples");
  jitter_ = params.getBool("jitter");
  lightSteps_ = params.getInt("light_steps");
  temporal_ = float(params.getFloat("temporal"));
  historyFrames_ = 0;
  current_ = 0;
  volumes_ = context.effects.volumeData;
  gridW_ = (context.width + tile_ - 1) / tile_;
  gridH_ = (context.height + tile_ - 1) / tile_;
  const int max3d = context.limits.maxTexture3DSize;
  if (gridW_ > max3d || gridH_ > max3d || slices_ > max3d)
    throw std::runtime_error("froxel grid " + std::to_string(gridW_) + "x" + std::to_string(gridH_) + "x" +
                             std::to_string(slices_) + " exceeds this GL implementation's 3D texture limit of " +
                             std::to_string(max3d));
  const double bytes = double(gridW_) * gridH_ * slices_ * 16.0 * (volumes_ ? 4 : 2) * (params.getFloat("temporal") > 0 ? 1.5 : 1.0);
  if (bytes > kMaxGridBytes)
    throw std::runtime_error("froxel grid " + std::to_string(gridW_) + "x" + std::to_string(gridH_) + "x" +
                             std::to_string(slices_) + " needs " + std::to_string(int(bytes / 1048576.0)) +
                             " MB, over the 1024 MB cap: raise tile or lower slices");
  // The history (the second scattering and extinction textures) only with temporal reprojection;
  // it is read trilinearly at reprojected positions.
  const int buffers = temporal_ > 0.0f ? 2 : 1;
  for (int i = 0; i < 2; ++i) {
    scattering_[i] = i < buffers ? gl::createTexture3D(GL_RGBA32F, gridW_, gridH_, slices_) : gl::Texture();
    extinction_[i] = i < buffers && volumes_ ? gl::createTexture3D(GL_RGBA32F, gridW_, gridH_, slices_) : gl::Texture();
    if (scattering_[i]) gl::setFilter(scattering_[i].id(), GL_LINEAR, GL_LINEAR);
    if (extinction_[i]) gl::setFilter(extinction_[i].id(), GL_LINEAR, GL_LINEAR);
  }
  integrated_ = gl::createTexture3D(GL_RGBA32F, gridW_, gridH_, slices_);
  gl::setFilter(integrated_.id(), GL_LINEAR, GL_LINEAR);
  opticalDepth_ = volumes_ ? gl::createTexture3D(GL_RGBA32F, gridW_, gridH_, slices_) : gl::Texture();
  if (opticalDepth_) gl::setFilter(opticalDepth_.id(), GL_LINEAR, GL_LINEAR);
  ubo_ = gl::createBuffer(sizeof(FroxelUniforms));
  const std::string defines = sceneDefines(context.effects);
  scatterProgram_ = gl::buildCompute("methods/froxel/shaders/scatter.comp", defines);
  integrateProgram_ = gl::buildCompute("methods/froxel/shaders/integrate.comp", defines);
  applyProgram_ = gl::buildFullscreen("methods/froxel/shaders/apply.frag", defines);
}

void FroxelMethod::render(const Frame& frame, PassTimer& timer) {
  // Samples at the centres of `samples` strata of each slice, or at one random offset per frame.
  float offset = 0.5f;
  const bool temporal = temporal_ > 0.0f;
  if (jitter_ || temporal) {
    uint32_t h = (frame.frameIndex + 1u) * 747796405u + frame.seed * 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    offset = float((h >> 22u) ^ h) / 4294967296.0f;
  }
  // The history is the previous frame's grid, when this frame follows it (a run's frames do; a
  // viewer that seeks or a method set up again starts without).
  const bool history = temporal && historyFrames_ > 0 && frame.frameIndex == historyFrame_ + 1;
  if (temporal && !history) historyFrames_ = 0;
  if (temporal) current_ = 1 - current_;
  const int cur = temporal ? current_ : 0;
  FroxelUniforms uniforms{{gridW_, gridH_, slices_, tile_},
                          {0.0f, exponential_ ? 1.0f : 0.0f, float(samples_), offset},
                          previousViewProj_,
                          glm::vec4(glm::vec3(previousEye_), history ? temporal_ : 0.0f)};
  glNamedBufferSubData(ubo_.id(), 0, sizeof uniforms, &uniforms);
  frame.bindShared();
  glBindBufferBase(GL_UNIFORM_BUFFER, 3, ubo_.id());
  {
    auto scope = timer.scope(kScatteringPass);
    glUseProgram(scatterProgram_.id());
    glUniform1i(0, lightSteps_);
    glBindImageTexture(0, scattering_[cur].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    if (volumes_) glBindImageTexture(1, extinction_[cur].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    if (temporal) {
      glBindTextureUnit(kScatteringHistoryUnit, scattering_[1 - cur].id());
      glBindSampler(kScatteringHistoryUnit, 0);
      if (volumes_) {
        glBindTextureUnit(kExtinctionHistoryUnit, extinction_[1 - cur].id());
        glBindSampler(kExtinctionHistoryUnit, 0);
      }
    }
    glDispatchCompute(GLuint((gridW_ + 3) / 4), GLuint((gridH_ + 3) / 4), GLuint((slices_ + 3) / 4));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  }
  {
    auto scope = timer.scope(kIntegrationPass);
    glUseProgram(integrateProgram_.id());
    glBindTextureUnit(kScatteringUnit, scattering_[cur].id());
    glBindSampler(kScatteringUnit, 0);
    glBindImageTexture(0, integrated_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    if (volumes_) {
      glBindTextureUnit(kExtinctionUnit, extinction_[cur].id());
      glBindSampler(kExtinctionUnit, 0);
      glBindImageTexture(1, opticalDepth_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    }
    glDispatchCompute(GLuint((gridW_ + 7) / 8), GLuint((gridH_ + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  }
  {
    auto scope = timer.scope(kApplyPass);
    glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
    glViewport(0, 0, frame.width, frame.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(applyProgram_.id());
    glBindTextureUnit(kScatteringUnit, integrated_.id());
    glBindSampler(kScatteringUnit, 0);
    if (volumes_) {
      glBindTextureUnit(kExtinctionUnit, opticalDepth_.id());
      glBindSampler(kExtinctionUnit, 0);
    }
    gl::drawFullscreenTriangle();
  }
  glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  if (temporal) {
    historyFrame_ = frame.frameIndex;
    historyFrames_ = history ? historyFrames_ + 1 : 1;
    previousViewProj_ = frame.uniforms.viewProj;
    previousEye_ = frame.uniforms.eye;
  }
}

// How much history the last frame had: a still frame after N frames of reprojection is not a
// single frame's cost (the warm-up frames are its history).
std::map<std::string, double> FroxelMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  (void)passes;
  if (temporal_ <= 0.0f) return {};
  return {{"history_frames", double(std::max(historyFrames_ - 1, 0))}};
}

std::vector<DebugView> FroxelMethod::debugViews() const {
  DebugView integrated;
  integrated.name = "integrated L_s (slice = layer)";
  integrated.texture = integrated_.id();
  integrated.layers = slices_;
  integrated.channels = 3;
  DebugView scattering;
  scattering.name = "in-scattering per froxel (slice = layer)";
  scattering.texture = scattering_[temporal_ > 0.0f ? current_ : 0].id();
  scattering.layers = slices_;
  scattering.channels = 3;
  return {integrated, scattering};
}

// After the papers' methods (registry.hpp): the production baseline they are measured against.
VS_REGISTER_METHOD(FroxelMethod, 60);

}  // namespace vs
