#include "raymarch.hpp"

namespace vs {

static constexpr const char* kPass = "Ray Marching";

std::string RaymarchMethod::description() const {
  return "brute-force per-pixel ray marching of L_s with shadow-map visibility (the reference)";
}

Capabilities RaymarchMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = true;
  c.texturedLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  return c;
}

std::vector<ParamSpec> RaymarchMethod::params() const {
  return {ParamSpec::integer("steps", 64, 1, 16384, "samples along each camera ray"),
          ParamSpec::flag("jitter", true, "stratified jitter inside each step (deterministic per pixel and seed)"),
          ParamSpec::choice("sampling", "uniform", {"uniform", "equiangular"},
                            "uniform steps in distance, or equiangular steps seen from a point/spot light")};
}

std::vector<std::string> RaymarchMethod::qualityLadder() const {
  return {"steps=8", "steps=16", "steps=32", "steps=64", "steps=128", "steps=256"};
}

std::string RaymarchMethod::referenceParams() const { return "steps=4096:jitter=1:sampling=equiangular"; }

void RaymarchMethod::setup(const SetupContext& context, const ParamValues& params) {
  steps_ = params.getInt("steps");
  jitter_ = params.getBool("jitter");
  equiangular_ = params.getString("sampling") == "equiangular";
  width_ = context.width;
  height_ = context.height;
  program_ = gl::buildFullscreen("methods/raymarch/shaders/raymarch.frag",
                                 sceneDefines(context.effects) + "#define EQUIANGULAR " +
                                     (equiangular_ ? "1" : "0") + "\n");
}

void RaymarchMethod::render(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kPass);
  frame.bindShared();
  glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
  glViewport(0, 0, frame.width, frame.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(program_.id());
  glUniform1i(0, steps_);
  glUniform1i(1, jitter_ ? 1 : 0);
  gl::drawFullscreenTriangle();
}

std::map<std::string, double> RaymarchMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  auto it = passes.find(kPass);
  double samples = double(width_) * double(height_) * double(steps_);
  if (it == passes.end() || it->second.medianMs <= 0.0) return {{"shadow_map_samples", samples}};
  return {{"shadow_map_samples", samples}, {"shadow_map_samples_per_s", samples / (it->second.medianMs * 1e-3)}};
}

}  // namespace vs
