#include "slicemap.hpp"
#include "registry.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace vs {

static constexpr const char* kNearFar = "Near/Far Maps";
static constexpr const char* kSlicemap = "Slicemap";
static constexpr const char* kPrefix = "Prefix Counts";
static constexpr const char* kScattering = "Scattering";
static constexpr const char* kShading = "Shading";
static constexpr GLuint kSlicemapUniforms = 4;
static constexpr GLuint kBitsUnit = bind::kFirstMethodUnit;
static constexpr GLuint kNearFarUnit = bind::kFirstMethodUnit + 1;
static constexpr GLuint kPrefixUnit = bind::kFirstMethodUnit + 2;
static constexpr double kMaxBytes = 1024.0 * 1024.0 * 1024.0;

// std140 mirror of SlicemapBlock in shaders/slicemap.glsl.
struct SlicemapUniforms {
  glm::mat4 faceViewProj[6];
  glm::vec4 params;  // resolution, faces, slices, classes
  glm::vec4 classRange[slicemap::kMaxClasses];  // uniform slicing: near, far, slices / (far - near)
  glm::vec4 classTransmittance[slicemap::kMaxClasses];     // rgb
  glm::vec4 classLog2Transmittance[slicemap::kMaxClasses];  // rgb: log2 of one crossing (-100 for 0)
  glm::vec4 classBin[slicemap::kMaxClasses];   // x alpha bin (-1: constant transmittance), y bins, z minimum
  glm::vec4 classTint[slicemap::kMaxClasses];  // rgb: the alpha bin's transmittance colour
};
VS_STD140_MIRROR(SlicemapUniforms, "SlicemapBlock", VS_STD140_FIELD(SlicemapUniforms, faceViewProj), VS_STD140_FIELD(SlicemapUniforms, params), VS_STD140_FIELD(SlicemapUniforms, classRange), VS_STD140_FIELD(SlicemapUniforms, classTransmittance), VS_STD140_FIELD(SlicemapUniforms, classLog2Transmittance), VS_STD140_FIELD(SlicemapUniforms, classBin), VS_STD140_FIELD(SlicemapUniforms, classTint));

namespace slicemap {

int AlphaQuantization::binOf(float opacity) const {
  if (!(opacity >= minimum) || bins < 1) return -1;
  float span = std::max(1.0f - minimum, 1e-6f);
  return std::clamp(int((opacity - minimum) / span * float(bins)), 0, bins - 1);
}

std::vector<ColorClass> colorClasses(const Scene& scene, bool opaqueInSlices, std::string& problem,
                                     const AlphaQuantization& alpha) {
  std::vector<ColorClass> classes;
  auto classOf = [&](glm::vec3 t) -> ColorClass& {
    for (auto& c : classes)
      if (c.alphaBin < 0 && glm::all(glm::lessThan(glm::abs(c.transmittance - t), glm::vec3(1e-3f)))) return c;
    classes.push_back({t, false, false, {}, -1, glm::vec3(0.0f)});
    return classes.back();
  };
  // Alpha-textured BLEND meshes by tint: per bin the texels' opacity sum and count.
  struct Bins {
    glm::vec3 tint;
    std::vector<double> sum, count;
    std::vector<int> meshes;
    std::set<std::pair<int, float>> counted;  // (texture, opacity): meshes sharing both count it once
  };
  std::vector<Bins> textured;
  problem.clear();
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    const Mesh& mesh = scene.meshes[i];
    if (mesh.indices.empty() || mesh.opacity <= 0.0f) continue;
    if (mesh.isOpaque()) {
      if (opaqueInSlices) {
        ColorClass& c = classOf(glm::vec3(0.0f));
        c.opaqueMeshes = true;
        c.meshes.push_back(int(i));
      }
      continue;
    }
    if (mesh.alphaTexture >= 0 && mesh.alphaCutoff < 0.0f && size_t(mesh.alphaTexture) < scene.alphaTextures.size()) {
      auto it = std::find_if(textured.begin(), textured.end(), [&](const Bins& b) {
        return glm::all(glm::lessThan(glm::abs(b.tint - mesh.transmittanceColor), glm::vec3(1e-3f)));
      });
      if (it == textured.end()) {
        textured.push_back({mesh.transmittanceColor, std::vector<double>(size_t(alpha.bins), 0.0),
                            std::vector<double>(size_t(alpha.bins), 0.0), {}, {}});
        it = textured.end() - 1;
      }
      // A texture atlas shared by many primitives is read once per opacity (the bins' means are
      // the same), not once per mesh.
      if (it->counted.insert({mesh.alphaTexture, mesh.opacity}).second)
        for (float a : scene.alphaTextures[size_t(mesh.alphaTexture)].alpha) {
          float o = mesh.opacityAt(a);
          int bin = alpha.binOf(o);
          if (bin < 0) continue;
          it->sum[size_t(bin)] += o;
          it->count[size_t(bin)] += 1.0;
        }
      it->meshes.push_back(int(i));
      continue;
    }
    // A MASK texel that stays is opaque: its crossing passes the transmittance colour.
    ColorClass& c = classOf(mesh.alphaTexture >= 0 ? mesh.transmittanceColor : mesh.crossingTransmittance());
    c.translucentMeshes = true;
    c.meshes.push_back(int(i));
  }
  for (const Bins& b : textured)
    for (int bin = 0; bin < alpha.bins; ++bin) {
      if (b.count[size_t(bin)] <= 0.0) continue;
      float mean = float(b.sum[size_t(bin)] / b.count[size_t(bin)]);
      ColorClass c{glm::vec3(1.0f) - mean * (glm::vec3(1.0f) - b.tint), false, true, b.meshes, bin, b.tint};
      classes.push_back(std::move(c));
    }
  if (classes.size() > size_t(kMaxClasses)) {
    problem = "the occluders have " + std::to_string(classes.size()) + " different transmittances; at most " +
              std::to_string(kMaxClasses) + " colour classes" +
              (textured.empty() ? "" : " (per-texel opacity takes up to alpha_classes of them: lower it)");
    return {};
  }
  return classes;
}

