// The epipolar frame of a VSV grid (Wyman 2011, §2.1), shared by vsv (one grid) and ivsv (one grid
// per virtual point light). Mirrors vs::epipolar::EpipolarBasis and toEpipolar in epipolar_grid.cpp.
// Axis from the eye towards the light; θ the angle of the epipolar half-plane around it (0 along
// e1); α the angle at the eye from the axis; φ the angle at the light from the light-to-eye
// direction, or, for a directional light (parallel), the distance from the axis.
struct EpipolarFrame {
  vec3 eye;
  float distance;  // |light - eye| > 0
  vec3 axis, e1, e2;
  bool parallel;
};

const float TWO_PI = 6.28318530717958647692;

// atan2 that is defined at the origin (§4.2: a vertex on the epipole).
float safeAtan(float y, float x) { return (abs(x) + abs(y) > 1e-30) ? atan(y, x) : 0.0; }

float frameTheta(EpipolarFrame f, vec3 offsetFromEye) {
  vec2 perp = vec2(dot(offsetFromEye, f.e1), dot(offsetFromEye, f.e2));
  float theta = safeAtan(perp.y, perp.x);
  return theta < 0.0 ? theta + TWO_PI : theta;
}
// (x along the axis, y >= 0 distance from it) in the point's own epipolar half-plane.
vec2 framePlane(EpipolarFrame f, vec3 offsetFromEye) {
  float x = dot(offsetFromEye, f.axis);
  vec2 perp = vec2(dot(offsetFromEye, f.e1), dot(offsetFromEye, f.e2));
  return vec2(x, length(perp));
}
float alphaOfPlane(vec2 p) { return safeAtan(p.y, p.x); }
float framePhi(EpipolarFrame f, vec2 p) { return f.parallel ? p.y : safeAtan(p.y, f.distance - p.x); }
// Unit vector from the eye towards θ in its half-plane, perpendicular to the axis.
vec3 frameHalfPlaneDir(EpipolarFrame f, float theta) { return cos(theta) * f.e1 + sin(theta) * f.e2; }
