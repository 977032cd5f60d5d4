#include "dsm.hpp"
#include "registry.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace vs {

static constexpr const char* kGeneration = "DSM Generation";
static constexpr const char* kMarch = "Volume March";
static constexpr const char* kSurface = "Surface Shadows";
static constexpr GLuint kDsmUniforms = 4;
static constexpr GLuint kDsmUnit = bind::kFirstMethodUnit;
static constexpr double kMaxMapBytes = 1024.0 * 1024.0 * 1024.0;

// std140 mirror of DsmBlock in shaders/dsm.glsl.
struct DsmUniforms {
  glm::mat4 faceViewProj[6];
  glm::mat4 faceInvViewProj[6];
  glm::vec4 params;  // resolution, faces, knots
  glm::vec4 thresholds[4];
  glm::vec4 knotTaus[4];  // -ln(1 - threshold)
  glm::vec4 channelRatio;  // rgb: dsm::channelRatios (one channel)
};
VS_STD140_MIRROR(DsmUniforms, "DsmBlock", VS_STD140_FIELD(DsmUniforms, faceViewProj), VS_STD140_FIELD(DsmUniforms, faceInvViewProj), VS_STD140_FIELD(DsmUniforms, params), VS_STD140_FIELD(DsmUniforms, thresholds), VS_STD140_FIELD(DsmUniforms, knotTaus), VS_STD140_FIELD(DsmUniforms, channelRatio));

