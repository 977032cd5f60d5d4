// The scene-independent frame pipeline shared by every method: scene upload, shadow map,
// G-buffer, direct lighting and composite. Methods only write L_s into the in-scatter target.
#pragma once
#include <glm/glm.hpp>

#include <memory>
#include <string>

#include "harness/pipeline/effects.hpp"
#include "harness/gl/gl.hpp"
#include "harness/io/image.hpp"
#include "scenes/scene.hpp"
#include "harness/gl/timer.hpp"

namespace vs {

// Texture units and binding points: harness/gl/bindings.hpp (namespace bind).

// Volumes a scene may hold (each a 3D texture on its own unit).
constexpr int kMaxVolumes = 4;

// std140 mirror of VolumeBlock in common.glsl.
struct VolumeUniforms {
  glm::ivec4 count{0};                 // x = number of volumes
  glm::vec4 boxLo[kMaxVolumes];        // xyz
  glm::vec4 boxHi[kMaxVolumes];        // xyz
  glm::vec4 coeff[kMaxVolumes];        // x mean sigma_s, y mean sigma_t over the colour channels per
                                       // unit density (times density_scale), z max density, w smallest
                                       // voxel side (world units)
  glm::vec4 scattering[kMaxVolumes];   // rgb sigma_s per unit density (times density_scale)
  glm::vec4 extinction[kMaxVolumes];   // rgb sigma_t per unit density (times density_scale)
};

// The scene's volumes on the GPU (built only when the scene has volume data).
struct VolumesGpu {
  int count = 0;
  gl::Texture density[kMaxVolumes];
  gl::Buffer ubo;
  VolumeUniforms uniforms{};
  explicit VolumesGpu(const Scene& scene);
  void bind() const;
};

// Semi-transparent occluders seen from the light: per light texel (and cube face for point lights) a
// list of every semi-transparent surface crossing, with its distance from the light and its
// transmittance; T(x) is the product over the crossings in front of x (common.glsl,
// translucentTransmittance). Exact along each light ray at texel resolution, any number of layers.
struct ShadowMap;
struct SceneGpu;
class TransmittanceMap {
 public:
  TransmittanceMap(const SceneGpu& geometry);
  // Rebuilt for the shadow map's faces, matrices and size.
  void render(const ShadowMap& shadow, const glm::vec3& lightPos, const glm::vec3& lightDir, int lightType);
  void clear(const ShadowMap& shadow);  // no crossings: T = 1
  void bind() const;
  size_t nodeCount() const { return nodes_; }
  int longestList() const { return longest_; }  // the lookups' loop trip count