glm::vec2 sliceRange(const Scene& scene, const ColorClass& cls) {
  const Light& light = scene.light;
  bool directional = light.type == LightType::Directional;
  glm::vec3 dir = glm::length(light.direction) > 0.0f ? glm::normalize(light.direction) : glm::vec3(0, -1, 0);
  float lo = 3e38f, hi = -3e38f;
  for (int index : cls.meshes)
    for (const glm::vec3& p : scene.meshes[size_t(index)].positions) {
      float d = directional ? glm::dot(p, dir) : glm::length(p - light.position);
      if (!std::isfinite(d)) continue;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  if (lo > hi) return {0.0f, 1.0f};
  // A little margin so that the nearest and farthest surfaces fall inside the first and last slice.
  // A class lying at one depth (a plane facing the light) still gets slices no thinner than float
  // noise in positions.
  float pad = std::max((hi - lo) * 1e-4f, 1e-3f * std::max({std::fabs(hi), std::fabs(lo), 1.0f}));
  return {lo - pad, hi + pad};
}

int bitsInFront(const std::vector<uint32_t>& words, int slice) {
  int n = 0;
  for (size_t w = 0; w < words.size(); ++w) {
    int bits = std::clamp(slice - int(w) * 32, 0, 32);
    uint32_t mask = bits >= 32 ? 0xFFFFFFFFu : (1u << bits) - 1u;
    n += __builtin_popcount(words[w] & mask);
  }
  return n;
}

}  // namespace slicemap

std::string SlicemapMethod::description() const {
  return "slicemap voxelization and transmittance shadow maps (Eisemann & Decoret 2006): light-space columns of "
         "one-bit slices set with a logical OR, visibility by counting the bits in front";
}

Capabilities SlicemapMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = true;
  c.texturedLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  c.semiTransparentOccluders = true;
  c.coloredShadows = true;
  c.surfaceShadows = true;
  return c;
}

std::vector<std::string> SlicemapMethod::passes() const {
  return {kNearFar, kSlicemap, kPrefix, kScattering, kShading};
}

// Shading shades L_surf: timed, not scattering time.
std::vector<std::string> SlicemapMethod::surfacePasses() const { return {kShading}; }

