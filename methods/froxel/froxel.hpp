// Frustum-voxel ("froxel") volumetric fog, the method engines ship (Wronski 2014, Hillaire 2015):
// in-scattering sampled on a camera-aligned grid, integrated front to back along its slices, and
// read per pixel at the depth of the pixel's surface.
#pragma once
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
  std::vector<std::string> approximations() const override;
  double declaredRelMseBound() const override;
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::vector<DebugView> debugViews() const override;

 private:
  gl::Program scatterProgram_, integrateProgram_, applyProgram_;
  // Per froxel: in-scattered radiance per unit length (rgb) and, with volume data, the volumes'
  // extinction (rgb); after the integration, L_s and the volumes' optical depth from the eye to
  // the far boundary of each slice.
  gl::Texture scattering_, extinction_, integrated_, opticalDepth_;
  gl::Buffer ubo_;
  int gridW_ = 0, gridH_ = 0, slices_ = 64, tile_ = 8, samples_ = 1, lightSteps_ = 64;
  bool exponential_ = true, jitter_ = false, volumes_ = false;
};

}  // namespace vs
