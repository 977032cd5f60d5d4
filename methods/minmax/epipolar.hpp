// CPU side of the min-max method: epipolar coordinates of the frame and the low-rank
// approximation of the smooth part of the scattering integrand (Chen et al. 2011, §3.1-3.3).
//
// Coordinates. The axis a points from the eye towards the light (directional: against the light's
// travel direction). A camera ray v = cos(beta) a + sin(beta) n(alpha) lies in the epipolar slice
// alpha, n(alpha) = cos(alpha) n0 + sin(alpha) n1. Inside a slice a light ray is named by gamma:
//  - point/spot: the angle at the light between the light-to-eye direction and the light ray;
//  - directional: the light ray's distance from the axis line through the eye.
// With D = |light - eye| (1 for directional), L_s of a ray becomes an integral over gamma:
//   point/spot:  L_s = I / (D sin beta) * Int V T(alpha, gamma) I'(beta, gamma) dgamma,
//                I' = sigma_s rho(cos(beta + gamma)) exp(-sigma_t D (sin gamma + sin beta) / sin(beta + gamma))
//   directional: L_s = E / sin(beta) * Int V T(alpha, gamma) I'(beta, gamma) dgamma,
//                I' = sigma_s rho(cos beta) exp(-sigma_t gamma / sin beta)
// I' is slice-independent and smooth; I' ~ sum_i B_i(beta) Gamma_i(gamma) by a truncated SVD.
#pragma once
#include <glm/glm.hpp>

#include <vector>

namespace vs::minmax {

struct MediumParams {
  bool directional = false;
  double sigmaS = 0, sigmaT = 0;
  bool hg = false;
  double g = 0;
};

double phaseFunction(const MediumParams& m, double cosTheta);
// I'(beta, gamma) above; 0 where the camera ray never reaches gamma.
double smoothIntegrand(const MediumParams& m, double eyeLightDistance, double beta, double gamma);

struct ViewInput {
  glm::dmat4 viewProj{1.0}, invViewProj{1.0};
  glm::dvec3 eye{0.0}, forward{0, 0, -1};
  double farZ = 100.0;
  int width = 1, height = 1;
  bool directional = false;
  glm::dvec3 lightPos{0.0}, lightTravelDir{0, -1, 0};
  glm::dvec3 boundsLo{-1.0}, boundsHi{1.0};  // scene geometry
  double epipoleRadius = 0.0;  // pixels around the epipole that the Near Epipole pass ray-marches
};

struct EpipolarFrame {
  bool directional = false;
  bool degenerate = false;  // light at the eye: every pixel is "near the epipole"
  glm::dvec3 axis{0, 0, 1}, n0{1, 0, 0}, n1{0, 1, 0};
  double eyeLightDistance = 1.0;  // D
  double alphaLo = -3.14159265358979, alphaRange = 6.28318530717959;
  bool fullCircle = true;   // the epipole (or its antipode) is on screen
  int autoSlices = 64;      // keeps every pixel within half a pixel of its slice
  double betaLo = 0, betaHi = 3.14159265358979;
  double gammaAll = 1;      // largest gamma any camera ray reaches
  double gammaMap = 1;      // rectified rows cover [0, gammaMap] (directional: beyond it nothing occludes)
  bool epipoleValid = false;
  glm::dvec2 epipolePixel{0.0};  // GL window coordinates (origin bottom left)
};

EpipolarFrame computeEpipolarFrame(const ViewInput& in);
// Camera ray through the centre of GL pixel (x, y) (origin bottom left).
glm::dvec3 pixelRay(const ViewInput& in, double x, double y);

// Grid of the SVD: beta is denser near the ends (Chebyshev spacing), gamma denser near 0
// (quadratic), where the integrand changes fastest.
constexpr int kGrid = 64;
double betaAtGrid(const EpipolarFrame& f, double t);   // t in [0, 1]
double gammaAtGrid(const EpipolarFrame& f, double t);  // t in [0, 1]

struct LowRank {
  int rank = 0;
  std::vector<float> basisBeta;    // rank x kGrid: sigma_i * U_i at the beta grid
  std::vector<float> basisGamma;   // rank x kGrid: V_i at the gamma grid
  std::vector<float> prefix;       // rank x (prefixRes + 1): Int_0^gamma Gamma_i, gamma = m / prefixRes * gammaAll
  int prefixRes = 0;
  double energy = 1.0;             // sum of the kept sigma^2 over the total
};
LowRank lowRankApproximation(const EpipolarFrame& f, const MediumParams& m, int rank, int prefixRes);
// Gamma_i and B_i interpolated like the shaders do (for tests).
double evalBasisGamma(const EpipolarFrame& f, const LowRank& lr, int i, double gamma);
double evalBasisBeta(const EpipolarFrame& f, const LowRank& lr, int i, double beta);

}  // namespace vs::minmax