std::vector<ParamSpec> SlicemapMethod::params() const {
  return {ParamSpec::integer("res", 512, 16, 8192, "slicemap resolution (texels per side, per cube face)").pow2(),
          ParamSpec::integer("targets", 1, 1, slicemap::kMaxTargets, "RGBA32UI render targets per slicemap: 128 slices each"),
          ParamSpec::choice("slicing", "uniform", {"uniform", "local"},
                            "uniform: slices span the occluders' near..far; local: each column's own near..far (a Near/Far Maps pass first)"),
          ParamSpec::choice("opaque", "slices", {"slices", "shadowmap"},
                            "opaque occluders: voxelized as a class of their own (transmittance 0), or in the shared shadow "
                            "map tested first (the paper's transmittance shadow maps)"),
          ParamSpec::choice("lookup", "scan", {"scan", "prefix"},
                            "bits in front: scan every word (the paper), or per-word prefix counts built once per frame (two fetches)")
              .sameImage(),
          ParamSpec::flag("pack", true,
                          "colour classes share the targets' words (4 x targets / classes words each), so that one fetch "
                          "serves every class"),
          ParamSpec::integer("steps", 128, 1, 4096, "Scattering: samples along the camera ray"),
          ParamSpec::integer("share", 1, 1, 16,
                             "Scattering: consecutive samples whose visibility comes from one column fetch (ours)"),
          ParamSpec::flag("equiangular", true, "Scattering: equiangular samples (point and spot lights)"),
          ParamSpec::flag("jitter", true, "stratified jitter of the camera-ray samples"),
          ParamSpec::flag("surface", true, "Shading: surfaces shadowed by the slicemap (the paper's use)"),
          ParamSpec::integer("alpha_classes", 2, 1, slicemap::kMaxClasses,
                             "per-texel opacity (alpha-textured BLEND): opacity bins, each a class of its mean opacity (ours)"),
          ParamSpec::real("alpha_min", 0.1, 0.0, 1.0,
                          "per-texel opacity: fragments below this opacity set no bit (the bins span alpha_min..1)")};
}

std::vector<std::string> SlicemapMethod::qualityLadder() const {
  return {"res=128:steps=32", "res=256:steps=64", "res=512:steps=128", "res=512:targets=2:slicing=local:steps=256",
          "res=512:targets=4:slicing=local:steps=512"};
}

std::vector<std::string> SlicemapMethod::approximations() const {
  std::vector<std::string> list = {
      "occluder depth quantised to slices; one bit per slice and column (layers in one slice count once)"};
  if (perTexelOpacity_) {
    char text[160];
    std::snprintf(text, sizeof text, "per-texel opacity quantised to %d classes of their mean (none below %g)",
                  alpha_.bins, double(alpha_.minimum));
    list.push_back(text);
  }
  return list;
}

static bool opaqueInSlices(const ParamValues& params) { return params.getString("opaque") == "slices"; }

static slicemap::AlphaQuantization alphaQuantization(const ParamValues& params) {
  return {params.getInt("alpha_classes"), float(params.getFloat("alpha_min"))};
}

std::string SlicemapMethod::unsupportedReason(const Scene& scene, const ParamValues& params) const {
  std::string base = Method::unsupportedReason(scene, params);
  if (!base.empty()) return base;
  std::string problem;
  auto classes = slicemap::colorClasses(scene, opaqueInSlices(params), problem, alphaQuantization(params));
  if (!problem.empty()) return problem;
  bool pack = params.getBool("pack");
  if (params.getInt("share") > 1 && params.getString("lookup") == "prefix")
    return "share > 1 needs lookup=scan (a shared fetch holds the column's words)";
  if (pack && params.getString("lookup") == "prefix" && classes.size() > 1)
    return "lookup=prefix needs pack=0 with more than one colour class (prefix counts run over one class's words)";
  if (pack && classes.size() > size_t(4 * params.getInt("targets")))
    return "pack=1 needs at least one word per class: " + std::to_string(classes.size()) + " classes in " +
           std::to_string(4 * params.getInt("targets")) + " words";
  int res = params.getInt("res");
  int faces = scene.light.type == LightType::Point ? 6 : 1;
  double bytes = double(res) * res * 16.0 * faces * double(pack ? 1 : classes.size()) * params.getInt("targets");
  if (params.getString("lookup") == "prefix") bytes *= 1.5;
  if (bytes > kMaxBytes)
    return "res=" + std::to_string(res) + " needs " + std::to_string(int(bytes / 1048576.0)) +
           " MiB of slicemaps (at most 1024 MiB)";
  return "";
}