 private:
  void resize(const ShadowMap& shadow);
  const SceneGpu& geometry_;
  gl::Program build_;
  gl::Texture heads_, lengths_;  // first node and list length per light texel and face
  gl::Buffer nodeBuffer_, counter_, ubo_;
  gl::Framebuffer fbo_;
  size_t capacity_ = 0, nodes_ = 0;
  int longest_ = 0;
  int size_ = 0, faces_ = 0;
};

// Why the scene's volumes cannot be uploaded with these limits (too many, too large); empty if they can.
std::string volumeLimitProblem(const Scene& scene, const gl::Limits& limits);

// std140 mirror of FrameUniforms in common.glsl.
struct FrameUniforms {
  glm::mat4 viewProj, invViewProj, view, proj;
  glm::mat4 lightViewProj;   // spot/directional shadow map and light-texture projection
  glm::mat4 lightView;       // light-space view (point: identity rotation at the light)
  glm::vec4 eye;             // xyz; w = 0
  glm::vec4 cameraForward;   // xyz; w = tan(fovY/2)
  glm::vec4 lightPos;        // xyz; w = type (0 point, 1 spot, 2 directional)
  glm::vec4 lightDir;        // xyz direction light travels; w = cos(outer cone)
  glm::vec4 lightColor;      // rgb * intensity; w = cos(inner cone)
  glm::vec4 shadowParams;    // x near, y far (light projection), z shadow-map size, w has light texture
  glm::vec4 medium;          // sigma_s, sigma_a, sigma_t, g
  glm::vec4 cameraClip;      // near, far, phase (0 iso, 1 HG), directional ortho half-extent
  glm::ivec4 viewport;       // width, height, frame index, seed
  glm::vec4 lightEmission;   // x: 1 cosine lobe about lightDir (area lights, virtual point lights); y: two-sided
};

// Vertex attributes: 0 position, 1 normal, 2 albedo, 3 transmittance colour, 4 texture coordinate,
// 5 alpha (x texture or -1, y MASK cutoff or -1 for BLEND, z opacity; see Mesh::opacityAt).
// Indices are ordered opaque meshes first, then semi-transparent ones; cut-out meshes (opacity 0)
// are not uploaded. Alpha textures sit on unit bind::kAlphaTexture while their meshes draw.
struct SceneGpu {
  gl::VertexArray vao;
  gl::Buffer vertices, indices;
  GLsizei indexCount = 0;        // every uploaded triangle
  GLsizei opaqueIndexCount = 0;  // the first opaqueIndexCount indices belong to opaque meshes
  glm::vec3 boundsLo{0}, boundsHi{0};
  explicit SceneGpu(const Scene& scene);
  // Uploads the vertices of `scene` again: the same meshes in new poses (a moving scene's frame).
  // The buffer has dynamic storage only when the scene's geometry moves.
  void updateVertices(const Scene& scene);
  void draw() const;             // everything the camera sees
  void drawOpaque() const;       // what the shadow map holds
  void drawTranslucent() const;  // what the transmittance map holds

 private:
  struct Range {
    GLsizei first, count;
    GLuint texture;  // 0: no alpha texture
  };
  std::vector<Range> translucent_;
  std::vector<gl::Texture> alphaTextures_;
  size_t vertexFloats_ = 0;
};

struct ShadowMap {
  LightType type = LightType::Point;
  int size = 0;
  gl::Texture depth;                  // 2D or cube, DEPTH_COMPONENT32F, compare mode on
  gl::Sampler compareSampler, plainSampler;
  gl::Framebuffer fbos[6];
  glm::mat4 viewProj{1.0f};           // 2D
  glm::mat4 faceViewProj[6];          // cube
  float nearZ = 0.01f, farZ = 100.0f;
  float orthoHalfExtent = 1.0f;
};

struct RenderSize {
  int width = 0, height = 0;
};

// What a method sees of the frame. Valid during Method::render.
struct Frame {
  const Scene& scene;
  const SceneGpu& geometry;
  const Effects& effects;
  const FrameUniforms& uniforms;
  const ShadowMap& shadowMap;
  int width, height;
  uint32_t frameIndex, seed;
  GLuint gPosition, gNormal, gAlbedo, depth;
  GLuint inscatter;         // RGBA32F texture the method writes L_s into
  GLuint inscatterFbo;      // framebuffer with `inscatter` as color attachment 0, viewport = size;
                            // with volume data `volumeTransmittance` is attachment 1 (draw buffer 1)
  GLuint volumeTransmittance;  // RGBA32F: the camera ray's rgb transmittance through volume data (0 without)
  GLuint direct;            // L_surf from Direct Lighting (RGBA32F)
  GLuint directFbo;         // a method with its own surface shadows may re-shade L_surf here
                            // (common.glsl surfaceRadiance); the composite reads it
  GLuint lightTexture;      // 0 when the light has no texture
  GLuint uboId;             // FrameUniforms
  const VolumesGpu* volumes;  // null without volume data
  const TransmittanceMap* transmittance;  // null without semi-transparent occluders
  bool shadowCasters;       // false: the run measures unshadowed L_s (RunOptions::shadowCasters)
  // Binds the frame's UBO, shadow map, light texture and G-buffer to the units in `bind`.
  void bindShared() const;
};

// The passes SharedPasses runs for every method; a method's own passes are the rest, and their sum
// is its scattering time (MethodRun::scatterMs, as the papers count).
inline constexpr const char* kShadowMapPass = "Shadow Map";
inline constexpr const char* kTransmittanceMapPass = "Transmittance Map";
inline constexpr const char* kGBufferPass = "G Buffer";
inline constexpr const char* kDirectLightingPass = "Direct Lighting";
inline constexpr const char* kCompositePass = "Composite";
// A moving scene's geometry placed at the frame's time and uploaded again: scene work that every
// method's frame pays alike, so shared.
inline constexpr const char* kGeometryUpdatePass = "Geometry Update";
inline constexpr const char* kSharedPasses[] = {kShadowMapPass,      kTransmittanceMapPass, kGBufferPass,
                                                kDirectLightingPass, kCompositePass,        kGeometryUpdatePass};
bool isSharedPass(const std::string& pass);

class SharedPasses {
 public:
  SharedPasses(const Scene& scene, const SceneGpu& geometry, const Effects& effects, int width, int height);
  // Rebuilds the shadow map if `size` changed.
  void setShadowMapSize(int size);
  // Refits the shadow map's projections to the scene's light after it moved (the viewer, the
  // per-VPL wrapper); reallocates only when the kind of map changes.
  void lightMoved();
  void updateUniforms(uint32_t frameIndex, uint32_t seed);
  void renderShadowMap(PassTimer& timer, const char* pass = kShadowMapPass);
  void setShadowCasters(bool on) { shadowCasters_ = on; }
  // >= 0: semi-transparent occluders are alpha-tested into the shadow map at this opacity and the
  // transmittance map stays empty (T = 1), so every pass sees binary visibility; -1: as the scene
  // has them (Capabilities::alphaTestedOccluders).
  void setAlphaTest(float threshold);
  void renderGBuffer(PassTimer& timer);     // "G Buffer"
  void renderDirect(PassTimer& timer);      // "Direct Lighting"
  void clearInscatter();
  void clearShadowMap();                    // every face to the far plane: V = 1
  void composite(PassTimer& timer);         // "Composite"
  Frame frame() const;
  Image readInscatter() const;
  Image readFinal() const;
  Image readDirect() const;
  const FrameUniforms& uniforms() const { return uniforms_; }
  const ShadowMap& shadowMap() const { return shadow_; }

