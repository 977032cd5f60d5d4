#include "minmax.hpp"
#include "registry.hpp"

#include <algorithm>
#include <cmath>

namespace vs {

namespace {
constexpr const char* kRectifyPass = "Shadow Map Rectification";
constexpr const char* kLowRankPass = "Low-Rank Approximation";
constexpr const char* kLightTexturePass = "Light Texture Precomputation";
constexpr const char* kMipmapPass = "Mipmap Construction";
constexpr const char* kIntegrationPass = "Integration";
constexpr const char* kNearEpipolePass = "Near Epipole";
constexpr int kPrefixRes = 1024;  // samples of the untextured prefix tables over gammaAll
constexpr int kMaxRank = 16;      // kMaxRank in shaders/epipolar.glsl
constexpr int kMipmapBlock = 16;  // kBlock in shaders/mipmap.comp: nodes reduced per invocation
constexpr int kRectifyBlock = 16;  // kBlock in shaders/rectify.comp: leaves rectified per invocation

// Texture units after bind::kFirstMethodUnit (see the shaders).
constexpr GLuint kUnitTree = 10, kUnitBasisBeta = 11, kUnitGammaPrefix = 12, kUnitTexturedPrefix = 13,
                 kUnitBasisGamma = 14;
constexpr GLuint kEpipolarUboBinding = 3;  // EpipolarBlock in shaders/epipolar.glsl

// std140 mirror of EpipolarBlock in shaders/epipolar.glsl.
struct EpipolarUniforms {
  glm::mat4 invLightViewProj;
  glm::vec4 axis, basis0, basis1, gammaInfo, betaInfo, epipoleInfo;
  glm::ivec4 counts, flags;
};
VS_STD140_MIRROR(EpipolarUniforms, "EpipolarBlock", VS_STD140_FIELD(EpipolarUniforms, invLightViewProj), VS_STD140_FIELD(EpipolarUniforms, axis), VS_STD140_FIELD(EpipolarUniforms, basis0), VS_STD140_FIELD(EpipolarUniforms, basis1), VS_STD140_FIELD(EpipolarUniforms, gammaInfo), VS_STD140_FIELD(EpipolarUniforms, betaInfo), VS_STD140_FIELD(EpipolarUniforms, epipoleInfo), VS_STD140_FIELD(EpipolarUniforms, counts), VS_STD140_FIELD(EpipolarUniforms, flags));

int nextPowerOfTwo(int v) {
  int p = 1;
  while (p < v) p <<= 1;
  return p;
}

// `invocations` in groups of 64, laid out in rows within the 65535 groups guaranteed per axis.
void dispatchBlocks(long invocations) {
  long groups = (invocations + 63) / 64, columns = std::clamp(groups, 1L, 32768L);
  glDispatchCompute(GLuint(columns), GLuint((groups + columns - 1) / columns), 1);
}

int rankGroups(int rank) { return (rank + 3) / 4; }

// rows x columns floats (row i = rank i) as ceil(rows / 4) rows of RGBA texels, four ranks per
// texel, the missing ranks 0: what the Integration shader reads with one fetch per four ranks.
std::vector<float> packRanks(const std::vector<float>& values, int rows, int columns, int allocatedRows) {
  std::vector<float> packed(size_t(rankGroups(allocatedRows)) * size_t(columns) * 4, 0.0f);
  for (int i = 0; i < rows; ++i)
    for (int x = 0; x < columns; ++x)
      packed[(size_t(i / 4) * size_t(columns) + size_t(x)) * 4 + size_t(i % 4)] = values[size_t(i) * size_t(columns) + size_t(x)];
  return packed;
}

// The view as computeEpipolarFrame reads it.
minmax::ViewInput viewInput(const Frame& frame, double epipoleRadius) {
  const FrameUniforms& fu = frame.uniforms;
  minmax::ViewInput in;
  in.viewProj = glm::dmat4(fu.viewProj);
  in.invViewProj = glm::dmat4(fu.invViewProj);
  in.eye = glm::dvec3(fu.eye);
  in.forward = glm::dvec3(fu.cameraForward);
  in.farZ = fu.cameraClip.y;
  in.width = frame.width;
  in.height = frame.height;
  in.directional = frame.scene.light.type == LightType::Directional;
  in.lightPos = glm::dvec3(fu.lightPos);
  in.lightTravelDir = glm::dvec3(fu.lightDir);
  in.boundsLo = glm::dvec3(frame.geometry.boundsLo);
  in.boundsHi = glm::dvec3(frame.geometry.boundsHi);
  in.epipoleRadius = epipoleRadius;
  return in;
}

// Pixels around the epipole that the Near Epipole pass marches, as the shaders get it
// (epipoleInfo.x); -1 when there is no epipole.
float nearEpipoleRadius(const minmax::EpipolarFrame& e, double epipoleRadius) {
  return e.epipoleValid ? float(epipoleRadius) : -1.0f;
}

// The Near Epipole pass's pixels (x0, y0, x1, y1): the square around the epipole within the
// viewport; the whole viewport when the light is at the eye; empty when there is no epipole.
glm::ivec4 nearEpipoleRect(const minmax::EpipolarFrame& e, float radius, int width, int height) {
  int x0 = 0, y0 = 0, x1 = width, y1 = height;
  if (!e.degenerate) {
    double r = radius;
    glm::dvec2 p = e.epipolePixel;
    if (r <= 0.0 || !std::isfinite(p.x) || !std::isfinite(p.y)) {
      x1 = x0;
    } else {
      x0 = int(std::clamp(std::floor(p.x - r), 0.0, double(width)));
      x1 = int(std::clamp(std::ceil(p.x + r), 0.0, double(width)));
      y0 = int(std::clamp(std::floor(p.y - r), 0.0, double(height)));
      y1 = int(std::clamp(std::ceil(p.y + r), 0.0, double(height)));
    }
  }
  return glm::ivec4(x0, y0, x1, y1);
}
}  // namespace

std::string MinmaxMethod::description() const {
  return "Chen et al. 2011: epipolar rectification, 1D min-max mipmaps per slice, low-rank integrand";
}

Capabilities MinmaxMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = true;
  c.cosineLobe = true;  // through the light-texture path, as the spot cone
  c.texturedLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  c.alphaTestedOccluders = true;  // rectified from the shared shadow map
  return c;
}

