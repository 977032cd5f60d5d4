// Brute-force ray marching of the single-scattering integral; also the harness's reference.
#pragma once
#include "harness/pipeline/method.hpp"

namespace vs {

class RaymarchMethod : public Method {
 public:
  std::string name() const override { return "raymarch"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> qualityLadder() const override;
  std::vector<QualitySeries> qualitySeries(const Effects& effects) const override;
  std::string referenceParams(const Effects& effects, const ReferenceBudget& budget) const override;
  std::string baselineParams(const BaselinePoint& point) const override;
  // Area lights: the light's sample points and their cube maps' range are placed in setup.
  bool setupDependsOnLight(const Effects& effects) const override { return effects.areaLight; }
  std::string unsupportedReason(const Scene& scene, const ParamValues& params) const override;
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;
  // The viewer's buffers (besides the shared shadow map): area-light point shadows, volume optical depth.
  std::vector<DebugView> debugViews() const override {
    std::vector<DebugView> views;
    if (vplShadows_) views.push_back({"area-light point shadow cubes", vplShadows_.id(), DebugView::Kind::Value, 6 * lightSamples_});
    if (volumes_) views.push_back({"volume optical depth", opticalDepth_[0].id()});
    return views;
  }

 private:
  // The passes one frame needs so that no invocation exceeds the loop budget.
  int stepsPerPass(const Frame& frame) const;
  void renderAreaLightShadows(const Frame& frame, PassTimer& timer);
  gl::Program program_;
  // Area lights: stratified points on the light, each with a cube shadow map in one array.
  int lightSamples_ = 0, lightShadowSize_ = 256;
  gl::Program shadowProgram_;
  gl::Texture vplShadows_;
  gl::Framebuffer vplFbo_;
  gl::Sampler vplSampler_;
  gl::Buffer vplUbo_;
  std::vector<glm::vec3> vplPositions_;
  float vplNear_ = 0.01f, vplFar_ = 100.0f;
  gl::Texture opticalDepth_[2];       // volume data: the camera ray's optical depth between passes
  gl::Framebuffer passFbo_[2];
  GLuint fboInscatter_ = 0;           // the in-scatter texture passFbo_ was made for
  bool volumes_ = false;
  int lightStepsMax_ = 512;
  int passes_ = 1;
  int steps_ = 0;
  bool jitter_ = true;
  bool equiangular_ = false;
  float volumeStepsPerVoxel_ = 1.0f;
  int width_ = 0, height_ = 0;
};

}  // namespace vs