 private:
  void buildShadowMap(int size);
  void fitShadowProjection();  // near/far and view-projections of shadow_ for the scene's light
  void drawFullscreen(GLuint fbo, GLuint program) const;  // shared bindings + one full-screen triangle
  Image readTexture(GLuint texture) const;

  const Scene& scene_;
  const SceneGpu& geometry_;
  const Effects& effects_;
  int width_, height_;
  FrameUniforms uniforms_{};
  gl::Buffer ubo_;
  ShadowMap shadow_;
  gl::Texture lightTexture_;
  std::unique_ptr<VolumesGpu> volumes_;
  std::unique_ptr<TransmittanceMap> transmittance_;
  gl::Sampler lightSampler_;
  gl::Texture gPosition_, gNormal_, gAlbedo_, depth_, direct_, inscatter_, volumeTransmittance_, final_;
  gl::Framebuffer gbufferFbo_, directFbo_, inscatterFbo_, finalFbo_;
  gl::Program alphaShadowProgram_;  // semi-transparent occluders alpha-tested (setAlphaTest)
  float alphaTest_ = -1.0f;
  bool transmittanceCleared_ = false;
  gl::Program shadowProgram_, skyProgram_, gbufferProgram_, directProgram_, compositeProgram_;
  uint32_t frameIndex_ = 0, seed_ = 0;
  bool shadowCasters_ = true;
};


// Preprocessor defines that specialise shaders to the scene's light type, light texture and phase
// function (see common.glsl); pass them to gl::buildProgram.
std::string sceneDefines(const Effects& effects);

// View-projection of cube face `face` (+x, -x, +y, -y, +z, -z, GL cube-map conventions) around a point.
glm::mat4 cubeFaceViewProj(const glm::vec3& position, int face, float nearZ, float farZ);

// Camera and light matrices, exposed for CPU-side integrators and tests.
glm::mat4 cameraView(const Camera& c);
glm::mat4 cameraProjection(const Camera& c, float aspect);

}  // namespace vs
