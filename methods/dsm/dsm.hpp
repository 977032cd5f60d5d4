// Deep shadow maps from volume data on the GPU (Shook): per light texel, the depths at which the
// volumes' accumulated opacity crosses K thresholds, and the final opacity; the camera ray then
// marches the volumes and reads light transmittance from the map.
#pragma once
#include <array>

#include "harness/pipeline/method.hpp"

namespace vs {

namespace dsm {

// The light views the map is rendered in, fitted to the volumes' boxes: one orthographic
// (directional) or perspective (point/spot outside the boxes) view, or six cube faces around a
// point/spot light inside or close to them.
struct LightViews {
  int faces = 1;
  std::array<glm::mat4, 6> viewProj{};
};
LightViews fitLightViews(const Light& light, const glm::vec3& boxLo, const glm::vec3& boxHi, int resolution);

// Opacity thresholds of K knots evenly spaced from `first` to `last` (K = 3: 0.1, 0.5, 0.9).
std::vector<float> knotThresholds(int knots, float first, float last);
// RGBA32F layers per face holding K knots and the final opacity.
inline int layersFor(int knots) { return (knots + 1 + 3) / 4; }
// Each colour channel's sigma_t over the mean sigma_t of the volumes (weighted by their largest
// optical thickness): a map of the mean extinction gives channel c's transmittance as
// T^ratio_c, exact when every volume has the same colour.
glm::vec3 channelRatios(const Scene& scene);
// Whether one visibility function serves every colour channel exactly: the volumes' extinction
// colours (sigma_t over its mean) are all the same.
bool oneColour(const Scene& scene);
// Visibility functions per light texel for `channels` = "auto" (3 unless oneColour), "1" or "3".
int channelsFor(const Scene& scene, const std::string& channels);

}  // namespace dsm

class DsmMethod : public Method {
 public:
  std::string name() const override { return "dsm"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> surfacePasses() const override;
  std::vector<std::string> qualityLadder() const override;
  std::vector<std::string> approximations() const override {
    std::vector<std::string> out = {"volume transmittance interpolated between opacity knots (linear in opacity or in optical depth)"};
    if (tintedByRatio_) out.push_back("one visibility function for every colour channel (volumes of different colours)");
    return out;
  }
  std::string unsupportedReason(const Scene& scene, const ParamValues& params) const override;
  bool needsSharedShadowMap() const override { return needsSharedShadowMap_; }
  bool lightFixedAtSetup() const override { return true; }  // light views are fitted in setup
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;
  // The viewer's buffers: the opacity knots, four per layer (rgb shows the first three), per light view.
  std::vector<DebugView> debugViews() const override {
    if (!map_) return {};
    return {{"deep shadow map knots", map_.id(), DebugView::Kind::Value, views_.faces * channels_ * layers_, 1, 3}};
  }

 private:
  // The steps of setup(), in order.
  void readParams(const SetupContext& context, const ParamValues& params);
  void fitViewsAndUploadUniforms(const Scene& scene, const ParamValues& params);
  void createMapAndFramebuffers(bool hardwareFilter);
  void buildPrograms(const Scene& scene, const Effects& effects, const ParamValues& params);

  int resolution_ = 512, genSteps_ = 256, viewSteps_ = 128, hazeSteps_ = 64, knots_ = 3, layers_ = 1, channels_ = 1;
  float genStep_ = 0.5f;
  double generationSamples_ = 0.0;  // per frame, counted on the CPU in setup
  bool jitter_ = true, surfaceShadows_ = true, needsSharedShadowMap_ = true;
  bool tintedByRatio_ = false;  // one channel for volumes of several colours: an approximation
  dsm::LightViews views_;
  gl::Texture map_;
  std::vector<gl::Framebuffer> faceFbos_;  // per light view and colour channel, its layers attached
  gl::Buffer ubo_;
  gl::Program generateProgram_, marchProgram_, surfaceProgram_;
};

}  // namespace vs
