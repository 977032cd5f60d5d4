// Slicemap voxelization and transmittance shadow maps (Eisemann & Decoret, I3D 2006): every light
// texel is a column of slices, one bit each, set in one rasterization pass with a logical OR; the
// camera ray's samples count the set bits in front of them (opaque: any bit; semi-transparent:
// (1 - sigma)^n per colour class).
#pragma once
#include <glm/glm.hpp>

#include "harness/pipeline/method.hpp"

namespace vs {

namespace slicemap {

constexpr int kSlicesPerTarget = 128;  // one RGBA32UI texel: 4 x 32 bits
constexpr int kMaxTargets = 8;
constexpr int kMaxClasses = 4;

// Geometry with one transmittance per crossing, voxelized into a slicemap of its own (the paper's
// colour classes). Transmittance 0: opaque.
struct ColorClass {
  glm::vec3 transmittance{0.0f};
  bool opaqueMeshes = false;  // the scene's opaque meshes belong to this class
  bool translucentMeshes = false;  // and semi-transparent ones
  std::vector<int> meshes;    // indices into Scene::meshes
  // Per-texel opacity (alpha-textured BLEND meshes, ours): the fragments whose opacity falls in
  // bin `alphaBin` of AlphaQuantization and whose transmittance colour is `tint`; `transmittance`
  // is that of the bin's mean opacity over the texels. -1: a class of constant transmittance.
  int alphaBin = -1;
  glm::vec3 tint{0.0f};
};

// How per-texel opacity becomes classes: opacities from `minimum` to 1 in `bins` equal bins, each
// a class of its texels' mean opacity; below `minimum` a fragment sets no bit.
struct AlphaQuantization {
  int bins = 2;
  float minimum = 0.1f;
  int binOf(float opacity) const;  // -1 below minimum
};

// The classes a scene's occluders fall into. opaqueInSlices: the opaque meshes join the class of
// transmittance 0 instead of the shared shadow map. When the scene cannot be voxelized (too many
// transmittances) `problem` says why and the list is empty.
std::vector<ColorClass> colorClasses(const Scene& scene, bool opaqueInSlices, std::string& problem,
                                     const AlphaQuantization& alpha = {});

// Range of light distances (point/spot) or of depths along the light direction (directional)
// that a class's vertices span: its uniform slicing's near and far.
glm::vec2 sliceRange(const Scene& scene, const ColorClass& cls);

// Bits set in front of slice `slice` (cells 0 .. slice-1) of a column of `words` 32-bit words:
// the CPU mirror of the shaders' count, for tests.
int bitsInFront(const std::vector<uint32_t>& words, int slice);

}  // namespace slicemap

class SlicemapMethod : public Method {
 public:
  std::string name() const override { return "slicemap"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> surfacePasses() const override;
  std::vector<std::string> qualityLadder() const override;
  std::vector<std::string> approximations() const override;
  std::string unsupportedReason(const Scene& scene, const ParamValues& params) const override;
  bool needsSharedShadowMap() const override { return needsSharedShadowMap_; }
  bool lightFixedAtSetup() const override { return true; }  // depth slices are fitted to the light in setup
  // ...and to the depth range of each colour class's meshes.
  bool setupDependsOnGeometry(const Effects& effects) const override {
    (void)effects;
    return true;
  }
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;
  // The words of every column of one (face, class) slicemap as the last frame left them: res x res
  // columns of 4 x targets words, row by row (tests and figures).
  std::vector<uint32_t> readSlicemap(int face, int cls) const;
  // Spot and directional lights: the first class's slices, one bit at a time, and the local
  // slicing's near/far map. (Point lights keep cube-map arrays, which the bit view does not read.)
  std::vector<DebugView> debugViews() const override {
    std::vector<DebugView> views;
    if (!slices_ || faces_ != 1) return views;
    views.push_back({"slicemap bits (first class)", slices_.id(), DebugView::Kind::Bits, slicemap::kSlicesPerTarget * targets_});
    if (nearFar_) views.push_back({"near/far map (near, -far)", nearFar_.id(), DebugView::Kind::Value, int(classes_.size()), 1, 2});
    return views;
  }
  int resolution() const { return resolution_; }
  int targets() const { return targets_; }

 private:
  // The steps of setup(), in order.
  void readParamsAndClasses(const Scene& scene, const ParamValues& params);
  void checkLimits(const gl::Limits& limits) const;
  void countVoxelizedTriangles(const Scene& scene);
  void uploadClassUniforms(const Scene& scene);
  void createSlicemaps();
  void buildPrograms(const Effects& effects, const ParamValues& params);
  void voxelize(const Frame& frame, PassTimer& timer);
  // Layer (2D array) or layer-face (cube-map array, point lights) of one target of a class's
  // slicemap; packed classes share one set of targets.
  int layer(int face, int cls, int target) const { return ((packed_ ? 0 : cls) * targets_ + target) * faces_ + face; }
  int slots() const { return packed_ ? 1 : int(classes_.size()); }
  int layers() const { return faces_ * slots() * targets_; }  // of the slicemap arrays
  int wordsPerClass() const { return packed_ ? 4 * targets_ / std::max(int(classes_.size()), 1) : 4 * targets_; }

  const SceneGpu* geometry_ = nullptr;
  std::vector<slicemap::ColorClass> classes_;
  slicemap::AlphaQuantization alpha_;
  bool perTexelOpacity_ = false;  // some class holds alpha-textured BLEND fragments
  int resolution_ = 512, targets_ = 1, faces_ = 1, steps_ = 128, share_ = 1;
  bool local_ = false, prefix_ = false, packed_ = false, jitter_ = true, surface_ = true, opaqueInSlices_ = false;
  bool needsSharedShadowMap_ = true;
  double triangles_ = 0.0;  // voxelized per frame (all faces and classes)
  gl::Texture slices_, nearFar_, prefixCounts_;
  std::vector<gl::Framebuffer> sliceFbos_, nearFarFbos_;  // per (face, class)
  gl::Buffer ubo_;
  gl::Program nearFarProgram_, voxelizeProgram_, prefixProgram_, marchProgram_, surfaceProgram_;
};

}  // namespace vs