void SlicemapMethod::setup(const SetupContext& context, const ParamValues& params) {
  geometry_ = &context.geometry;
  readParamsAndClasses(context.scene, params);
  checkLimits(context.limits);
  countVoxelizedTriangles(context.scene);
  uploadClassUniforms(context.scene);
  createSlicemaps();
  buildPrograms(context.effects, params);
}

// The knobs, then the colour classes the scene's occluders fall into (throws when it has too many
// transmittances).
void SlicemapMethod::readParamsAndClasses(const Scene& scene, const ParamValues& params) {
  resolution_ = params.getInt("res");
  targets_ = params.getInt("targets");
  local_ = params.getString("slicing") == "local";
  prefix_ = params.getString("lookup") == "prefix";
  packed_ = false;  // set once the classes are known: packing one class changes nothing
  steps_ = params.getInt("steps");
  share_ = params.getInt("share");
  jitter_ = params.getBool("jitter");
  surface_ = params.getBool("surface");
  opaqueInSlices_ = opaqueInSlices(params);
  // The opaque class replaces the shared shadow map only where the Shading pass re-shades surfaces.
  needsSharedShadowMap_ = !(opaqueInSlices_ && surface_);
  faces_ = scene.light.type == LightType::Point ? 6 : 1;
  std::string problem;
  alpha_ = alphaQuantization(params);
  classes_ = slicemap::colorClasses(scene, opaqueInSlices_, problem, alpha_);
  if (!problem.empty()) throw std::runtime_error(problem);
  perTexelOpacity_ = std::any_of(classes_.begin(), classes_.end(), [](const slicemap::ColorClass& c) { return c.alphaBin >= 0; });
  packed_ = params.getBool("pack") && int(classes_.size()) > 1;
}

// Resolution, render targets and array layers within the GL implementation's limits.
void SlicemapMethod::checkLimits(const gl::Limits& limits) const {
  if (resolution_ > limits.maxTextureSize)
    throw std::runtime_error("res=" + std::to_string(resolution_) + " exceeds GL_MAX_TEXTURE_SIZE " +
                             std::to_string(limits.maxTextureSize));
  if (targets_ > limits.maxDrawBuffers || targets_ > limits.maxColorAttachments)
    throw std::runtime_error("targets=" + std::to_string(targets_) + " exceeds GL_MAX_DRAW_BUFFERS " +
                             std::to_string(limits.maxDrawBuffers));
  GLint maxLayers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (layers() > maxLayers)
    throw std::runtime_error(std::to_string(layers()) + " slicemap layers exceed GL_MAX_ARRAY_TEXTURE_LAYERS " +
                             std::to_string(maxLayers));
}

// Triangles voxelized per frame, over all faces (the stats' count).
void SlicemapMethod::countVoxelizedTriangles(const Scene& scene) {
  triangles_ = 0.0;
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.opacity <= 0.0f) continue;
    bool member = mesh.isOpaque() ? opaqueInSlices_ : true;
    if (member) triangles_ += double(mesh.triangleCount()) * faces_;
  }
}

// SlicemapBlock: each class's slicing range, transmittance and alpha bin.
void SlicemapMethod::uploadClassUniforms(const Scene& scene) {
  int classes = int(classes_.size());
  SlicemapUniforms uniforms{};
  float slices = float(32 * wordsPerClass());  // per class
  uniforms.params = glm::vec4(float(resolution_), float(faces_), slices, float(classes));
  for (int c = 0; c < classes; ++c) {
    glm::vec2 range = slicemap::sliceRange(scene, classes_[size_t(c)]);
    uniforms.classRange[c] = glm::vec4(range, slices / std::max(range.y - range.x, 1e-30f), 0.0f);
    glm::vec3 t = classes_[size_t(c)].transmittance;
    uniforms.classTransmittance[c] = glm::vec4(t, 0.0f);
    uniforms.classLog2Transmittance[c] = glm::vec4(glm::log2(glm::max(t, glm::vec3(1e-30f))), 0.0f);
    uniforms.classBin[c] = glm::vec4(float(classes_[size_t(c)].alphaBin), float(alpha_.bins), alpha_.minimum, 0.0f);
    uniforms.classTint[c] = glm::vec4(classes_[size_t(c)].tint, 0.0f);
  }
  ubo_ = gl::createBuffer(sizeof uniforms, &uniforms);
}

