// vsv: the epipolar transform and the scan against CPU implementations, leaks and spurious shadows
// in the hard triangle cases against raymarch, convergence with grid resolution, hard cases.
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstdio>
#include <random>

#include "gl_test.hpp"
#include "harness/metrics.hpp"
#include "vsv/vsv.hpp"

namespace vs::testing {
namespace {

class VsvTest : public GlTest {};

// ---- the scan

void checkScanMatchesCpu(const vsv::GridSize& size, uint32_t seed) {
  vsv::VoxelBuffer buffer(size);
  std::mt19937 rng(seed);
  std::vector<uint32_t> words(size_t(size.nAlpha) * size.nTheta * size.layers() * 4, 0u);
  // Sparse random bits, plus bits in the first and the last column of every row.
  for (auto& w : words) w = (rng() % 7 == 0) ? (1u << (rng() % 32)) : 0u;
  for (int layer = 0; layer < size.layers(); ++layer)
    for (int row = 0; row < size.nTheta; ++row) {
      size_t base = (size_t(layer) * size.nTheta + row) * size.nAlpha * 4;
      words[base + rng() % 4] |= 1u << (rng() % 32);
      words[base + (size.nAlpha - 1) * 4 + rng() % 4] |= 0x80000000u;
    }
  buffer.write(words);
  vsv::Scan scan;
  scan.run(buffer);
  std::vector<uint32_t> gpu = buffer.read();
  vsv::prefixOrRowsCpu(words, size);
  ASSERT_EQ(gpu.size(), words.size());
  size_t mismatches = 0;
  for (size_t i = 0; i < gpu.size(); ++i) mismatches += gpu[i] != words[i];
  EXPECT_EQ(mismatches, 0u) << "N_alpha " << size.nAlpha << " N_theta " << size.nTheta << " N_phi " << size.nPhi;
}

TEST_F(VsvTest, ScanMatchesCpuBitForBit) {
  checkScanMatchesCpu({37, 11, 128}, 1);   // N_alpha not a power of two
  checkScanMatchesCpu({64, 16, 256}, 2);   // two layers
  checkScanMatchesCpu({1, 5, 128}, 3);     // a single column
  checkScanMatchesCpu({129, 3, 384 / 128 * 128}, 4);
}

// ---- the epipolar transform

std::vector<glm::dvec3> randomPoints(const vsv::EpipolarBasis& b, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-6.0, 6.0);
  std::vector<glm::dvec3> points;
  for (int i = 0; i < count; ++i) points.push_back(b.eye + glm::dvec3(u(rng), u(rng), u(rng)));
  points.push_back(b.eye);                         // on the epipole (the eye itself)
  points.push_back(b.light);                       // the light
  points.push_back(b.eye + 2.0 * b.axis);          // on the axis between eye and light
  points.push_back(b.eye - 3.0 * b.axis);          // on the axis behind the eye
  points.push_back(b.eye + 3.0 * b.distance * b.axis);  // beyond the light
  return points;
}

struct ProbeResult {
  std::vector<glm::vec4> coords;
  std::vector<glm::ivec4> cells;
};

ProbeResult probe(const vsv::EpipolarBasis& basis, const vsv::GridSize& size, const std::vector<glm::dvec3>& points) {
  gl::Program program = gl::buildCompute("methods/vsv/shaders/probe.comp", "#define VSV_LAYERS 1\n");
  vsv::GridUniforms g = vsv::makeGridUniforms(basis, size, false);
  gl::Buffer ubo = gl::createBuffer(sizeof(g), &g);
  uint32_t rangesInit[2] = {0, 0};
  gl::Buffer ranges = gl::createBuffer(sizeof(rangesInit), rangesInit);
  std::vector<glm::vec4> in;
  for (auto& p : points) in.emplace_back(glm::vec3(p), 1.0f);
  gl::Buffer pointBuf = gl::createBuffer(in.size() * sizeof(glm::vec4), in.data());
  gl::Buffer coordBuf = gl::createBuffer(in.size() * sizeof(glm::vec4));
  gl::Buffer cellBuf = gl::createBuffer(in.size() * sizeof(glm::ivec4));
  glBindBufferBase(GL_UNIFORM_BUFFER, 1, ubo.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ranges.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, pointBuf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, coordBuf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, cellBuf.id());
  glUseProgram(program.id());
  glUniform1i(0, GLint(in.size()));
  glDispatchCompute(GLuint((in.size() + 63) / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  ProbeResult r;
  r.coords.resize(in.size());
  r.cells.resize(in.size());
  glGetNamedBufferSubData(coordBuf.id(), 0, r.coords.size() * sizeof(glm::vec4), r.coords.data());
  glGetNamedBufferSubData(cellBuf.id(), 0, r.cells.size() * sizeof(glm::ivec4), r.cells.data());
  return r;
}

// Distance (in cells) from the nearest cell boundary: cells are compared only away from them.
double boundaryDistance(double value, double range, int n) {
  double x = value / range * n;
  return std::fabs(x - std::round(x));
}

void checkTransform(const vsv::EpipolarBasis& basis, const char* what) {
  const vsv::GridSize size{37, 29, 128};
  std::vector<glm::dvec3> points = randomPoints(basis, 2000, 11);
  ProbeResult r = probe(basis, size, points);
  const double pi = glm::pi<double>();
  int compared = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    vsv::EpiCoords c = vsv::toEpipolar(basis, points[i]);
    for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(r.coords[i][k])) << what << " point " << i;
    bool onAxis = std::fabs(c.alpha) < 1e-6 || std::fabs(c.alpha - pi) < 1e-6;
    // θ is arbitrary on the axis (defined as 0 there); compare it only off the axis.
    double dTheta = std::fabs(r.coords[i].x - c.theta);
    if (!onAxis) {
      EXPECT_LT(std::min(dTheta, 2 * pi - dTheta), 1e-4) << what << " theta of point " << i;
    }
    EXPECT_NEAR(r.coords[i].y, c.alpha, 1e-4) << what << " alpha of point " << i;
    bool atLight = glm::length(points[i] - basis.light) < 1e-4 * basis.distance;  // φ undefined there
    if (!atLight) {
      EXPECT_NEAR(r.coords[i].z, c.phi, 1e-4) << what << " phi of point " << i;
    }
    const double margin = 1e-3;
    if (onAxis || atLight || boundaryDistance(c.theta, 2 * pi, size.nTheta) < margin ||
        boundaryDistance(c.alpha, pi, size.nAlpha) < margin || boundaryDistance(c.phi, pi, size.nPhi) < margin)
      continue;
    ++compared;
    EXPECT_EQ(r.cells[i].x, vsv::thetaRow(c.theta, size.nTheta)) << what << " row of point " << i;
    EXPECT_EQ(r.cells[i].y, vsv::alphaColumn(c.alpha, pi, size.nAlpha)) << what << " column of point " << i;
    EXPECT_EQ(r.cells[i].z, vsv::phiBin(c.phi, pi, size.nPhi)) << what << " bin of point " << i;
  }
  EXPECT_GT(compared, 1500) << what;
}

TEST_F(VsvTest, EpipolarTransformMatchesCpu) {
  checkTransform(vsv::makeBasis({0, 2, 8}, {0.5, 4, -1.5}, {0, 0, -1}, 1e-4), "general");
  checkTransform(vsv::makeBasis({1, 1, 1}, {1, 1, 1}, {0, 0, -1}, 1e-3), "light at the eye");
  checkTransform(vsv::makeBasis({0, 0, 0}, {1e-7, 0, 0}, {0, 0, -1}, 1e-3), "light near the eye");
  checkTransform(vsv::makeBasis({0, 0, 0}, {0, 50, 0}, {0, 0, -1}, 1e-3), "light along +y");
}

}  // namespace
}  // namespace vs::testing
