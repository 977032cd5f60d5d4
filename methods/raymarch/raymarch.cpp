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
  c.volumeData = true;
  c.semiTransparentOccluders = true;
  c.coloredShadows = true;
  return c;
}

std::vector<ParamSpec> RaymarchMethod::params() const {
  return {ParamSpec::integer("steps", 64, 1, 16384, "samples along each camera ray"),
          ParamSpec::flag("jitter", true, "stratified jitter inside each step (deterministic per pixel and seed)"),
          ParamSpec::choice("sampling", "uniform", {"uniform", "equiangular"},
                            "uniform steps in distance, or equiangular steps seen from a point/spot light"),
          ParamSpec::real("vsteps", 1.0, 0.125, 16.0,
                          "volume data: light-ray steps per voxel of the nested march towards the light"),
          ParamSpec::integer("light_steps_max", 512, 16, 8192,
                             "volume data: most steps of the nested march per volume and sample")};
}

std::vector<std::string> RaymarchMethod::qualityLadder() const {
  return {"steps=8", "steps=16", "steps=32", "steps=64", "steps=128", "steps=256"};
}

std::string RaymarchMethod::referenceParams() const { return "steps=4096:jitter=1:sampling=equiangular:vsteps=2"; }

void RaymarchMethod::setup(const SetupContext& context, const ParamValues& params) {
  steps_ = params.getInt("steps");
  jitter_ = params.getBool("jitter");
  equiangular_ = params.getString("sampling") == "equiangular";
  volumeStepsPerVoxel_ = float(params.getFloat("vsteps"));
  lightStepsMax_ = params.getInt("light_steps_max");
  width_ = context.width;
  height_ = context.height;
  volumes_ = context.effects.volumeData;
  fboInscatter_ = 0;
  if (volumes_) {
    for (auto& t : opticalDepth_) t = gl::createTexture2D(GL_RGBA32F, width_, height_);
  }
  program_ = gl::buildFullscreen("methods/raymarch/shaders/raymarch.frag",
                                 sceneDefines(context.effects) + "#define EQUIANGULAR " +
                                     (equiangular_ ? "1" : "0") + "\n");
}

// Loop iterations one sample costs at most: the sample loop itself, the transmittance map's list
// walk and, per volume, its coefficient and segment loops and the nested march.
int RaymarchMethod::stepsPerPass(const Frame& frame) const {
  int perSample = 1;
  if (frame.transmittance) perSample += frame.transmittance->longestList();
  if (volumes_) perSample += frame.effects.volumeCount * (2 + lightStepsMax_);
  return std::max(1, (gl::kShaderLoopBudget - 64) / perSample);
}

void RaymarchMethod::render(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kPass);
  frame.bindShared();
  glViewport(0, 0, frame.width, frame.height);
  glDisable(GL_DEPTH_TEST);
  glUseProgram(program_.id());
  glUniform1i(0, steps_);
  glUniform1i(1, jitter_ ? 1 : 0);
  glUniform1f(2, volumeStepsPerVoxel_);
  glUniform1i(5, lightStepsMax_);
  int chunk = stepsPerPass(frame);
  passes_ = (steps_ + chunk - 1) / chunk;
  if (volumes_ && fboInscatter_ != frame.inscatter) {
    for (int k = 0; k < 2; ++k)
      passFbo_[k] = gl::createFramebuffer({{GL_COLOR_ATTACHMENT0, frame.inscatter},
                                           {GL_COLOR_ATTACHMENT1, opticalDepth_[k].id()}});
    fboInscatter_ = frame.inscatter;
  }
  if (passes_ > 1) {
    // Passes add their L_s; the alpha (the camera ray's volume transmittance) is the last pass's.
    const float nothing[4] = {0, 0, 0, 1};
    glClearNamedFramebufferfv(frame.inscatterFbo, GL_COLOR, 0, nothing);
    glEnablei(GL_BLEND, 0);
    glBlendEquationi(0, GL_FUNC_ADD);
    glBlendFuncSeparatei(0, GL_ONE, GL_ONE, GL_ONE, GL_ZERO);
  } else {
    glDisable(GL_BLEND);
  }
  for (int pass = 0; pass < passes_; ++pass) {
    if (volumes_) {
      // Optical depth in from the previous pass, out to the other texture.
      glBindFramebuffer(GL_FRAMEBUFFER, passFbo_[pass % 2].id());
      const GLenum targets[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
      glNamedFramebufferDrawBuffers(passFbo_[pass % 2].id(), 2, targets);
      glBindTextureUnit(bind::kFirstMethodUnit, opticalDepth_[(pass + 1) % 2].id());
      glDisablei(GL_BLEND, 1);
    } else {
      glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
    }
    glUniform1i(3, pass * chunk);
    glUniform1i(4, std::min(steps_, (pass + 1) * chunk));
    gl::drawFullscreenTriangle();
  }
  glDisable(GL_BLEND);
}

std::map<std::string, double> RaymarchMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  auto it = passes.find(kPass);
  double samples = double(width_) * double(height_) * double(steps_);
  if (it == passes.end() || it->second.medianMs <= 0.0) return {{"shadow_map_samples", samples}};
  return {{"shadow_map_samples", samples},
          {"shadow_map_samples_per_s", samples / (it->second.medianMs * 1e-3)},
          {"passes_per_frame", double(passes_)}};
}

}  // namespace vs