std::vector<std::string> MinmaxMethod::passes() const {
  return {kRectifyPass, kLowRankPass, kLightTexturePass, kMipmapPass, kIntegrationPass, kNearEpipolePass};
}

std::vector<ParamSpec> MinmaxMethod::params() const {
  return {
      ParamSpec::integer("slices", 0, 0, 8192, "epipolar slices; 0 = auto (every pixel within half a pixel of a slice)"),
      ParamSpec::integer("rank", 4, 1, kMaxRank, "singular vectors kept of the 64x64 integrand SVD"),
      ParamSpec::integer("res", 0, 0, 8192, "rectified row length (rounded up to a power of two); 0 = shadow-map size"),
      ParamSpec::integer("tex_res", 256, 16, 4096, "gamma samples of the per-slice light-texture prefix sums"),
      ParamSpec::real("epipole_radius", 8.0, 0.0, 100000.0, "pixels around the epipole that are ray marched"),
      ParamSpec::integer("epipole_steps", 256, 1, 16384, "ray-march steps near the epipole"),
      ParamSpec::flag("up_one_level", true, "traversal climbs at most one level per step (paper 3.5)").sameImage(),
      ParamSpec::flag("delay_gamma", true, "evaluate prefix sums once per lit run, not per lit node (paper 3.5)"),
      ParamSpec::flag("top_start", true, "traversal starts at the largest node at the ray's start (the root), not its leaf").sameImage(),
  };
}

std::vector<std::string> MinmaxMethod::qualityLadder() const {
  return {"slices=128:rank=2:res=256", "slices=512:rank=3:res=512", "slices=512:rank=4", "rank=6:epipole_steps=512"};
}

