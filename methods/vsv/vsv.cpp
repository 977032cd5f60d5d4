#include "vsv.hpp"
#include "registry.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <bitset>
#include <cmath>
#include <stdexcept>

namespace vs {

// ---- the method

static constexpr const char* kVoxelizeSm = "Voxelize: From SM";
static constexpr const char* kVoxelizeGeometry = "Voxelize: Geometry";
static constexpr const char* kScan = "Scan VSV";
static constexpr const char* kInscatter = "Compute L_s";
static constexpr const char* kRanges = "Epipolar Ranges";
static constexpr const char* kSurface = "Surface Shadows";
// std140 mirror of VsvRangesBlock in shaders/epipolar.glsl (filled from the Ranges pass's buffer).
struct RangesUniforms {
  uint32_t alphaMaxBits, phiMaxBits;
};
VS_STD140_MIRROR(RangesUniforms, "VsvRangesBlock", VS_STD140_FIELD(RangesUniforms, alphaMaxBits),
                 VS_STD140_FIELD(RangesUniforms, phiMaxBits));
VS_STD140_MIRROR(epipolar::GridUniforms, "VsvBlock", VS_STD140_FIELD_AS(epipolar::GridUniforms, eye, "eyeAndDistance"),
                 VS_STD140_FIELD_AS(epipolar::GridUniforms, light, "gridLight"),
                 VS_STD140_FIELD(epipolar::GridUniforms, axis), VS_STD140_FIELD(epipolar::GridUniforms, e1),
                 VS_STD140_FIELD(epipolar::GridUniforms, e2), VS_STD140_FIELD(epipolar::GridUniforms, grid),
                 VS_STD140_FIELD_AS(epipolar::GridUniforms, ranges, "fixedRanges"));
static constexpr GLuint kGridUboBinding = 3;    // VsvBlock in shaders/epipolar.glsl
static constexpr GLuint kRangesUboBinding = 5;  // VsvRangesBlock in shaders/epipolar.glsl
static constexpr int kRangesTile = 4;  // pixels per side of one Epipolar Ranges invocation

std::string VsvMethod::description() const {
  return "voxelized shadow volumes (Wyman 2011): epipolar bit grid from the shadow map or the geometry, "
         "prefix-OR scan, per-pixel Riemann sum over phi";
}

Capabilities VsvMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = true;
  c.cosineLobe = true;  // L_in comes from lightIncident() at each sample
  c.texturedLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  c.surfaceShadows = true;  // with surface=1
  c.alphaTestedOccluders = true;  // vox=sm: voxelized from the shared shadow map
  return c;
}

std::string VsvMethod::unsupportedReason(const Scene& scene, const ParamValues& params) const {
  std::string base = Method::unsupportedReason(scene, params);
  if (!base.empty()) return base;
  if (params.getString("vox") == "geom" && deriveEffects(scene).semiTransparent)
    return "vox=geom extrudes whole triangles, so semi-transparent occluders cannot be alpha-tested: use vox=sm";
  return "";
}

std::vector<std::string> VsvMethod::passes() const {
  return {kRanges, kVoxelizeSm, kVoxelizeGeometry, kScan, kInscatter, kSurface};
}

// Surface Shadows shades L_surf: timed, not scattering time.
std::vector<std::string> VsvMethod::surfacePasses() const { return {kSurface}; }

std::vector<ParamSpec> VsvMethod::params() const {
  return {ParamSpec::integer("alpha", 256, 8, 8192, "N_alpha: columns (eye angle from the light axis)"),
          ParamSpec::integer("theta", 512, 8, 8192, "N_theta: rows (epipolar planes)"),
          ParamSpec::integer("phi", 256, 128, 1024, "N_phi: bits per column (light angle), 128 per render target").pow2(),
          ParamSpec::choice("vox", "sm", {"sm", "geom"}, "voxelizer: resample the shadow map or rasterize triangles"),
          ParamSpec::flag("fused", true,
                          "vox=sm: one compute pass writes the scanned words (no points, logic op or Scan VSV); 0 = the paper's points, then Scan VSV")
              .sameImage(),
          ParamSpec::flag("ranges", true, "dynamic angular ranges: alpha_max from the pixels, phi_max from visible geometry"),
          ParamSpec::integer("coarse", 4, 1, 64, "phi bins per light evaluation when the light is textured"),
          ParamSpec::choice("group", "auto", {"auto", "8", "16", "32", "64", "128"},
                            "untextured lights: phi bins per group, over which the integrand is taken as linear "
                            "through two light evaluations; auto: 16 for a spot light's cone edges or a peaked "
                            "phase (|g| >= 0.5), else 64"),
          ParamSpec::flag("surface", false, "surface shadows from the VSV (Fig. 7) instead of the shared shadow map"),
          ParamSpec::real("sbias", 2.0, 0.0, 16.0, "surface shadows: lookup offset towards the light, in voxels"),
          ParamSpec::real("nbias", 0.5, 0.0, 16.0, "surface shadows: lookup offset along the normal, in voxels")};
}

