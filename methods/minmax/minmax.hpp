// Real-time volumetric shadows using 1D min-max mipmaps (Chen, Baran, Durand, Jarosz, I3D 2011).
#pragma once
#include "epipolar.hpp"
#include "harness/pipeline/method.hpp"
#include "harness/gl/work_counters.hpp"

namespace vs {

class MinmaxMethod : public Method {
 public:
  std::string name() const override { return "minmax"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> approximations() const override {
    return {"visibility from the nearest texel of the rectified shadow map (no PCF)",
            "each pixel integrates its nearest epipolar slice"};
  }
  std::vector<std::string> qualityLadder() const override;
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;
  // Integration's traversal iterations and lit runs per pixel (mean, max).
  bool beginWorkCount(int width, int height) override;
  std::map<std::string, double> endWorkCount() override;
  // The viewer's buffer: one epipolar slice per row, its 1D min-max levels (left two thirds, two
  // nodes per texel) and its rectified shadow map (the leaves, right third, four per texel).
  std::vector<DebugView> debugViews() const override {
    if (!tree_) return {};
    return {{"rectified shadow map (right third, 4 texels per pixel) and its min-max levels (left, 2 nodes per pixel)",
             tree_.id(), DebugView::Kind::Value, 1, 1, 3}};
  }

 private:
  void allocate(int slices, int rowLength, int rank, bool textured);
  // The passes of render(), one step each, in the paper's order.
  void rectifyShadowMap(const Frame& frame);  // Shadow Map Rectification
  void uploadEpipolarUniforms(const FrameUniforms& fu);
  void uploadLowRankApproximation(const Medium& medium);  // Low-Rank Approximation
  void precomputeLightTexture();  // Light Texture Precomputation
  void buildMinMaxMipmaps();      // Mipmap Construction
  void integrate();               // Integration
  void marchNearEpipole(const glm::ivec4& rect);  // Near Epipole

  // Knobs.
  int slicesParam_ = 0, rank_ = 4, rowParam_ = 0, textureRes_ = 256, epipoleSteps_ = 256;
  double epipoleRadius_ = 8.0;
  bool upOneLevel_ = true, delayGamma_ = true, topStart_ = true;
  // Scene facts fixed at setup.
  bool textured_ = false;  // light texture or spot cone: per-slice prefix tables
  int maxTextureSize_ = 0;
  // Per frame.
  int slices_ = 0, rowLength_ = 0, allocatedRank_ = 0;
  bool allocatedTextured_ = false;
  double energy_ = 1.0;
  minmax::EpipolarFrame epipolar_;

  gl::Program rectifyProgram_, mipmapProgram_, lightTextureProgram_, integrateProgram_, nearEpipoleProgram_;
  gl::Program countingProgram_;  // Integration with work counters, built on the first count
  std::string integrateDefines_;
  WorkCounters counters_{{"visited", "iterations", "lit_runs"}};
  bool counting_ = false;
  gl::Buffer epipolarUbo_;
  gl::Texture tree_;  // the rectified rows are its leaves
  gl::Texture basisBeta_, basisGamma_, gammaPrefix_, texturedPrefix_;
};

}  // namespace vs