void MinmaxMethod::setup(const SetupContext& context, const ParamValues& params) {
  slicesParam_ = params.getInt("slices");
  rank_ = params.getInt("rank");
  rowParam_ = params.getInt("res");
  textureRes_ = params.getInt("tex_res");
  epipoleRadius_ = params.getFloat("epipole_radius");
  epipoleSteps_ = params.getInt("epipole_steps");
  upOneLevel_ = params.getBool("up_one_level");
  delayGamma_ = params.getBool("delay_gamma");
  topStart_ = params.getBool("top_start");
  maxTextureSize_ = context.limits.maxTextureSize;
  textured_ = context.effects.lightTexture || context.scene.light.type == LightType::Spot || context.effects.cosineLobe;
  rowLength_ = slices_ = allocatedRank_ = 0;

  std::string defines = sceneDefines(context.effects);
  // Integration is specialised per variant: a switch read from a uniform inside the traversal
  // loop would cost as if always taken.
  std::string variant = "#define MINMAX_RANK " + std::to_string(std::min(rank_, kMaxRank)) + "\n#define MINMAX_TEXTURED " +
                        (textured_ ? "1" : "0") + "\n#define MINMAX_DELAY_GAMMA " + (delayGamma_ ? "1" : "0") +
                        "\n#define MINMAX_UP_ONE_LEVEL " + (upOneLevel_ ? "1" : "0") +
                        "\n#define MINMAX_TOP_START " + (topStart_ ? "1" : "0") + "\n";
  rectifyProgram_ = gl::buildCompute("methods/minmax/shaders/rectify.comp", defines);
  mipmapProgram_ = gl::buildCompute("methods/minmax/shaders/mipmap.comp", defines);
  if (textured_) lightTextureProgram_ = gl::buildCompute("methods/minmax/shaders/light_texture.comp", defines + variant);
  integrateDefines_ = defines + variant;
  integrateProgram_ = gl::buildFullscreen("methods/minmax/shaders/integrate.frag", integrateDefines_);
  countingProgram_.reset();
  nearEpipoleProgram_ = gl::buildFullscreen("methods/minmax/shaders/near_epipole.frag", defines);
  epipolarUbo_ = gl::createBuffer(sizeof(EpipolarUniforms));
}

void MinmaxMethod::allocate(int slices, int rowLength, int rank, bool textured) {
  if (slices == slices_ && rowLength == rowLength_ && rank == allocatedRank_ && textured == allocatedTextured_) return;
  slices_ = slices;
  rowLength_ = rowLength;
  allocatedRank_ = rank;
  allocatedTextured_ = textured;
  tree_ = gl::createTexture2D(GL_RGBA32F, 3 * rowLength / 4, slices);  // shaders/tree.glsl
  gl::setFilter(tree_.id(), GL_NEAREST, GL_NEAREST);
  basisBeta_ = gl::createTexture2D(GL_RGBA32F, minmax::kGrid, rankGroups(rank));
  gl::setFilter(basisBeta_.id(), GL_LINEAR, GL_LINEAR);
  basisGamma_ = gl::createTexture2D(GL_R32F, minmax::kGrid, rank);
  gl::setFilter(basisGamma_.id(), GL_NEAREST, GL_NEAREST);
  gammaPrefix_ = gl::createTexture2D(GL_RGBA32F, kPrefixRes + 1, rankGroups(rank));
  gl::setFilter(gammaPrefix_.id(), GL_LINEAR, GL_LINEAR);
  texturedPrefix_ = gl::Texture();
  if (textured) {
    texturedPrefix_ = gl::createTexture2D(GL_RGBA32F, textureRes_ + 1, slices * rank);
    gl::setFilter(texturedPrefix_.id(), GL_LINEAR, GL_LINEAR);
  }
}

