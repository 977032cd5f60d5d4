// Frustum-voxel ("froxel") volumetric fog, the method engines ship (Wronski 2014, Hillaire 2015):
// in-scattering sampled on a camera-aligned grid, integrated front to back along its slices, and
// read per pixel at the depth of the pixel's surface.
#pragma once
#include <glm/glm.hpp>

#include "harness/pipeline/method.hpp"

namespace vs {

class FroxelMethod : public Method {
 public:
  std::string name() const override { return "froxel"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> qualityLadder() const override;
  std::vector<QualitySeries> qualitySeries(const Effects& effects) const override;
  std::vector<std::string> approximations() const override;
  double declaredRelMseBound() const override;
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::vector<DebugView> debugViews() const override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;

 private:
  gl::Program scatterProgram_, integrateProgram_, applyProgram_;
  // Per froxel: in-scattered radiance per unit length (rgb) and, with volume data, the volumes'
  // the extinction; after the integration, L_s and the volumes' optical depth from the eye to the
  // far boundary of each slice. Scattering and extinction alternate between two textures: the
  // previous frame's is the history of temporal reprojection.
  gl::Texture scattering_[2], extinction_[2], integrated_, opticalDepth_;
  int current_ = 0;
  float temporal_ = 0.0f;
  // The history: the frame it was rendered in, its camera, and how many frames it accumulates.
  uint32_t historyFrame_ = 0;
  int historyFrames_ = 0;
  glm::mat4 previousViewProj_{1.0f};
  glm::vec4 previousEye_{0.0f};
  gl::Buffer ubo_;
  int gridW_ = 0, gridH_ = 0, slices_ = 64, tile_ = 8, samples_ = 1, lightSteps_ = 64;
  bool exponential_ = true, jitter_ = false, volumes_ = false;
};

}  // namespace vs
