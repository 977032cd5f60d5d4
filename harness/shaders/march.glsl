// Sample positions and weights of a camera-ray march over [0, dist] with N stratified samples
// u_i = (i + xi_i) / N; xi_i = fract(h + i * phi) with h a hash of (pixel, seed) when jittered,
// otherwise 0.5.
//  - uniform:     s_i = u_i dist, weight dist / N.
//  - equiangular: (point and spot lights) s_i spaced evenly in the angle seen from the light,
//    s = delta + D tan(theta), weight (theta_b - theta_a) r^2 / (D N): it cancels the 1/r^2 of
//    L_in, so rays passing close to the light converge as fast as the others.
// Needs common.glsl. The includer defines MARCH_EQUIANGULAR (0 or 1) at build time: a uniform
// would cost a branch per step, which llvmpipe does not hoist.
#ifndef MARCH_EQUIANGULAR
#error "define MARCH_EQUIANGULAR before including march.glsl"
#endif
#include "equiangular.glsl"
#define kMarchAngular (MARCH_EQUIANGULAR != 0 && lightType() != LIGHT_DIRECTIONAL)

struct March {
  float dist, pixelOffset;
  EquiangularSpan span;  // kMarchAngular only
  int n;
  bool jitter;
};

March beginMarch(ivec2 pixel, vec3 eye, vec3 dir, float dist, int steps, bool jitter) {
  March m;
  m.dist = dist;
  m.n = max(steps, 1);
  m.jitter = jitter;
  m.pixelOffset = jitter ? random01(uvec4(uint(pixel.x), uint(pixel.y), uint(u.viewport.w), 0u)) : 0.5;
  m.span = EquiangularSpan(0.0, 1.0, 0.0, 0.0);
  if (kMarchAngular) m.span = equiangularSpan(u.lightPos.xyz, eye, dir, dist);
  return m;
}

// Distance s along the ray of sample i and its quadrature weight.
void marchSample(March m, int i, out float s, out float weight) {
  const float goldenRatio = 0.61803398875;
  float ui = stratumPosition(i, m.n, m.pixelOffset, m.jitter, goldenRatio);
  if (kMarchAngular) {
    s = equiangularDistance(m.span, ui, m.dist);
    weight = equiangularWeight(m.span, s, m.n);
  } else {
    s = ui * m.dist;
    weight = m.dist / float(m.n);
  }
}

// The unshadowed integrand of sample (s, weight) at x = eye + s dir:
// weight sigma_s exp(-sigma_t s) rho(cos theta) L_in(x). Under equiangular sampling the weight's r^2
// cancels L_in's 1/r^2 and the two extinctions share one exp.
vec3 marchInscatter(March m, vec3 x, vec3 dir, float s, float weight) {
  if (kMarchAngular) {
    vec3 d = x - u.lightPos.xyz;
    float r = length(d);
    vec3 l = r > 1e-20 ? d / r : u.lightDir.xyz;
    return equiangularAngularWeight(m.span, m.n) * sigmaS() * exp(-sigmaT() * (s + r)) * phase(dot(l, -dir)) * lightEmitted(x, l);
  }
  return weight * sigmaS() * exp(-sigmaT() * s) * phase(dot(lightTravelDir(x), -dir)) * lightIncident(x);
}
