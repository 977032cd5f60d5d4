// The epipolar voxel grid of voxelized shadow volumes (Wyman 2011), shared by vsv and ivsv (the
// imperfect VSVs of area lights): the epipolar frame, grid sizes and coordinates, the RGBA32UI
// voxel buffer and the "Scan VSV" prefix OR along α.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "harness/gl/gl.hpp"

namespace vs {
namespace epipolar {

// Epipolar frame (§2.1): axis from the eye towards the light, θ the angle of the epipolar half-plane
// around it, α the angle at the eye from the axis, φ the angle at the light from the light-to-eye
// direction. `distance` is |light - eye|, clamped away from zero (§4.2): the grid's light sits on
// the axis at that distance. A directional light has its axis towards the light at infinity and
// φ becomes the distance from the axis (light rays are parallel to it), up to `phiRange`.
struct EpipolarBasis {
  glm::dvec3 eye{0}, light{0}, axis{0, 0, -1}, e1{1, 0, 0}, e2{0, 1, 0};
  double distance = 1.0;
  bool directional = false;
  double phiRange = 3.14159265358979323846;  // fixed φ_max: π, or the largest distance from the axis
};
// `fallbackAxis` is used when the light is (almost) at the eye.
EpipolarBasis makeBasis(glm::dvec3 eye, glm::dvec3 light, glm::dvec3 fallbackAxis, double minDistance);
// Directional light travelling along `travelDir`; `phiRange` bounds every occluder's distance
// from the axis (see sceneAxisDistance).
EpipolarBasis makeDirectionalBasis(glm::dvec3 eye, glm::dvec3 travelDir, double phiRange);
// Largest distance from the line through `eye` along unit `axis` over the box [lo, hi].
double sceneAxisDistance(glm::dvec3 eye, glm::dvec3 axis, glm::dvec3 lo, glm::dvec3 hi);

struct EpiCoords {
  double theta = 0, alpha = 0, phi = 0;  // θ in [0, 2π), α and φ in [0, π]
};
EpiCoords toEpipolar(const EpipolarBasis& basis, glm::dvec3 point);

// Grid resolution: N_α columns, N_θ rows, N_φ bits (128 per RGBA32UI texel, one layer per 128).
struct GridSize {
  int nAlpha = 256, nTheta = 512, nPhi = 256;
  int layers() const { return (nPhi + 127) / 128; }
};
int thetaRow(double theta, int nTheta);
int alphaColumn(double alpha, double alphaMax, int nAlpha);  // -1 at or beyond alphaMax
int phiBin(double phi, double phiMax, int nPhi);             // -1 at or beyond phiMax

// std140 mirror of VsvBlock in shaders/epipolar.glsl.
struct GridUniforms {
  glm::vec4 eye;        // xyz; w = distance to the grid light
  glm::vec4 light;      // xyz grid light
  glm::vec4 axis, e1, e2;
  glm::ivec4 grid;      // N_α, N_θ, N_φ, layers
  glm::vec4 ranges;     // fixed α_max, fixed φ_max, dynamic (1/0), directional (1/0)
};
GridUniforms makeGridUniforms(const EpipolarBasis& basis, const GridSize& size, bool dynamicRanges);

// CPU reference of the scan: words hold layers x N_θ x N_α texels of 4 uints (layer-major, rows,
// then columns), the layout glGetTextureImage returns for the voxel buffer.
void prefixOrRowsCpu(std::vector<uint32_t>& words, const GridSize& size);

// The voxel buffer (§2.2): a 2D-array RGBA32UI texture, N_α x N_θ, one layer per 128 φ bits, and
// a framebuffer with every layer attached as its own colour target (OR-blended MRT).
class VoxelBuffer {
 public:
  explicit VoxelBuffer(const GridSize& size);
  const GridSize& size() const { return size_; }
  GLuint texture() const { return texture_.id(); }
  GLuint framebuffer() const { return fbo_.id(); }
  void clear() const;
  std::vector<uint32_t> read() const;
  void write(const std::vector<uint32_t>& words) const;

 private:
  GridSize size_;
  gl::Texture texture_;
  gl::Framebuffer fbo_;
};

// "Scan VSV": in-place prefix OR along α of every row and layer (compute; any N_α).
class Scan {
 public:
  Scan();
  void run(const VoxelBuffer& buffer) const;
  // Any RGBA32UI 2D-array texture of N_α x N_θ texels and `layers` layers (ivsv packs one grid
  // per virtual point light into the layers).
  void run(GLuint texture, int nAlpha, int nTheta, int layers) const;

 private:
  gl::Program program_;
};

}  // namespace epipolar

}  // namespace vs
