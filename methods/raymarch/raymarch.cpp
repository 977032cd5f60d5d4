#include "raymarch.hpp"

#include <cstdio>

#include <glm/gtc/type_ptr.hpp>

#include "registry.hpp"

#include "harness/pipeline/vpl.hpp"

namespace vs {

static constexpr const char* kPass = "Ray Marching";
static constexpr const char* kAreaShadowPass = "Area Light Shadow Maps";
static constexpr int kMaxLightSamples = 256;
static constexpr GLuint kVplShadowUnit = bind::kFirstMethodUnit + 1;
static constexpr GLuint kVplUniforms = 3;

// std140 mirror of AreaLightBlock in raymarch.frag.
struct AreaLightUniforms {
  glm::vec4 position[kMaxLightSamples];  // xyz
  glm::vec4 weight;                      // rgb radiance x area / samples; w count
  glm::vec4 range;                       // x near, y far of the cube maps
};
VS_STD140_MIRROR(AreaLightUniforms, "AreaLightBlock", VS_STD140_FIELD(AreaLightUniforms, position), VS_STD140_FIELD(AreaLightUniforms, weight), VS_STD140_FIELD(AreaLightUniforms, range));

std::string RaymarchMethod::description() const {
  return "brute-force per-pixel ray marching of L_s with shadow-map visibility (the reference)";
}

Capabilities RaymarchMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = c.areaLight = c.cosineLobe = true;
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
                             "volume data: most steps of the nested march per volume and sample"),
          ParamSpec::integer("light_samples", 16, 1, kMaxLightSamples,
                             "area lights: stratified points on the light, each with its own cube shadow map"),
          ParamSpec::integer("light_sm", 256, 16, 2048, "area lights: cube shadow-map size per light sample").pow2(),
          ParamSpec::flag("light_shift", false,
                          "area lights: light samples shifted off the Hammersley points the VPL methods use (the reference)")};
}

std::vector<std::string> RaymarchMethod::passes() const { return {kAreaShadowPass, kPass}; }

std::vector<std::string> RaymarchMethod::qualityLadder() const {
  return {"steps=8", "steps=16", "steps=32", "steps=64", "steps=128", "steps=256"};
}

// Uniform steps (the papers' brute force) and, where a point or spot light makes it the stronger
// baseline, equiangular steps: the shootout draws both brute-force curves.
std::vector<Method::QualitySeries> RaymarchMethod::qualitySeries(const Effects& effects) const {
  std::vector<QualitySeries> series = {{"uniform", qualityLadder()}};
  if (effects.light == LightType::Point || effects.light == LightType::Spot) {
    QualitySeries equiangular{"equiangular", {}};
    for (const std::string& rung : qualityLadder()) equiangular.rungs.push_back(rung + ":sampling=equiangular");
    series.push_back(equiangular);
  }
  return series;
}

std::string RaymarchMethod::referenceParams(const Effects& effects, const ReferenceBudget& budget) const {
  auto capped = [](int value, int most) { return std::to_string(most > 0 ? std::min(value, most) : value); };
  const int lightSamples = budget.lightSamples > 0 ? std::min(budget.lightSamples, kMaxLightSamples) : 64;
  // Area lights: the light samples dominate the error (scripts/benchmark-effects: at 64 samples,
  // 256 steps are within relMSE 1.4e-3 of 4096), and 4096 x 64 took 130 s at 384x288.
  // The light samples are shifted off the Hammersley points that ivsv, the per-VPL wrapper and
  // raymarch's own light_samples use: a reference on the same points would hide their VPL error.
  if (effects.areaLight)
    return "steps=" + capped(1024, budget.maxSteps) + ":jitter=1:sampling=equiangular:light_samples=" + std::to_string(lightSamples) + ":light_sm=" +
           capped(512, budget.maxShadowMapSize) + ":light_shift=1";
  return "steps=" + capped(4096, budget.maxSteps) + ":jitter=1:sampling=equiangular:vsteps=2";
}

// The series are qualitySeries()'s: uniform steps (the papers' brute force), equiangular steps.
std::string RaymarchMethod::baselineParams(const BaselinePoint& point) const {
  if (point.series != "uniform" && point.series != "equiangular") return "";
  std::string params = "steps=" + std::to_string(point.steps);
  if (point.lightRaySteps > 0) {
    char vsteps[32];
    std::snprintf(vsteps, sizeof vsteps, "%g", point.lightRaySteps);
    params += std::string(":vsteps=") + vsteps;
  }
  params += ":sampling=" + point.series;
  if (point.lightSamples > 0) params += ":light_samples=" + std::to_string(point.lightSamples);
  return params;
}

