// Imperfect voxelized shadow volumes (Wyman and co-authors): an area light as N virtual point
// lights, each with a coarse epipolar VSV grid voxelized from an imperfect shadow map (Ritschel et
// al. 2008), all grids packed into one texture, scanned in one pass and gathered per pixel with
// visibility interpolated in (α, θ).
#pragma once
#include <glm/glm.hpp>

#include <memory>
#include <vector>

#include "epipolar/epipolar_grid.hpp"
#include "harness/pipeline/method.hpp"

namespace vs {

namespace ivsv {
// Points spread over the opaque triangles by area (`count` of them, consecutive blocks of
// `perLight` being independent samples: one block per VPL). xyz position, w unused. alphaTest >= 0
// adds the semi-transparent occluders where their opacity is at least alphaTest (SetupContext).
std::vector<glm::vec4> samplePointCloud(const Scene& scene, size_t count, uint32_t seed, float alphaTest = -1.0f);
// Paraboloid projection of the hemisphere around unit `normal` (tangent frame t, b): direction d
// (unit, dot(d, normal) > 0) to [-1, 1]^2.
glm::vec2 paraboloid(const glm::vec3& d, const glm::vec3& t, const glm::vec3& b, const glm::vec3& normal);
// std140 mirror of IvsvBlock in shaders/ivsv.glsl.
struct Uniforms {
  glm::ivec4 dims;    // VPL count, grid, ISM tiles per side, ISM tile texels
  glm::ivec4 counts;  // points per VPL, gather steps, first VPL of the gather pass, VPLs in it
  glm::vec4 tangent, bitangent, normal;  // the light's frame; normal.w = ISM depth range
  glm::vec4 weight;   // rgb one VPL's intensity; w jitter
};
}  // namespace ivsv

class IvsvMethod : public Method {
 public:
  std::string name() const override { return "ivsv"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> qualityLadder() const override;
  std::vector<std::string> approximations() const override {
    return {"area light as virtual point lights", "visibility from imperfect shadow maps (point splats, pull-push)",
            "visibility quantised to a coarse epipolar grid per VPL"};
  }
  std::string unsupportedReason(const Scene& scene, const ParamValues& params) const override;
  // The VPLs, the light's frame and the ISMs' depth range are placed in setup.
  bool setupDependsOnLight(const Effects& effects) const override {
    (void)effects;
    return true;
  }
  // The ISMs' point cloud is sampled on the meshes in setup.
  bool setupDependsOnGeometry(const Effects& effects) const override {
    (void)effects;
    return true;
  }
  // The ISM's holes leak light: with the light shut inside a box (tests/hard_cases.cpp) L_s
  // relMSE reaches 0.05 at the defaults.
  double declaredRelMseBound() const override { return 0.1; }
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;
  std::vector<DebugView> debugViews() const override;

 private:
  void sampleLights(const Frame& frame, PassTimer& timer);
  void renderImperfectShadowMaps(const Frame& frame, PassTimer& timer);
  void voxelize(PassTimer& timer);
  void gather(const Frame& frame, PassTimer& timer);

  int count_ = 64, grid_ = 128, pointsPerLight_ = 4096, ismRes_ = 64, pullPushLevels_ = 3, steps_ = 64;
  bool interpolate_ = true, jitter_ = true;
  float bias_ = 2.0f;  // ISM depth bias, texel angles
  int tiles_ = 1;          // ISM atlas: tiles_ x tiles_ tiles of ismRes_ texels
  float far_ = 1.0f;       // ISM depth range
  float minDistance_ = 1e-3f;
  std::vector<glm::vec3> positions_;
  glm::vec3 tangent_{1, 0, 0}, bitangent_{0, 0, 1}, normal_{0, -1, 0};
  gl::Buffer points_, lights_, ubo_;
  gl::Texture ism_, splats_, grids_;  // ISM levels (R32F, 0 = hole), the splat target (R32UI bits)
  gl::Program splat_, resolve_, pullPush_, voxelize_, gather_;
  std::unique_ptr<epipolar::Scan> scan_;
  int lightsPerGatherPass_ = 1;
  int voxelizeRows_ = 1;  // theta rows per Voxelize workgroup
  GLsizei pointsTotal_ = 0;
  ivsv::Uniforms uniforms_{};
};

}  // namespace vs