// The slicemap textures (bits; prefix counts; near/far maps) and a framebuffer per (face, class).
void SlicemapMethod::createSlicemaps() {
  int classes = int(classes_.size());
  sliceFbos_.clear();
  nearFarFbos_.clear();
  slices_.reset();
  nearFar_.reset();
  prefixCounts_.reset();
  if (classes == 0) return;
  // Point lights: cube-map arrays, so that a lookup is one fetch by direction (the sampler picks
  // the face); spot and directional lights: 2D arrays.
  GLenum target = faces_ == 6 ? GL_TEXTURE_CUBE_MAP_ARRAY : GL_TEXTURE_2D_ARRAY;
  auto create = [&](GLenum format, int count) {
    GLuint id = 0;
    glCreateTextures(target, 1, &id);
    glTextureStorage3D(id, 1, format, resolution_, resolution_, count);
    gl::setFilter(id, GL_NEAREST, GL_NEAREST);  // integer textures are incomplete otherwise
    return gl::Texture(id);
  };
  slices_ = create(GL_RGBA32UI, layers());
  if (prefix_) prefixCounts_ = create(GL_RGBA16UI, layers());
  if (local_) nearFar_ = create(GL_RG32F, faces_ * classes);
  GLuint id = 0;
  std::vector<GLenum> drawBuffers;
  for (int k = 0; k < targets_; ++k) drawBuffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + k));
  for (int f = 0; f < faces_; ++f)
    for (int c = 0; c < classes; ++c) {
      if (c < slots()) {
        glCreateFramebuffers(1, &id);
        sliceFbos_.emplace_back(id);
        for (int k = 0; k < targets_; ++k)
          glNamedFramebufferTextureLayer(id, drawBuffers[size_t(k)], slices_.id(), 0, layer(f, c, k));
        glNamedFramebufferDrawBuffers(id, targets_, drawBuffers.data());
        gl::checkFramebuffer(id, "slicemap");
      }
      if (local_) {
        glCreateFramebuffers(1, &id);
        nearFarFbos_.emplace_back(id);
        glNamedFramebufferTextureLayer(id, GL_COLOR_ATTACHMENT0, nearFar_.id(), 0, c * faces_ + f);
        gl::checkFramebuffer(id, "slicemap near/far map");
      }
    }
}

// The passes' programs, specialised by defines to the classes and knobs.
void SlicemapMethod::buildPrograms(const Effects& effects, const ParamValues& params) {
  int classes = int(classes_.size());
  bool grey = std::all_of(classes_.begin(), classes_.end(), [](const slicemap::ColorClass& c) {
    return c.transmittance.r == c.transmittance.g && c.transmittance.g == c.transmittance.b;
  });
  std::string defines = sceneDefines(effects) + "#define SLICEMAP_CLASSES " + std::to_string(classes) +
                        "\n#define SLICEMAP_TARGETS " + std::to_string(targets_) + "\n#define SLICEMAP_LOCAL " +
                        (local_ ? "1" : "0") + "\n#define SLICEMAP_PREFIX " + (prefix_ ? "1" : "0") +
                        "\n#define SLICEMAP_OPAQUE_IN_SLICES " + (opaqueInSlices_ ? "1" : "0") +
                        "\n#define SLICEMAP_CUBE " + (faces_ == 6 ? "1" : "0") + "\n#define SLICEMAP_PACKED " +
                        (packed_ ? "1" : "0") + "\n#define SLICEMAP_CLASS_WORDS " + std::to_string(wordsPerClass()) +
                        "\n#define SLICEMAP_GREY " + (grey ? "1" : "0") +
                        "\n#define SLICEMAP_SHARE " + std::to_string(share_) + "\n";
  const gl::ShaderStage vertex{GL_VERTEX_SHADER, "harness/shaders/transmittance.vert"};
  if (classes > 0) {
    voxelizeProgram_ = gl::buildProgram({vertex, {GL_FRAGMENT_SHADER, "methods/slicemap/shaders/voxelize.frag"}}, defines);
    if (local_)
      nearFarProgram_ = gl::buildProgram({vertex, {GL_FRAGMENT_SHADER, "methods/slicemap/shaders/voxelize.frag"}},
                                         defines + "#define NEAR_FAR_PASS 1\n");
    if (prefix_) prefixProgram_ = gl::buildCompute("methods/slicemap/shaders/prefix.comp", defines);
  }
  marchProgram_ = gl::buildFullscreen("methods/slicemap/shaders/march.frag",
                                      defines + "#define MARCH_EQUIANGULAR " +
                                          (params.getBool("equiangular") ? "1" : "0") + "\n");
  if (surface_) surfaceProgram_ = gl::buildFullscreen("methods/slicemap/shaders/surface.frag", defines);
}

