#include "epipolar_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vs {
namespace epipolar {

static constexpr double kPi = 3.14159265358979323846;

static double safeAtan2(double y, double x) { return std::fabs(x) + std::fabs(y) > 1e-300 ? std::atan2(y, x) : 0.0; }

EpipolarBasis makeBasis(glm::dvec3 eye, glm::dvec3 light, glm::dvec3 fallbackAxis, double minDistance) {
  EpipolarBasis b;
  b.eye = eye;
  glm::dvec3 toLight = light - eye;
  double len = glm::length(toLight);
  if (len > 1e-12 && std::isfinite(len)) {
    b.axis = toLight / len;
  } else {
    double f = glm::length(fallbackAxis);
    b.axis = f > 1e-12 ? fallbackAxis / f : glm::dvec3(0, 0, -1);
  }
  // Light at or near the eye (§4.2): keep the grid's light a small distance along the axis.
  b.distance = std::max(std::isfinite(len) ? len : 0.0, std::max(minDistance, 1e-9));
  b.light = eye + b.axis * b.distance;
  glm::dvec3 helper = std::fabs(b.axis.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  b.e1 = glm::normalize(glm::cross(b.axis, helper));
  b.e2 = glm::cross(b.axis, b.e1);
  return b;
}

EpipolarBasis makeDirectionalBasis(glm::dvec3 eye, glm::dvec3 travelDir, double phiRange) {
  double len = glm::length(travelDir);
  glm::dvec3 toLight = len > 1e-12 && std::isfinite(len) ? -travelDir / len : glm::dvec3(0, 1, 0);
  // Any point on the axis will do as the "light": only the axis is used.
  EpipolarBasis b = makeBasis(eye, eye + toLight, toLight, 1.0);
  b.directional = true;
  b.phiRange = std::isfinite(phiRange) ? std::max(phiRange, 1e-6) : 1.0;
  return b;
}

double sceneAxisDistance(glm::dvec3 eye, glm::dvec3 axis, glm::dvec3 lo, glm::dvec3 hi) {
  double largest = 0.0;  // the distance from a line is convex: its maximum over a box is at a corner
  for (int i = 0; i < 8; ++i) {
    glm::dvec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    glm::dvec3 d = c - eye;
    largest = std::max(largest, glm::length(d - axis * glm::dot(d, axis)));
  }
  return largest;
}

EpiCoords toEpipolar(const EpipolarBasis& b, glm::dvec3 point) {
  glm::dvec3 offset = point - b.eye;
  double x = glm::dot(offset, b.axis);
  double p1 = glm::dot(offset, b.e1), p2 = glm::dot(offset, b.e2);
  double y = std::sqrt(p1 * p1 + p2 * p2);
  EpiCoords c;
  c.theta = safeAtan2(p2, p1);
  if (c.theta < 0) c.theta += 2.0 * kPi;
  c.alpha = safeAtan2(y, x);
  c.phi = b.directional ? y : safeAtan2(y, b.distance - x);
  return c;
}

int thetaRow(double theta, int nTheta) { return std::clamp(int(theta / (2.0 * kPi) * nTheta), 0, nTheta - 1); }
int alphaColumn(double alpha, double alphaMax, int nAlpha) {
  if (!(alpha < alphaMax)) return -1;
  return std::clamp(int(alpha / alphaMax * nAlpha), 0, nAlpha - 1);
}
int phiBin(double phi, double phiMax, int nPhi) {
  if (!(phi < phiMax)) return -1;
  return std::clamp(int(phi / phiMax * nPhi), 0, nPhi - 1);
}

GridUniforms makeGridUniforms(const EpipolarBasis& b, const GridSize& size, bool dynamicRanges) {
  GridUniforms g{};
  g.eye = glm::vec4(glm::vec3(b.eye), float(b.distance));
  g.light = glm::vec4(glm::vec3(b.light), 1.0f);
  g.axis = glm::vec4(glm::vec3(b.axis), 0.0f);
  g.e1 = glm::vec4(glm::vec3(b.e1), 0.0f);
  g.e2 = glm::vec4(glm::vec3(b.e2), 0.0f);
  g.grid = glm::ivec4(size.nAlpha, size.nTheta, size.nPhi, size.layers());
  g.ranges = glm::vec4(float(kPi), float(b.phiRange), dynamicRanges ? 1.0f : 0.0f, b.directional ? 1.0f : 0.0f);
  return g;
}

void prefixOrRowsCpu(std::vector<uint32_t>& words, const GridSize& size) {
  const size_t texel = 4, row = texel * size_t(size.nAlpha);
  for (int layer = 0; layer < size.layers(); ++layer) {
    for (int r = 0; r < size.nTheta; ++r) {
      uint32_t* base = &words[(size_t(layer) * size.nTheta + r) * row];
      for (int col = 1; col < size.nAlpha; ++col)
        for (size_t c = 0; c < texel; ++c) base[col * texel + c] |= base[(col - 1) * texel + c];
    }
  }
}

VoxelBuffer::VoxelBuffer(const GridSize& size) : size_(size) {
  if (size.nPhi % 128 != 0 || size.layers() < 1 || size.layers() > 8)
    throw std::invalid_argument("vsv: N_phi must be 128, 256, ..., 1024 (128 bits per texel, at most 8 targets)");
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
  texture_ = gl::Texture(id);
  glTextureStorage3D(id, 1, GL_RGBA32UI, size.nAlpha, size.nTheta, size.layers());
  // Integer textures are incomplete (texelFetch returns 0) unless both filters are NEAREST.
  gl::setFilter(id, GL_NEAREST, GL_NEAREST);
  glCreateFramebuffers(1, &id);
  fbo_ = gl::Framebuffer(id);
  std::vector<GLenum> drawBuffers;
  for (int layer = 0; layer < size.layers(); ++layer) {
    glNamedFramebufferTextureLayer(id, GL_COLOR_ATTACHMENT0 + layer, texture_.id(), 0, layer);
    drawBuffers.push_back(GL_COLOR_ATTACHMENT0 + layer);
  }
  glNamedFramebufferDrawBuffers(id, GLsizei(drawBuffers.size()), drawBuffers.data());
  gl::checkFramebuffer(id, "vsv voxel buffer");
}

void VoxelBuffer::clear() const {
  const GLuint zero[4] = {0, 0, 0, 0};
  glClearTexImage(texture_.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, zero);
}

std::vector<uint32_t> VoxelBuffer::read() const {
  std::vector<uint32_t> words(size_t(size_.nAlpha) * size_.nTheta * size_.layers() * 4);
  glFinish();
  glGetTextureImage(texture_.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(words.size() * 4), words.data());
  return words;
}

void VoxelBuffer::write(const std::vector<uint32_t>& words) const {
  glTextureSubImage3D(texture_.id(), 0, 0, 0, 0, size_.nAlpha, size_.nTheta, size_.layers(), GL_RGBA_INTEGER,
                      GL_UNSIGNED_INT, words.data());
}

Scan::Scan() { program_ = gl::buildCompute("methods/epipolar/shaders/scan.comp"); }

void Scan::run(const VoxelBuffer& buffer) const {
  const GridSize& s = buffer.size();
  run(buffer.texture(), s.nAlpha, s.nTheta, s.layers());
}

void Scan::run(GLuint texture, int nAlpha, int nTheta, int layers) const {
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  glUseProgram(program_.id());
  glUniform3i(0, nAlpha, nTheta, layers);
  glBindImageTexture(0, texture, 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32UI);
  GLuint invocations = GLuint(nTheta * layers);
  glDispatchCompute((invocations + 63) / 64, 1, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

}  // namespace epipolar

}  // namespace vs