std::vector<std::string> VsvMethod::qualityLadder() const {
  return {"alpha=64:theta=128:phi=128", "alpha=128:theta=256:phi=128", "alpha=256:theta=512:phi=256",
          "alpha=512:theta=1024:phi=512", "alpha=512:theta=2048:phi=512"};
}

// Untextured lights: the bins over which Compute L_s takes the integrand as linear. It is smooth in
// φ for a point light (the Jacobian cancels 1/r²): 64 bins cost a third of the light evaluations
// of 16 at the same error on room (README); a spot light's cone edges and a peaked phase are kinks
// and peaks that a long line misses.
static int binsPerGroup(const std::string& group, const Scene& scene) {
  if (group != "auto") return std::stoi(group);
  const bool peakedPhase = scene.medium.phase == Phase::HenyeyGreenstein && std::fabs(scene.medium.g) >= 0.5f;
  return scene.light.type == LightType::Spot || peakedPhase ? 16 : 64;
}

void VsvMethod::setup(const SetupContext& context, const ParamValues& params) {
  size_.nAlpha = params.getInt("alpha");
  size_.nTheta = params.getInt("theta");
  size_.nPhi = params.getInt("phi");
  fromGeometry_ = params.getString("vox") == "geom";
  // The fused voxelizer keeps a row's N_alpha x N_phi bits in shared memory; larger grids take the
  // paper's path (points, then Scan VSV), as the row's passes show.
  GLint sharedBytes = 0;
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &sharedBytes);
  rowWords_ = size_.nAlpha * (size_.nPhi / 32);
  fused_ = !fromGeometry_ && params.getBool("fused") && double(rowWords_) * 4.0 <= double(sharedBytes);
  // Rows per fused workgroup: as many as fit, up to 8 (their α walks run side by side).
  rowsPerGroup_ = 8;
  while (rowsPerGroup_ > 1 && double(rowsPerGroup_) * double(rowWords_) * 4.0 > double(sharedBytes)) rowsPerGroup_ /= 2;
  dynamicRanges_ = params.getBool("ranges");
  coarse_ = params.getInt("coarse");
  surfaceShadows_ = params.getBool("surface");
  surfaceBias_ = glm::vec2(params.getFloat("sbias"), params.getFloat("nbias"));
  width_ = context.width;
  height_ = context.height;
  if (size_.nAlpha > context.limits.maxViewportW || size_.nTheta > context.limits.maxViewportH)
    throw std::runtime_error("vsv: grid larger than the GL viewport limit");
  glm::vec3 extent = context.geometry.boundsHi - context.geometry.boundsLo;
  sceneRadius_ = std::max(0.5f * glm::length(extent), 1e-3f);
  boundsLo_ = context.geometry.boundsLo;
  boundsHi_ = context.geometry.boundsHi;

  voxels_ = std::make_unique<epipolar::VoxelBuffer>(size_);
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  emptyVao_ = gl::VertexArray(vao);
  scan_ = std::make_unique<epipolar::Scan>();
  gridUbo_ = gl::createBuffer(sizeof(epipolar::GridUniforms));
  rangesSsbo_ = gl::createBuffer(2 * sizeof(uint32_t));
  const uint32_t noRanges[4] = {0, 0, 0, 0};  // read, but unused, with ranges=0
  rangesUbo_ = gl::createBuffer(sizeof(noRanges), noRanges);
  const std::string defines = sceneDefines(context.effects) + "#define VSV_LAYERS " + std::to_string(size_.layers()) + "\n";
  rangesProgram_ = gl::buildCompute("methods/vsv/shaders/ranges.comp",
                                    defines + "#define RANGES_TILE " + std::to_string(kRangesTile) + "\n");
  inscatterDefines_ = defines + "#define VSV_GROUP " + std::to_string(binsPerGroup(params.getString("group"), context.scene)) + "\n";
  inscatterProgram_ = gl::buildFullscreen("methods/vsv/shaders/inscatter.frag", inscatterDefines_);
  countingProgram_.reset();
  if (surfaceShadows_) surfaceProgram_ = gl::buildFullscreen("methods/vsv/shaders/surface.frag", defines);
  if (fromGeometry_) {
    geometryProgram_ = gl::buildProgram({{GL_VERTEX_SHADER, "methods/vsv/shaders/voxelize_geom.vert"},
                                         {GL_GEOMETRY_SHADER, "methods/vsv/shaders/voxelize_geom.geom"},
                                         {GL_FRAGMENT_SHADER, "methods/vsv/shaders/voxelize_geom.frag"}},
                                        defines);
  } else if (fused_) {
    fusedProgram_ = gl::buildCompute("methods/vsv/shaders/voxelize_sm.comp",
                                     defines + "#define VSV_ROW_WORDS " + std::to_string(rowWords_) + "\n#define VSV_ROWS " +
                                         std::to_string(rowsPerGroup_) + "\n");
  } else {
    fromSmProgram_ = gl::buildProgram({{GL_VERTEX_SHADER, "methods/vsv/shaders/voxelize_sm.vert"},
                                       {GL_FRAGMENT_SHADER, "methods/vsv/shaders/voxelize_sm.frag"}},
                                      defines);
  }
}