void SlicemapMethod::voxelize(const Frame& frame, PassTimer& timer) {
  int classes = int(classes_.size());
  const glm::mat4* views = faces_ == 6 ? frame.shadowMap.faceViewProj : &frame.shadowMap.viewProj;
  glViewport(0, 0, resolution_, resolution_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // thin and open geometry: both sides
  auto drawClass = [&](int c) {
    if (!frame.shadowCasters) return;
    glUniform1i(4, c);
    if (classes_[size_t(c)].opaqueMeshes) {
      glUniform1i(6, 1);
      geometry_->drawOpaque();
    }
    // The semi-transparent meshes draw for the classes that hold any (their fragments pick theirs).
    if (!classes_[size_t(c)].translucentMeshes) return;
    glUniform1i(6, 0);
    geometry_->drawTranslucent();
  };
  if (local_) {
    auto scope = timer.scope(kNearFar);
    // Each column's nearest and farthest crossing in one pass: MIN blending of (d, -d).
    glUseProgram(nearFarProgram_.id());
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    const float empty[4] = {3e38f, 3e38f, 0.0f, 0.0f};
    for (int f = 0; f < faces_; ++f) {
      glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(views[f]));
      for (int c = 0; c < classes; ++c) {
        GLuint fbo = nearFarFbos_[size_t(f * classes + c)].id();
        glClearNamedFramebufferfv(fbo, GL_COLOR, 0, empty);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        drawClass(c);
      }
    }
    glBlendEquation(GL_FUNC_ADD);
    glDisable(GL_BLEND);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  }
  {
    auto scope = timer.scope(kSlicemap);
    glUseProgram(voxelizeProgram_.id());
    glBindTextureUnit(kNearFarUnit, local_ ? nearFar_.id() : 0);
    glEnable(GL_COLOR_LOGIC_OP);
    glLogicOp(GL_OR);
    const GLuint zero[4] = {0, 0, 0, 0};
    for (int f = 0; f < faces_; ++f) {
      glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(views[f]));
      for (int c = 0; c < classes; ++c) {
        GLuint fbo = sliceFbos_[size_t(f * slots() + (packed_ ? 0 : c))].id();
        if (c < slots()) {  // packed classes OR into the words the first one cleared
          for (int k = 0; k < targets_; ++k) glClearNamedFramebufferuiv(fbo, GL_COLOR, k, zero);
        }
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        drawClass(c);
      }
    }
    glDisable(GL_COLOR_LOGIC_OP);
    glLogicOp(GL_COPY);
  }
  if (prefix_) {
    auto scope = timer.scope(kPrefix);
    glUseProgram(prefixProgram_.id());
    glUniform1i(0, faces_);
    glBindImageTexture(0, slices_.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32UI);
    glBindImageTexture(1, prefixCounts_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16UI);
    glDispatchCompute(GLuint((resolution_ + 7) / 8), GLuint((resolution_ + 7) / 8), GLuint(faces_ * slots()));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  }
}

