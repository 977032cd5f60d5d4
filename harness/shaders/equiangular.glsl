// Equiangular sampling of a camera ray [0, dist] around a point (a point or spot light, a virtual
// point light): samples spaced evenly in the angle seen from the point, s = delta + D tan(theta),
// each weighted (theta_b - theta_a) r^2 / (D N). The weight cancels the point's 1/r^2, so rays
// passing close to it converge as fast as the others. Shared by the harness's march (march.glsl)
// and the methods that march around a light of their own (dsm's haze, ivsv's gather).
#ifndef EQUIANGULAR_GLSL
#define EQUIANGULAR_GLSL

struct EquiangularSpan {
  float delta;           // ray parameter closest to the point
  float D;               // the point's distance from the ray (> 0)
  float thetaA, thetaB;  // angles of the ray's ends seen from the point
};

EquiangularSpan equiangularSpan(vec3 point, vec3 eye, vec3 dir, float dist) {
  EquiangularSpan e;
  vec3 toPoint = point - eye;
  e.delta = dot(toPoint, dir);
  e.D = max(length(toPoint - e.delta * dir), 1e-6 * max(dist, 1.0));
  e.thetaA = atan(-e.delta, e.D);
  e.thetaB = atan(dist - e.delta, e.D);
  return e;
}

// Stratum position of sample i of n: (i + xi) / n, xi = fract(offset + i step) when jittered
// (a per-pixel offset and a low-discrepancy step), else 0.5.
float stratumPosition(int i, int n, float offset, bool jitter, float step) {
  return (float(i) + (jitter ? fract(offset + float(i) * step) : 0.5)) / float(n);
}

// The distance along the ray at stratum position u in [0, 1].
float equiangularDistance(EquiangularSpan e, float u, float dist) {
  return clamp(e.delta + e.D * tan(mix(e.thetaA, e.thetaB, u)), 0.0, dist);
}

// (theta_b - theta_a) / (D N): the weight of one of n samples once r^2 has cancelled 1/r^2.
float equiangularAngularWeight(EquiangularSpan e, int n) { return (e.thetaB - e.thetaA) / (e.D * float(n)); }

// The quadrature weight of one of n samples at distance s: the angular weight times r^2.
float equiangularWeight(EquiangularSpan e, float s, int n) {
  return equiangularAngularWeight(e, n) * (e.D * e.D + (s - e.delta) * (s - e.delta));
}

#endif
