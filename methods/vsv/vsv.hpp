// Voxelized shadow volumes (Wyman, HPG 2011): visibility in an epipolar-space bit grid, built from
// the shadow map or from the geometry, OR-scanned along α, then integrated per pixel over φ. The
// grid itself (frame, voxel buffer, Scan VSV) is shared with ivsv: methods/epipolar/.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "epipolar/epipolar_grid.hpp"
#include "harness/pipeline/method.hpp"
#include "harness/gl/work_counters.hpp"

namespace vs {

class VsvMethod : public Method {
 public:
  std::string name() const override { return "vsv"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> surfacePasses() const override;
  std::vector<std::string> approximations() const override {
    return {"visibility quantised to the epipolar voxel grid"};
  }
  std::vector<std::string> qualityLadder() const override;
  std::string unsupportedReason(const Scene& scene, const ParamValues& params) const override;
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;
  // Compute L_s's φ bins, light evaluations and voxel fetches per pixel (mean, max), and the
  // voxels the voxelizer and scan set (in shadow).
  bool beginWorkCount(int width, int height) override;
  std::map<std::string, double> endWorkCount() override;
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

  epipolar::GridSize size_;
  int rowWords_ = 0;  // fused voxelizer: shared words per theta row
  int rowsPerGroup_ = 1;  // fused voxelizer: theta rows per workgroup
  bool fromGeometry_ = false, fused_ = true, dynamicRanges_ = true, surfaceShadows_ = false;
  int coarse_ = 4;
  glm::vec2 surfaceBias_{2.0f, 0.5f};  // towards the light, along the normal (voxels)
  glm::vec3 boundsLo_{0}, boundsHi_{0};
  float sceneRadius_ = 1.0f;
  int width_ = 0, height_ = 0;
  std::unique_ptr<epipolar::VoxelBuffer> voxels_;
  std::unique_ptr<epipolar::Scan> scan_;
  gl::Buffer gridUbo_, rangesSsbo_, rangesUbo_;  // rangesUbo_: the passes' copy of the ranges
  gl::VertexArray emptyVao_;
  gl::Program rangesProgram_, fromSmProgram_, fusedProgram_, geometryProgram_, inscatterProgram_, surfaceProgram_;
  gl::Program countingProgram_;  // Compute L_s with work counters, built on the first count
  std::string inscatterDefines_;
  WorkCounters counters_{{"visited", "bins", "light_evals", "fetches"}};
  bool counting_ = false;
};

}  // namespace vs