namespace dsm {

LightViews fitLightViews(const Light& light, const glm::vec3& boxLo, const glm::vec3& boxHi, int resolution) {
  LightViews views;
  glm::vec3 center = 0.5f * (boxLo + boxHi);
  float radius = std::max(0.5f * glm::length(boxHi - boxLo), 1e-4f);
  std::array<glm::vec3, 8> corners;
  for (int i = 0; i < 8; ++i)
    corners[size_t(i)] = glm::vec3(i & 1 ? boxHi.x : boxLo.x, i & 2 ? boxHi.y : boxLo.y, i & 4 ? boxHi.z : boxLo.z);
  // One texel of margin on each side, so that bilinear lookups at the boxes' rim stay inside.
  float pad = 1.0f + 4.0f / float(std::max(resolution, 4));
  if (light.type == LightType::Directional) {
    glm::vec3 dir = glm::normalize(light.direction);
    glm::vec3 up = std::fabs(dir.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    glm::mat4 view = glm::lookAt(center - dir * (2.0f * radius), center, up);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const auto& c : corners) {
      glm::vec3 v = glm::vec3(view * glm::vec4(c, 1.0f));
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    float halfX = std::max(0.5f * (hi.x - lo.x) * pad, 1e-4f), halfY = std::max(0.5f * (hi.y - lo.y) * pad, 1e-4f);
    float cx = 0.5f * (hi.x + lo.x), cy = 0.5f * (hi.y + lo.y);
    glm::mat4 proj = glm::ortho(cx - halfX, cx + halfX, cy - halfY, cy + halfY, std::max(-hi.z - radius, 1e-4f),
                                -lo.z + radius);
    views.viewProj[0] = proj * view;
    return views;
  }
  glm::vec3 p = light.position;
  float farthest = 0.0f;
  for (const auto& c : corners) farthest = std::max(farthest, glm::length(c - p));
  float farZ = std::max(farthest * 1.01f, 1e-3f);
  glm::vec3 toCenter = center - p;
  float centerDist = glm::length(toCenter);
  bool single = centerDist > 1.05f * radius;  // outside the boxes' bounding sphere
  if (single) {
    glm::vec3 forward = toCenter / centerDist;
    glm::vec3 up = std::fabs(forward.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    glm::mat4 view = glm::lookAt(p, center, up);
    float tanHalf = 0.0f, nearZ = 1e30f;
    for (const auto& c : corners) {
      glm::vec3 v = glm::vec3(view * glm::vec4(c, 1.0f));
      float z = -v.z;
      nearZ = std::min(nearZ, z);
      tanHalf = std::max({tanHalf, std::fabs(v.x) / std::max(z, 1e-6f), std::fabs(v.y) / std::max(z, 1e-6f)});
    }
    tanHalf *= pad;
    // Past 60 degrees from the axis a single view wastes most texels: six faces instead.
    if (nearZ > 0.0f && tanHalf < 1.7320508f) {
      glm::mat4 proj = glm::perspective(2.0f * std::atan(tanHalf), 1.0f, std::max(0.5f * nearZ, 1e-5f), farZ);
      views.viewProj[0] = proj * view;
      return views;
    }
  }
  views.faces = 6;
  for (int f = 0; f < 6; ++f) views.viewProj[size_t(f)] = cubeFaceViewProj(p, f, std::max(farZ * 1e-5f, 1e-6f), farZ);
  return views;
}

std::vector<float> knotThresholds(int knots, float first, float last) {
  std::vector<float> t;
  for (int k = 0; k < knots; ++k) t.push_back(knots == 1 ? first : first + (last - first) * float(k) / float(knots - 1));
  return t;
}

static float mean(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

// A volume's largest optical thickness along its box diagonal, per unit of mean sigma_t.
static float thicknessWeight(const Volume& v) {
  return v.densityScale * v.maxDensity() * glm::length(v.boxHi - v.boxLo);
}

glm::vec3 channelRatios(const Scene& scene) {
  glm::vec3 channel(0.0f);
  float total = 0.0f;
  for (const Volume& v : scene.volumes) {
    float w = thicknessWeight(v);
    channel += w * v.sigmaT();
    total += w * mean(v.sigmaT());
  }
  return total > 0.0f ? channel / total : glm::vec3(1.0f);
}

bool oneColour(const Scene& scene) {
  glm::vec3 first(-1.0f);
  for (const Volume& v : scene.volumes) {
    float m = mean(v.sigmaT());
    if (!(m > 0.0f) || !(thicknessWeight(v) > 0.0f)) continue;  // casts no shadow
    glm::vec3 colour = v.sigmaT() / m;
    if (first.x < 0.0f) first = colour;
    else if (glm::length(colour - first) > 1e-5f * glm::length(first)) return false;
  }
  return true;
}

int channelsFor(const Scene& scene, const std::string& channels) {
  if (channels == "auto") return oneColour(scene) ? 1 : 3;
  return channels == "3" ? 3 : 1;
}

}  // namespace dsm

static void unionBox(const Scene& scene, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::vec3(1e30f);
  hi = glm::vec3(-1e30f);
  for (const auto& v : scene.volumes) {
    lo = glm::min(lo, v.boxLo);
    hi = glm::max(hi, v.boxHi);
  }
}

std::string DsmMethod::description() const {
  return "deep shadow maps from volume data (Shook): opacity-threshold depths per light texel, "
         "camera rays marched through the volumes";
}

Capabilities DsmMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = true;
  c.texturedLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  c.volumeData = true;
  c.semiTransparentOccluders = true;  // through the shared transmittance map
  c.coloredShadows = true;
  c.surfaceShadows = true;
  return c;
}

std::vector<std::string> DsmMethod::passes() const { return {kGeneration, kMarch, kSurface}; }

// Surface Shadows shades L_surf: timed, not scattering time.
std::vector<std::string> DsmMethod::surfacePasses() const { return {kSurface}; }

std::vector<ParamSpec> DsmMethod::params() const {
  return {ParamSpec::integer("res", 512, 16, 8192, "DSM resolution (texels per side, per face)"),
          ParamSpec::real("gen_step", 0.5, 0.01, 64.0, "DSM Generation: step length along light rays, in voxels of the finest volume"),
          ParamSpec::integer("gen_steps", 512, 1, 4096, "DSM Generation: most steps per light ray (the paper: 512)"),
          ParamSpec::integer("view_steps", 128, 1, 4096, "Volume March: steps along the camera ray through the volumes"),
          ParamSpec::integer("haze_steps", 64, 0, 4096,
                             "Volume March: steps over the rest of the camera ray (homogeneous medium only)"),
          ParamSpec::choice("knots", "3", {"3", "4", "8", "16"}, "opacity knots per texel (3: the paper; more: MRT layers)"),
          ParamSpec::real("first", 0.1, 0.001, 0.999, "opacity threshold of the first knot"),
          ParamSpec::real("last", 0.9, 0.001, 0.999, "opacity threshold of the last knot (knots evenly spaced between)"),
          ParamSpec::choice("interp", "linear", {"linear", "smoothstep", "bucket"},
                            "crossing depth between two steps: linear in opacity, smoothstep (the paper), bucket (step before)"),
          ParamSpec::choice("segments", "exponential", {"linear", "exponential"},
                            "visibility between knots: linear in opacity (the paper, Lokovic and Veach) or in optical depth (exact in homogeneous stretches)"),
          ParamSpec::choice("thresholds", "relative", {"absolute", "relative"},
                            "knot thresholds: fixed opacities (the paper), or fractions first..last of each ray's final opacity (optical depth with segments=exponential)"),
          ParamSpec::choice("filter", "hardware", {"hardware", "texels"},
                            "lookup: one bilinear lookup of the knots (the paper), or the four nearest texels' visibility functions blended"),
          ParamSpec::choice("channels", "auto", {"auto", "1", "3"},
                            "visibility functions per texel: 1 (mean extinction, each colour channel's transmittance a power of it: exact for volumes of one colour), 3 (one per colour channel: generation and lookups x3), auto (3 only for volumes of different colours)"),
          ParamSpec::flag("jitter", true, "stratified jitter of the camera-ray samples"),
          ParamSpec::flag("surface", true, "Surface Shadows: re-shade surfaces with the DSM's transmittance")};
}

std::vector<std::string> DsmMethod::qualityLadder() const {
  return {"res=128:gen_step=2:view_steps=32:haze_steps=16", "res=256:gen_step=1:view_steps=32:haze_steps=64",
          "res=512:gen_step=0.5:view_steps=128:haze_steps=64",
          "res=512:gen_step=0.5:view_steps=64:haze_steps=128:knots=8",
          "res=512:gen_step=0.25:view_steps=128:haze_steps=256:knots=16"};
}

// Samples DSM Generation takes per frame: the shader's span and step count, texel by texel.
static double generationSamples(const Scene& scene, const dsm::LightViews& views, int res, float stepVoxels, int maxSteps) {
  float voxel = 3e38f;
  for (const auto& v : scene.volumes)
    for (int a = 0; a < 3; ++a) voxel = std::min(voxel, (v.boxHi[a] - v.boxLo[a]) / float(std::max(v.dims[a], 1)));
  bool directional = scene.light.type == LightType::Directional;
  double total = 0.0;
  for (int f = 0; f < views.faces; ++f) {
    glm::mat4 inv = glm::inverse(views.viewProj[size_t(f)]);
    for (int y = 0; y < res; ++y)
      for (int x = 0; x < res; ++x) {
        glm::vec2 ndc((float(x) + 0.5f) / float(res) * 2.0f - 1.0f, (float(y) + 0.5f) / float(res) * 2.0f - 1.0f);
        glm::vec4 n = inv * glm::vec4(ndc, -1.0f, 1.0f), fa = inv * glm::vec4(ndc, 1.0f, 1.0f);
        glm::vec3 nearP = glm::vec3(n) / n.w, farP = glm::vec3(fa) / fa.w;
        glm::vec3 origin, dir;
        if (directional) {
          dir = glm::normalize(scene.light.direction);
          origin = nearP - dir * glm::dot(nearP, dir);
        } else {
          origin = scene.light.position;
          dir = glm::normalize(farP - origin);
        }
        float t0 = 3e38f, t1 = -3e38f;
        for (const auto& v : scene.volumes) {
          float lo = directional ? -3e38f : 0.0f, hi = 3e38f;
          for (int a = 0; a < 3; ++a) {
            float d = std::fabs(dir[a]) < 1e-30f ? 1e-30f : dir[a];
            float ta = (v.boxLo[a] - origin[a]) / d, tb = (v.boxHi[a] - origin[a]) / d;
            lo = std::max(lo, std::min(ta, tb));
            hi = std::min(hi, std::max(ta, tb));
          }
          if (hi > lo) {
            t0 = std::min(t0, lo);
            t1 = std::max(t1, hi);
          }
        }
        if (t1 > t0)
          total += std::clamp(std::ceil(std::min((t1 - t0) / std::max(voxel * stepVoxels, 1e-30f), 1e6f)), 1.0f, float(maxSteps));
      }
  }
  return total;
}

std::string DsmMethod::unsupportedReason(const Scene& scene, const ParamValues& params) const {
  std::string base = Method::unsupportedReason(scene, params);
  if (!base.empty()) return base;
  if (scene.volumes.empty()) return "needs volume data (a deep shadow map of the scene's volumes)";
  if (params.getFloat("first") >= params.getFloat("last") && std::stoi(params.getString("knots")) > 1)
    return "first must be below last (the knots' opacity thresholds increase)";
  glm::vec3 lo, hi;
  unionBox(scene, lo, hi);
  int res = params.getInt("res");
  int faces = dsm::fitLightViews(scene.light, lo, hi, res).faces;
  double bytes = double(res) * res * 16.0 * faces * dsm::layersFor(std::stoi(params.getString("knots"))) *
                 dsm::channelsFor(scene, params.getString("channels"));
  if (bytes > kMaxMapBytes)
    return "res=" + std::to_string(res) + " needs " + std::to_string(int(bytes / 1048576.0)) +
           " MiB of deep shadow map (at most 1024 MiB)";
  return "";
}

void DsmMethod::setup(const SetupContext& context, const ParamValues& params) {
  readParams(context, params);
  fitViewsAndUploadUniforms(context.scene, params);
  createMapAndFramebuffers(params.getString("filter") == "hardware");
  buildPrograms(context.scene, context.effects, params);
}

// The knobs kept as members (throws beyond GL_MAX_TEXTURE_SIZE).
void DsmMethod::readParams(const SetupContext& context, const ParamValues& params) {
  resolution_ = params.getInt("res");
  if (resolution_ > context.limits.maxTextureSize)
    throw std::runtime_error("res=" + std::to_string(resolution_) + " exceeds GL_MAX_TEXTURE_SIZE " +
                             std::to_string(context.limits.maxTextureSize));
  genSteps_ = params.getInt("gen_steps");
  genStep_ = float(params.getFloat("gen_step"));
  viewSteps_ = params.getInt("view_steps");
  hazeSteps_ = params.getInt("haze_steps");
  knots_ = std::stoi(params.getString("knots"));
  layers_ = dsm::layersFor(knots_);
  channels_ = dsm::channelsFor(context.scene, params.getString("channels"));
  tintedByRatio_ = channels_ == 1 && !dsm::oneColour(context.scene);
  jitter_ = params.getBool("jitter");
  surfaceShadows_ = params.getBool("surface");
  // Without meshes nothing but the volumes casts shadows: the map replaces the shared shadow map.
  needsSharedShadowMap_ = !context.scene.meshes.empty();
}

// The light views around the volumes, the generation's sample count, and DsmBlock.
void DsmMethod::fitViewsAndUploadUniforms(const Scene& scene, const ParamValues& params) {
  bool relative = params.getString("thresholds") == "relative";
  glm::vec3 lo, hi;
  unionBox(scene, lo, hi);
  views_ = dsm::fitLightViews(scene.light, lo, hi, resolution_);
  // Relative thresholds march every light ray twice (the final optical depth first); each colour
  // channel has its own marches.
  generationSamples_ = generationSamples(scene, views_, resolution_, genStep_, genSteps_) * (relative ? 2.0 : 1.0) * channels_;
  DsmUniforms uniforms{};
  for (int f = 0; f < 6; ++f) {
    uniforms.faceViewProj[f] = views_.viewProj[size_t(f)];
    uniforms.faceInvViewProj[f] = glm::inverse(views_.viewProj[size_t(f)]);
  }
  uniforms.params = glm::vec4(float(resolution_), float(views_.faces), float(knots_), 0.0f);
  std::vector<float> t = dsm::knotThresholds(knots_, float(params.getFloat("first")), float(params.getFloat("last")));
  for (int k = 0; k < knots_; ++k) {
    uniforms.thresholds[k / 4][k % 4] = t[size_t(k)];
    uniforms.knotTaus[k / 4][k % 4] = -std::log(std::max(1.0f - t[size_t(k)], 1e-30f));
  }
  uniforms.channelRatio = glm::vec4(dsm::channelRatios(scene), 0.0f);
  ubo_ = gl::createBuffer(sizeof uniforms, &uniforms, 0);
}

// The map (one layer per face, colour channel and group of four knots) and its framebuffers.
void DsmMethod::createMapAndFramebuffers(bool hardwareFilter) {
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
  map_ = gl::Texture(id);
  glTextureStorage3D(id, 1, GL_RGBA32F, resolution_, resolution_, views_.faces * channels_ * layers_);
  GLenum filter = hardwareFilter ? GL_LINEAR : GL_NEAREST;
  gl::setFilter(id, filter, filter);
  // One framebuffer per face and colour channel, its layers attached once (MRT: knots 4j..4j+3 in
  // target j); layer (face * channels + channel) * layers + j.
  std::vector<GLenum> targets;
  for (int j = 0; j < layers_; ++j) targets.push_back(GLenum(GL_COLOR_ATTACHMENT0 + j));
  faceFbos_.clear();
  for (int face = 0; face < views_.faces; ++face)
    for (int channel = 0; channel < channels_; ++channel) {
      glCreateFramebuffers(1, &id);
      faceFbos_.emplace_back(id);
      for (int j = 0; j < layers_; ++j)
        glNamedFramebufferTextureLayer(id, targets[size_t(j)], map_.id(), 0, (face * channels_ + channel) * layers_ + j);
      glNamedFramebufferDrawBuffers(id, layers_, targets.data());
      gl::checkFramebuffer(id, "deep shadow map");
    }
}

// The passes' programs, specialised by defines to the knots, filter, segments and channels.
void DsmMethod::buildPrograms(const Scene& scene, const Effects& effects, const ParamValues& params) {
  std::string interp = params.getString("interp");
  bool hardwareFilter = params.getString("filter") == "hardware";
  int interpCode = interp == "smoothstep" ? 1 : interp == "bucket" ? 2 : 0;
  bool exponential = params.getString("segments") == "exponential";
  bool relative = params.getString("thresholds") == "relative";
  // One map for grey volumes needs no per-channel power (llvmpipe would pay a log and three exps a lookup).
  const glm::vec3 ratio = dsm::channelRatios(scene);
  const bool grey = channels_ == 1 && ratio.x == 1.0f && ratio.y == 1.0f && ratio.z == 1.0f;
  std::string defines = sceneDefines(effects) + "#define DSM_KNOTS " + std::to_string(knots_) +
                        "\n#define DSM_LAYERS " + std::to_string(layers_) + "\n#define DSM_FILTER " +
                        (hardwareFilter ? "1" : "0") + "\n#define DSM_SEGMENTS " + (exponential ? "1" : "0") +
                        "\n#define DSM_RELATIVE " + (relative ? "1" : "0") + "\n#define DSM_FACES " + std::to_string(views_.faces) +
                        "\n#define DSM_CHANNELS " + std::to_string(channels_) +
                        "\n#define DSM_GREY " + (grey ? "1" : "0") + "\n";
  generateProgram_ = gl::buildFullscreen("methods/dsm/shaders/generate.frag",
                                         defines + "#define GEN_STEPS " + std::to_string(genSteps_) +
                                             "\n#define GEN_STEP_VOXELS " + std::to_string(genStep_) +
                                             "\n#define DSM_INTERP " + std::to_string(interpCode) + "\n");
  marchProgram_ = gl::buildFullscreen("methods/dsm/shaders/march.frag",
                                      defines + "#define VIEW_STEPS " + std::to_string(viewSteps_) +
                                          "\n#define HAZE_STEPS " + std::to_string(hazeSteps_) + "\n");
  if (surfaceShadows_) surfaceProgram_ = gl::buildFullscreen("methods/dsm/shaders/surface.frag", defines);
}

void DsmMethod::render(const Frame& frame, PassTimer& timer) {
  frame.bindShared();
  glBindBufferBase(GL_UNIFORM_BUFFER, kDsmUniforms, ubo_.id());
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  {
    auto scope = timer.scope(kGeneration);
    glBindTextureUnit(kDsmUnit, 0);
    glViewport(0, 0, resolution_, resolution_);
    glUseProgram(generateProgram_.id());
    for (int face = 0; face < views_.faces; ++face)
      for (int channel = 0; channel < channels_; ++channel) {
        glBindFramebuffer(GL_FRAMEBUFFER, faceFbos_[size_t(face * channels_ + channel)].id());
        glUniform1i(0, face);
        glUniform1i(1, channel);
        gl::drawFullscreenTriangle();
      }
  }
  glBindTextureUnit(kDsmUnit, map_.id());
  {
    auto scope = timer.scope(kMarch);
    glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
    glViewport(0, 0, frame.width, frame.height);
    glUseProgram(marchProgram_.id());
    glUniform1i(0, jitter_ ? 1 : 0);
    gl::drawFullscreenTriangle();
  }
  if (surfaceShadows_) {
    auto scope = timer.scope(kSurface);
    glBindFramebuffer(GL_FRAMEBUFFER, frame.directFbo);
    glUseProgram(surfaceProgram_.id());
    gl::drawFullscreenTriangle();
  }
  glBindTextureUnit(kDsmUnit, 0);
}

std::map<std::string, double> DsmMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  double samples = generationSamples_;
  std::map<std::string, double> out{{"dsm_faces", double(views_.faces)}, {"dsm_channels", double(channels_)},
                                    {"dsm_voxel_samples", samples}};
  auto it = passes.find(kGeneration);
  if (it != passes.end() && it->second.medianMs > 0.0)
    out["dsm_voxel_samples_per_s"] = samples / (it->second.medianMs * 1e-3);
  return out;
}

VS_REGISTER_METHOD(DsmMethod, 30);

}  // namespace vs