void VsvMethod::updateGrid(const Frame& frame) {
  const Camera& cam = frame.scene.camera;
  glm::dvec3 eye(cam.position), light(frame.scene.light.position);
  glm::dvec3 forward(frame.uniforms.cameraForward);
  // Light at or near the eye (§4.2): the grid's light stays at least the camera's near distance
  // away, where L_s (an integral of 1/s^2 from the eye) would otherwise have no bound.
  double minDistance = std::max(1e-4 * double(sceneRadius_), double(cam.nearZ));
  epipolar::EpipolarBasis basis;
  if (frame.scene.light.type == LightType::Directional) {
    basis = epipolar::makeDirectionalBasis(eye, glm::dvec3(frame.uniforms.lightDir), 1.0);
    // Occluders lie inside the scene bounds: their distance from the axis bounds the φ range.
    double reach = epipolar::sceneAxisDistance(eye, basis.axis, glm::dvec3(boundsLo_), glm::dvec3(boundsHi_));
    basis.phiRange = std::isfinite(reach) ? std::max(reach, 1e-4 * double(sceneRadius_)) : 2.0 * double(sceneRadius_);
  } else {
    basis = epipolar::makeBasis(eye, light, forward, minDistance);
  }
  epipolar::GridUniforms g = epipolar::makeGridUniforms(basis, size_, dynamicRanges_);
  glNamedBufferSubData(gridUbo_.id(), 0, sizeof(g), &g);
  glBindBufferBase(GL_UNIFORM_BUFFER, kGridUboBinding, gridUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, rangesSsbo_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, kRangesUboBinding, rangesUbo_.id());
}

void VsvMethod::computeRanges(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kRanges);
  const uint32_t zero = 0;
  glClearNamedBufferData(rangesSsbo_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glUseProgram(rangesProgram_.id());
  const int groupPixels = 8 * kRangesTile;  // 8x8 invocations, each a tile of pixels
  glDispatchCompute(GLuint((frame.width + groupPixels - 1) / groupPixels),
                    GLuint((frame.height + groupPixels - 1) / groupPixels), 1);
  // The passes after this one read the ranges through a uniform block: a copy on the GPU.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glCopyNamedBufferSubData(rangesSsbo_.id(), rangesUbo_.id(), 0, 0, 2 * sizeof(uint32_t));
}

// Both voxelizers OR fragments into every layer of the voxel buffer.
static void beginOrTargets(const epipolar::VoxelBuffer& voxels) {
  voxels.clear();
  glBindFramebuffer(GL_FRAMEBUFFER, voxels.framebuffer());
  glViewport(0, 0, voxels.size().nAlpha, voxels.size().nTheta);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glEnable(GL_COLOR_LOGIC_OP);
  glLogicOp(GL_OR);
}