std::string RaymarchMethod::unsupportedReason(const Scene& scene, const ParamValues& params) const {
  Effects e = deriveEffects(scene);
  if (e.areaLight && (e.volumeData || e.semiTransparent))
    return "area lights together with volume data or semi-transparent occluders are not supported";
  return Method::unsupportedReason(scene, params);
}

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
  lightSamples_ = context.effects.areaLight ? params.getInt("light_samples") : 0;
  lightShadowSize_ = params.getInt("light_sm");
  program_ = gl::buildFullscreen("methods/raymarch/shaders/raymarch.frag",
                                 sceneDefines(context.effects) + "#define MARCH_EQUIANGULAR " +
                                     (equiangular_ ? "1" : "0") + "\n#define AREA_SAMPLES " +
                                     std::to_string(lightSamples_) + "\n");
  if (lightSamples_ > 0) {
    const Light& light = context.scene.light;
    vplPositions_ = virtualPointLightPositions(light, lightSamples_, params.getBool("light_shift"));
    // Cube maps reach every corner of the scene's bounds from any point on the light.
    glm::vec3 lo = context.geometry.boundsLo, hi = context.geometry.boundsHi;
    float reach = glm::length(hi - lo) + 2.0f * std::max({light.width, light.height, light.radius}) +
                  glm::length(light.position - 0.5f * (lo + hi));
    vplFar_ = std::max(reach * 1.01f, 1e-3f);
    vplNear_ = std::max(vplFar_ * 1e-4f, 1e-5f);
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_CUBE_MAP_ARRAY, 1, &id);
    vplShadows_ = gl::Texture(id);
    glTextureStorage3D(id, 1, GL_DEPTH_COMPONENT32F, lightShadowSize_, lightShadowSize_, 6 * lightSamples_);
    glCreateFramebuffers(1, &id);
    vplFbo_ = gl::Framebuffer(id);
    glNamedFramebufferDrawBuffer(id, GL_NONE);
    glNamedFramebufferReadBuffer(id, GL_NONE);
    glCreateSamplers(1, &id);
    vplSampler_ = gl::Sampler(id);
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    shadowProgram_ = gl::buildProgram({{GL_VERTEX_SHADER, "harness/shaders/shadow.vert"},
                                       {GL_FRAGMENT_SHADER, "harness/shaders/shadow.frag"}});
    AreaLightUniforms al{};
    for (int k = 0; k < lightSamples_; ++k) al.position[k] = glm::vec4(vplPositions_[size_t(k)], 1.0f);
    al.weight = glm::vec4(light.color * light.intensity * light.area() / float(lightSamples_), float(lightSamples_));
    al.range = glm::vec4(vplNear_, vplFar_, 0.0f, 0.0f);
    vplUbo_ = gl::createBuffer(sizeof al, &al, 0);
  }
}

// Loop iterations one sample costs at most: the sample loop itself, the transmittance map's list
// walk and, per volume, its coefficient and segment loops and the nested march.
int RaymarchMethod::stepsPerPass(const Frame& frame) const {
  int perSample = 1 + lightSamples_;
  if (frame.transmittance) perSample += frame.transmittance->longestList();
  if (volumes_) perSample += frame.effects.volumeCount * (2 + lightStepsMax_);
  return std::max(1, (gl::kShaderLoopBudget - 64) / perSample);
}

void RaymarchMethod::renderAreaLightShadows(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kAreaShadowPass);
  glUseProgram(shadowProgram_.id());
  glBindFramebuffer(GL_FRAMEBUFFER, vplFbo_.id());
  glViewport(0, 0, lightShadowSize_, lightShadowSize_);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  const float one = 1.0f;
  for (int k = 0; k < lightSamples_; ++k) {
    for (int face = 0; face < 6; ++face) {
      glNamedFramebufferTextureLayer(vplFbo_.id(), GL_DEPTH_ATTACHMENT, vplShadows_.id(), 0, 6 * k + face);
      glClearNamedFramebufferfv(vplFbo_.id(), GL_DEPTH, 0, &one);
      glm::mat4 m = cubeFaceViewProj(vplPositions_[size_t(k)], face, vplNear_, vplFar_);
      glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(m));
      if (frame.shadowCasters) frame.geometry.drawOpaque();
    }
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_DEPTH_TEST);
}

void RaymarchMethod::render(const Frame& frame, PassTimer& timer) {
  if (lightSamples_ > 0) renderAreaLightShadows(frame, timer);
  auto scope = timer.scope(kPass);
  frame.bindShared();
  if (lightSamples_ > 0) {
    glBindTextureUnit(kVplShadowUnit, vplShadows_.id());
    glBindSampler(kVplShadowUnit, vplSampler_.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, kVplUniforms, vplUbo_.id());
  }
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
                                           {GL_COLOR_ATTACHMENT1, frame.volumeTransmittance},
                                           {GL_COLOR_ATTACHMENT2, opticalDepth_[k].id()}});
    fboInscatter_ = frame.inscatter;
  }
  if (passes_ > 1) {
    // Passes add their L_s; the camera ray's volume transmittance (draw buffer 1) is the last pass's.
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
      const GLenum targets[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
      glNamedFramebufferDrawBuffers(passFbo_[pass % 2].id(), 3, targets);
      glBindTextureUnit(bind::kFirstMethodUnit, opticalDepth_[(pass + 1) % 2].id());
      glDisablei(GL_BLEND, 1);
      glDisablei(GL_BLEND, 2);
    } else {
      glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
    }
    glUniform1i(3, pass * chunk);
    glUniform1i(4, std::min(steps_, (pass + 1) * chunk));
    gl::drawFullscreenTriangle();
  }
  glDisable(GL_BLEND);
  if (lightSamples_ > 0) glBindSampler(kVplShadowUnit, 0);
}

std::map<std::string, double> RaymarchMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  auto it = passes.find(kPass);
  double samples = double(width_) * double(height_) * double(steps_);
  if (it == passes.end() || it->second.medianMs <= 0.0) return {{"shadow_map_samples", samples}};
  return {{"shadow_map_samples", samples},
          {"shadow_map_samples_per_s", samples / (it->second.medianMs * 1e-3)},
          {"passes_per_frame", double(passes_)}};
}

VS_REGISTER_METHOD(RaymarchMethod, 0);

}  // namespace vs