void SlicemapMethod::render(const Frame& frame, PassTimer& timer) {
  frame.bindShared();
  // The light views are the shared shadow map's (cube faces for point lights).
  SlicemapUniforms head{};
  const glm::mat4* views = faces_ == 6 ? frame.shadowMap.faceViewProj : &frame.shadowMap.viewProj;
  for (int f = 0; f < faces_; ++f) head.faceViewProj[f] = views[f];
  glNamedBufferSubData(ubo_.id(), 0, sizeof head.faceViewProj, head.faceViewProj);
  glBindBufferBase(GL_UNIFORM_BUFFER, kSlicemapUniforms, ubo_.id());
  if (!classes_.empty()) voxelize(frame, timer);
  glBindTextureUnit(kBitsUnit, slices_.id());
  glBindTextureUnit(kNearFarUnit, nearFar_.id());
  glBindTextureUnit(kPrefixUnit, prefixCounts_.id());
  glDisable(GL_DEPTH_TEST);
  {
    auto scope = timer.scope(kScattering);
    glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
    glViewport(0, 0, frame.width, frame.height);
    const float clear[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    glClearNamedFramebufferfv(frame.inscatterFbo, GL_COLOR, 0, clear);
    glUseProgram(marchProgram_.id());
    glUniform1i(0, steps_);
    glUniform1i(1, jitter_ ? 1 : 0);
    // llvmpipe ends the loops of an invocation after 65,535 iterations in all (gl::kShaderLoopBudget):
    // long marches run as several additive passes.
    int perSample = 1 + int(classes_.size()) * (2 + targets_);
    int chunk = std::max(gl::kShaderLoopBudget / perSample, 1);
    chunk = std::max(chunk / share_ * share_, share_);  // whole groups of shared fetches per pass
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    for (int first = 0; first < steps_; first += chunk) {
      glUniform1i(2, first);
      glUniform1i(3, std::min(first + chunk, steps_));
      gl::drawFullscreenTriangle();
    }
    glDisable(GL_BLEND);
  }
  if (surface_) {
    auto scope = timer.scope(kShading);
    glBindFramebuffer(GL_FRAMEBUFFER, frame.directFbo);
    glUseProgram(surfaceProgram_.id());
    gl::drawFullscreenTriangle();
  }
  for (GLuint unit : {kBitsUnit, kNearFarUnit, kPrefixUnit}) glBindTextureUnit(unit, 0);
}

std::vector<uint32_t> SlicemapMethod::readSlicemap(int face, int cls) const {
  if (!slices_ || face < 0 || face >= faces_ || cls < 0 || cls >= int(classes_.size()))
    throw std::runtime_error("no slicemap for face " + std::to_string(face) + ", class " + std::to_string(cls));
  size_t texels = size_t(resolution_) * size_t(resolution_);
  std::vector<uint32_t> plane(texels * 4), columns(texels * 4 * size_t(targets_));
  // Per column: the words of target 0, then target 1, ...
  for (int k = 0; k < targets_; ++k) {
    glGetTextureSubImage(slices_.id(), 0, 0, 0, layer(face, cls, k), resolution_, resolution_, 1, GL_RGBA_INTEGER,
                         GL_UNSIGNED_INT, GLsizei(plane.size() * 4), plane.data());
    for (size_t t = 0; t < texels; ++t)
      for (int w = 0; w < 4; ++w) columns[(t * size_t(targets_) + size_t(k)) * 4 + size_t(w)] = plane[t * 4 + size_t(w)];
  }
  return columns;
}

std::map<std::string, double> SlicemapMethod::stats(const std::map<std::string, TimingStats>& passes) const {
  double slices = 32.0 * wordsPerClass();  // per class
  double voxels = double(resolution_) * resolution_ * faces_ * double(classes_.size()) * slices;
  std::map<std::string, double> out{{"slicemap_slices", slices},
                                    {"slicemap_classes", double(classes_.size())},
                                    {"slicemap_triangles", triangles_},
                                    {"slicemap_voxels", voxels}};
  auto it = passes.find(kSlicemap);
  if (it != passes.end() && it->second.medianMs > 0.0) {
    out["slicemap_triangles_per_s"] = triangles_ / (it->second.medianMs * 1e-3);
    out["slicemap_voxels_per_s"] = voxels / (it->second.medianMs * 1e-3);
  }
  return out;
}

VS_REGISTER_METHOD(SlicemapMethod, 40);

}  // namespace vs