// The passes of the paper's table, in its order; each step below is one pass.
void MinmaxMethod::render(const Frame& frame, PassTimer& timer) {
  frame.bindShared();
  glBindBufferBase(GL_UNIFORM_BUFFER, kEpipolarUboBinding, epipolarUbo_.id());
  {
    auto scope = timer.scope(kRectifyPass);
    rectifyShadowMap(frame);
  }
  {
    auto scope = timer.scope(kLowRankPass);
    uploadLowRankApproximation(frame.scene.medium);
  }
  if (textured_) {
    auto scope = timer.scope(kLightTexturePass);
    precomputeLightTexture();
  }
  {
    auto scope = timer.scope(kMipmapPass);
    buildMinMaxMipmaps();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
  glViewport(0, 0, frame.width, frame.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  {
    auto scope = timer.scope(kIntegrationPass);
    integrate();
  }
  // Pixels near the epipole: a scissored, ray-marched pass (skipped when none is on screen).
  glm::ivec4 rect = nearEpipoleRect(epipolar_, nearEpipoleRadius(epipolar_, epipoleRadius_), frame.width, frame.height);
  if (rect.z > rect.x && rect.w > rect.y) {
    auto scope = timer.scope(kNearEpipolePass);
    marchNearEpipole(rect);
  }
}

// Shadow Map Rectification: the epipolar frame of this view (CPU), textures sized for it, its
// uniforms, then one texel per (light ray, slice).
void MinmaxMethod::rectifyShadowMap(const Frame& frame) {
  epipolar_ = minmax::computeEpipolarFrame(viewInput(frame, epipoleRadius_));
  int rank = std::min(rank_, kMaxRank);
  int maxSlices = std::min(8192, textured_ ? maxTextureSize_ / rank : maxTextureSize_);
  int slices = std::clamp(slicesParam_ > 0 ? slicesParam_ : epipolar_.autoSlices, 1, maxSlices);
  int rowLength = nextPowerOfTwo(std::max(rowParam_ > 0 ? rowParam_ : frame.shadowMap.size, 16));
  rowLength = std::min(rowLength, std::max(maxTextureSize_ / 2, 16));
  allocate(slices, rowLength, rank, textured_);  // slices_, rowLength_, allocatedRank_ from here on
  uploadEpipolarUniforms(frame.uniforms);

  glUseProgram(rectifyProgram_.id());
  glBindImageTexture(3, tree_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  dispatchBlocks(long(slices_) * (rowLength_ / kRectifyBlock));
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

// EpipolarBlock of this frame, after allocate().
void MinmaxMethod::uploadEpipolarUniforms(const FrameUniforms& fu) {
  const auto& e = epipolar_;
  EpipolarUniforms eu{};
  eu.invLightViewProj = glm::inverse(fu.lightViewProj);
  eu.axis = glm::vec4(glm::vec3(e.axis), float(e.eyeLightDistance));
  eu.basis0 = glm::vec4(glm::vec3(e.n0), float(e.alphaLo));
  eu.basis1 = glm::vec4(glm::vec3(e.n1), float(e.alphaRange));
  eu.gammaInfo = glm::vec4(float(e.gammaMap), float(e.gammaAll), float(rowLength_), 0.0f);
  eu.betaInfo = glm::vec4(float(e.betaLo), float(e.betaHi), float(e.epipolePixel.x), float(e.epipolePixel.y));
  eu.epipoleInfo = glm::vec4(nearEpipoleRadius(e, epipoleRadius_), float(epipoleSteps_), e.degenerate ? 1.0f : 0.0f, 0.0f);
  eu.counts = glm::ivec4(slices_, allocatedRank_, kPrefixRes, textureRes_);
  eu.flags = glm::ivec4(upOneLevel_ ? 1 : 0, delayGamma_ ? 1 : 0, textured_ ? 1 : 0, 0);
  glNamedBufferSubData(epipolarUbo_.id(), 0, sizeof(eu), &eu);
}

// Low-Rank Approximation (CPU): SVD of the smooth integrand on the 64x64 grid, prefix sums of
// Gamma_i; upload.
void MinmaxMethod::uploadLowRankApproximation(const Medium& medium) {
  minmax::MediumParams m;
  m.directional = epipolar_.directional;
  m.sigmaS = medium.sigmaS;
  m.sigmaT = medium.sigmaT();
  m.hg = medium.phase == Phase::HenyeyGreenstein;
  m.g = medium.g;
  minmax::LowRank lr = minmax::lowRankApproximation(epipolar_, m, allocatedRank_, kPrefixRes);
  energy_ = lr.energy;
  // Ranks the SVD did not give (lr.rank < the allocated rank) are zero, not stale.
  int groups = rankGroups(allocatedRank_);
  std::vector<float> basisGamma(size_t(allocatedRank_) * minmax::kGrid, 0.0f);
  std::copy(lr.basisGamma.begin(), lr.basisGamma.begin() + long(lr.rank) * minmax::kGrid, basisGamma.begin());
  glTextureSubImage2D(basisBeta_.id(), 0, 0, 0, minmax::kGrid, groups, GL_RGBA, GL_FLOAT,
                      packRanks(lr.basisBeta, lr.rank, minmax::kGrid, allocatedRank_).data());
  glTextureSubImage2D(basisGamma_.id(), 0, 0, 0, minmax::kGrid, allocatedRank_, GL_RED, GL_FLOAT, basisGamma.data());
  glTextureSubImage2D(gammaPrefix_.id(), 0, 0, 0, kPrefixRes + 1, groups, GL_RGBA, GL_FLOAT,
                      packRanks(lr.prefix, lr.rank, kPrefixRes + 1, allocatedRank_).data());
}

// Light Texture Precomputation (light texture or spot cone): per-slice prefix tables.
void MinmaxMethod::precomputeLightTexture() {
  glUseProgram(lightTextureProgram_.id());
  glBindTextureUnit(kUnitBasisGamma, basisGamma_.id());
  glBindImageTexture(0, texturedPrefix_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glDispatchCompute(GLuint((slices_ + 63) / 64), 1, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
}

// Mipmap Construction: the min-max levels of every rectified row, in place in tree_.
void MinmaxMethod::buildMinMaxMipmaps() {
  glUseProgram(mipmapProgram_.id());
  glBindImageTexture(3, tree_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glUniform1i(2, slices_);
  // Rectification stored the leaves and the three levels above them (a row of 16: all); each pass
  // here reads one level and writes up to three above it, the last pass four (kBlock in the shader).
  int first = rowLength_ > kRectifyBlock ? rowLength_ / (kRectifyBlock / 2) : 1;
  for (int inWidth = first; inWidth > 1; inWidth = inWidth > kMipmapBlock ? inWidth / (kMipmapBlock / 2) : 1) {
    glUniform1i(0, inWidth);
    dispatchBlocks(long(slices_) * (inWidth / std::min(inWidth, kMipmapBlock)));
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  }
}

// Integration: every pixel traverses its slice's min-max tree (into the bound inscatter target).
void MinmaxMethod::integrate() {
  glUseProgram(counting_ ? countingProgram_.id() : integrateProgram_.id());
  if (counting_) counters_.bind();
  glBindTextureUnit(kUnitTree, tree_.id());
  glBindTextureUnit(kUnitBasisBeta, basisBeta_.id());
  glBindTextureUnit(kUnitGammaPrefix, gammaPrefix_.id());
  glBindTextureUnit(kUnitTexturedPrefix, texturedPrefix_.id());
  gl::drawFullscreenTriangle();
}

// Near Epipole: ray marches the pixels of rect (x0, y0, x1, y1).
void MinmaxMethod::marchNearEpipole(const glm::ivec4& rect) {
  glEnable(GL_SCISSOR_TEST);
  glScissor(rect.x, rect.y, rect.z - rect.x, rect.w - rect.y);
  glUseProgram(nearEpipoleProgram_.id());
  gl::drawFullscreenTriangle();
  glDisable(GL_SCISSOR_TEST);
}

bool MinmaxMethod::beginWorkCount(int width, int height) {
  if (!countingProgram_)
    countingProgram_ = gl::buildFullscreen("methods/minmax/shaders/integrate.frag",
                                           integrateDefines_ + "#define VS_WORK_COUNTERS 1\n");
  counters_.begin(width, height);
  counting_ = true;
  return true;
}

std::map<std::string, double> MinmaxMethod::endWorkCount() {
  counting_ = false;
  return counters_.read("minmax");
}

std::map<std::string, double> MinmaxMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  (void)passes;
  return {{"slices", double(slices_)},
          {"row_length", double(rowLength_)},
          {"rank", double(allocatedRank_)},
          {"svd_energy_kept", energy_},
          {"auto_slices", double(epipolar_.autoSlices)}};
}

VS_REGISTER_METHOD(MinmaxMethod, 10);

}  // namespace vs
