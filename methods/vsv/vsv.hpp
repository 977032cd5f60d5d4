// Voxelized shadow volumes (Wyman, HPG 2011): visibility in an epipolar-space bit grid, built from
// the shadow map or from the geometry, OR-scanned along α, then integrated per pixel over φ.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "harness/method.hpp"

namespace vs {
namespace vsv {

// Epipolar frame (§2.1): axis from the eye towards the light, θ the angle of the epipolar half-plane
// around it, α the angle at the eye from the axis, φ the angle at the light from the light-to-eye
// direction. `distance` is |light - eye|, clamped away from zero (§4.2): the grid's light sits on
// the axis at that distance. A directional light has its axis towards the light at infinity and
// φ becomes the distance from the axis (light rays are parallel to it), up to `phiRange`.
struct EpipolarBasis {
  glm::dvec3 eye{0}, light{0}, axis{0, 0, -1}, e1{1, 0, 0}, e2{0, 1, 0};
  double distance = 1.0;
  bool directional = false;
  double phiRange = 3.14159265358979323846;  // fixed φ_max: π, or the largest distance from the axis
};
// `fallbackAxis` is used when the light is (almost) at the eye.
EpipolarBasis makeBasis(glm::dvec3 eye, glm::dvec3 light, glm::dvec3 fallbackAxis, double minDistance);
// Directional light travelling along `travelDir`; `phiRange` bounds every occluder's distance
// from the axis (see sceneAxisDistance).
EpipolarBasis makeDirectionalBasis(glm::dvec3 eye, glm::dvec3 travelDir, double phiRange);
// Largest distance from the line through `eye` along unit `axis` over the box [lo, hi].
double sceneAxisDistance(glm::dvec3 eye, glm::dvec3 axis, glm::dvec3 lo, glm::dvec3 hi);

struct EpiCoords {
  double theta = 0, alpha = 0, phi = 0;  // θ in [0, 2π), α and φ in [0, π]
};
EpiCoords toEpipolar(const EpipolarBasis& basis, glm::dvec3 point);

// Grid resolution: N_α columns, N_θ rows, N_φ bits (128 per RGBA32UI texel, one layer per 128).
struct GridSize {
  int nAlpha = 256, nTheta = 512, nPhi = 256;
  int layers() const { return (nPhi + 127) / 128; }
};
int thetaRow(double theta, int nTheta);
int alphaColumn(double alpha, double alphaMax, int nAlpha);  // -1 at or beyond alphaMax
int phiBin(double phi, double phiMax, int nPhi);             // -1 at or beyond phiMax

// std140 mirror of VsvBlock in shaders/epipolar.glsl.
struct GridUniforms {
  glm::vec4 eye;        // xyz; w = distance to the grid light
  glm::vec4 light;      // xyz grid light
  glm::vec4 axis, e1, e2;
  glm::ivec4 grid;      // N_α, N_θ, N_φ, layers
  glm::vec4 ranges;     // fixed α_max, fixed φ_max, dynamic (1/0), directional (1/0)
};
GridUniforms makeGridUniforms(const EpipolarBasis& basis, const GridSize& size, bool dynamicRanges);

// CPU reference of the scan: words hold layers x N_θ x N_α texels of 4 uints (layer-major, rows,
// then columns), the layout glGetTextureImage returns for the voxel buffer.
void prefixOrRowsCpu(std::vector<uint32_t>& words, const GridSize& size);

// The voxel buffer (§2.2): a 2D-array RGBA32UI texture, N_α x N_θ, one layer per 128 φ bits, and
// a framebuffer with every layer attached as its own colour target (OR-blended MRT).
class VoxelBuffer {
 public:
  explicit VoxelBuffer(const GridSize& size);
  const GridSize& size() const { return size_; }
  GLuint texture() const { return texture_.id(); }
  GLuint framebuffer() const { return fbo_.id(); }
  void clear() const;
  std::vector<uint32_t> read() const;
  void write(const std::vector<uint32_t>& words) const;

 private:
  GridSize size_;
  gl::Texture texture_;
  gl::Framebuffer fbo_;
};

// "Scan VSV": in-place prefix OR along α of every row and layer (compute; any N_α).
class Scan {
 public:
  Scan();
  void run(const VoxelBuffer& buffer) const;

 private:
  gl::Program program_;
};

}  // namespace vsv

class VsvMethod : public Method {
 public:
  std::string name() const override { return "vsv"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> approximations() const override {
    return {"visibility quantised to the epipolar voxel grid"};
  }
  std::vector<std::string> qualityLadder() const override;
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;
  // The viewer's buffers: the scanned voxel grid, one phi slice (bit) at a time (alpha across, theta down).
  std::vector<DebugView> debugViews() const override {
    if (!voxels_) return {};
    return {{"voxel grid (phi slices)", voxels_->texture(), DebugView::Kind::Bits, voxels_->size().nPhi}};
  }

 private:
  void updateGrid(const Frame& frame);
  void computeRanges(const Frame& frame, PassTimer& timer);
  void voxelizeFromShadowMap(const Frame& frame, PassTimer& timer);
  void voxelizeGeometry(const Frame& frame, PassTimer& timer);
  void voxelizeFused(const Frame& frame, PassTimer& timer);
  void integrate(const Frame& frame, PassTimer& timer);
  void shadeSurfaces(const Frame& frame, PassTimer& timer);

  vsv::GridSize size_;
  int rowWords_ = 0;  // fused voxelizer: shared words per theta row
  bool fromGeometry_ = false, fused_ = true, dynamicRanges_ = true, surfaceShadows_ = false;
  int coarse_ = 4;
  glm::vec2 surfaceBias_{2.0f, 0.5f};  // towards the light, along the normal (voxels)
  glm::vec3 boundsLo_{0}, boundsHi_{0};
  float sceneRadius_ = 1.0f;
  int width_ = 0, height_ = 0;
  std::unique_ptr<vsv::VoxelBuffer> voxels_;
  std::unique_ptr<vsv::Scan> scan_;
  gl::Buffer gridUbo_, rangesSsbo_;
  gl::VertexArray emptyVao_;
  gl::Program rangesProgram_, fromSmProgram_, fusedProgram_, geometryProgram_, inscatterProgram_, surfaceProgram_;
};

}  // namespace vs