static void endOrTargets() {
  glDisable(GL_COLOR_LOGIC_OP);
  glLogicOp(GL_COPY);
}

void VsvMethod::voxelizeFromShadowMap(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kVoxelizeSm);
  (void)frame;
  beginOrTargets(*voxels_);
  glUseProgram(fromSmProgram_.id());
  glDisable(GL_PROGRAM_POINT_SIZE);
  glPointSize(1.0f);
  glBindVertexArray(emptyVao_.id());  // attribute-less: positions come from gl_VertexID
  glDrawArrays(GL_POINTS, 0, GLsizei(size_.nTheta) * size_.nPhi);
  endOrTargets();
}

// Fused: the scanned words straight from the shadow map, one workgroup per rowsPerGroup_ θ rows.
void VsvMethod::voxelizeFused(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kVoxelizeSm);
  (void)frame;
  glUseProgram(fusedProgram_.id());
  glBindImageTexture(0, voxels_->texture(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
  glDispatchCompute(GLuint((size_.nTheta + rowsPerGroup_ - 1) / rowsPerGroup_), 1, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

void VsvMethod::voxelizeGeometry(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kVoxelizeGeometry);
  beginOrTargets(*voxels_);
  glUseProgram(geometryProgram_.id());
  frame.geometry.draw();
  endOrTargets();
}

void VsvMethod::integrate(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kInscatter);
  glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
  glViewport(0, 0, frame.width, frame.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(counting_ ? countingProgram_.id() : inscatterProgram_.id());
  if (counting_) counters_.bind();
  glBindTextureUnit(bind::kFirstMethodUnit, voxels_->texture());
  glUniform1i(0, frame.effects.lightTexture ? coarse_ : 1);
  gl::drawFullscreenTriangle();
}

// Fig. 7: L_surf re-shaded with the scanned VSV's visibility at each visible surface point.
void VsvMethod::shadeSurfaces(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kSurface);
  glBindFramebuffer(GL_FRAMEBUFFER, frame.directFbo);
  glViewport(0, 0, frame.width, frame.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(surfaceProgram_.id());
  glBindTextureUnit(bind::kFirstMethodUnit, voxels_->texture());
  glUniform2f(0, surfaceBias_.x, surfaceBias_.y);
  gl::drawFullscreenTriangle();
}

void VsvMethod::render(const Frame& frame, PassTimer& timer) {
  frame.bindShared();
  updateGrid(frame);
  if (dynamicRanges_) computeRanges(frame, timer);
  if (fused_) {
    voxelizeFused(frame, timer);  // already scanned
  } else {
    if (fromGeometry_)
      voxelizeGeometry(frame, timer);
    else
      voxelizeFromShadowMap(frame, timer);
    auto scope = timer.scope(kScan);
    scan_->run(*voxels_);
  }
  integrate(frame, timer);
  if (surfaceShadows_) shadeSurfaces(frame, timer);
}

bool VsvMethod::beginWorkCount(int width, int height) {
  if (!countingProgram_)
    countingProgram_ =
        gl::buildFullscreen("methods/vsv/shaders/inscatter.frag", inscatterDefines_ + "#define VS_WORK_COUNTERS 1\n");
  counters_.begin(width, height);
  counting_ = true;
  return true;
}

std::map<std::string, double> VsvMethod::endWorkCount() {
  counting_ = false;
  std::map<std::string, double> out = counters_.read("vsv");
  if (voxels_) {
    double set = 0.0;
    for (uint32_t word : voxels_->read()) set += double(std::bitset<32>(word).count());
    double total = double(size_.nAlpha) * size_.nTheta * size_.nPhi;
    out["vsv_shadowed_voxels"] = set;
    out["vsv_shadowed_voxel_fraction"] = total > 0.0 ? set / total : 0.0;
  }
  return out;
}

std::map<std::string, double> VsvMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  std::map<std::string, double> out;
  out["voxels"] = double(size_.nAlpha) * size_.nTheta * size_.nPhi;
  auto it = passes.find(kInscatter);
  if (it != passes.end() && it->second.medianMs > 0.0)
    out["pixels_per_s"] = double(width_) * height_ / (it->second.medianMs * 1e-3);
  return out;
}

VS_REGISTER_METHOD(VsvMethod, 20);

}  // namespace vs
