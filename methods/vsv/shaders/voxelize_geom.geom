#version 450 core
// Epipolar bounds of one triangle (§4.1.1): a box of (α, θ) texels that holds every voxel it
// touches. A triangle wrapping the θ = 0 seam becomes two boxes; one covering the epipole (the
// axis pierces it, or a vertex lies on it) spans every θ and reaches α = 0 or π. The fragment
// shader then finds the exact φ span inside each texel (conservative coverage, §4.1.2).
#include "common.glsl"
#include "epipolar.glsl"
layout(triangles) in;
layout(triangle_strip, max_vertices = 8) out;
in vec3 vWorld[];
flat out vec3 gP0, gP1, gP2;  // vertices as offsets from the eye

float angleBetween(vec3 a, vec3 b) { return safeAtan(length(cross(a, b)), dot(a, b)); }

// Smallest and largest angle from unit c along the great-circle arc from unit u0 to unit u1
// (the extremes may lie inside the arc, not only at its ends).
vec2 arcAngleRange(vec3 u0, vec3 u1, vec3 c) {
  float a0 = angleBetween(u0, c), a1 = angleBetween(u1, c);
  vec2 r = vec2(min(a0, a1), max(a0, a1));
  vec3 n = cross(u0, u1);
  float nl = length(n);
  if (nl < 1e-7) return r;
  n /= nl;
  vec3 q = c - n * dot(c, n);
  float ql = length(q);
  if (ql < 1e-7) return r;  // c is the arc's pole: constant angle
  q /= ql;
  if (dot(cross(u0, q), n) >= 0.0 && dot(cross(q, u1), n) >= 0.0) r.x = min(r.x, angleBetween(q, c));
  if (dot(cross(u0, -q), n) >= 0.0 && dot(cross(-q, u1), n) >= 0.0) r.y = max(r.y, angleBetween(-q, c));
  return r;
}

void emitBox(int colLo, int colHi, int rowLo, int rowHi) {
  vec2 lo = vec2(colLo, rowLo) / vec2(nAlpha(), nTheta()) * 2.0 - 1.0;
  vec2 hi = vec2(colHi + 1, rowHi + 1) / vec2(nAlpha(), nTheta()) * 2.0 - 1.0;
  vec2 corners[4] = vec2[4](lo, vec2(hi.x, lo.y), vec2(lo.x, hi.y), hi);
  for (int i = 0; i < 4; ++i) {
    gP0 = vWorld[0] - vsv.eyeAndDistance.xyz;
    gP1 = vWorld[1] - vsv.eyeAndDistance.xyz;
    gP2 = vWorld[2] - vsv.eyeAndDistance.xyz;
    gl_Position = vec4(corners[i], 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}

void main() {
  vec3 p[3];
  vec2 q[3];  // projection onto the plane perpendicular to the axis
  float scale = 0.0;
  bool touchesEye = false;
  for (int i = 0; i < 3; ++i) {
    p[i] = vWorld[i] - vsv.eyeAndDistance.xyz;
    q[i] = vec2(dot(p[i], vsv.e1.xyz), dot(p[i], vsv.e2.xyz));
    scale = max(scale, dot(p[i], p[i]));
    touchesEye = touchesEye || dot(p[i], p[i]) < 1e-12;
  }
  if (any(isnan(vec3(scale))) || isinf(scale)) return;
  vec3 axis = vsv.axis.xyz;
  float aMax = alphaMax();
  float alphaLo = PI, alphaHi = 0.0;
  bool allTheta = touchesEye;
  if (!touchesEye) {
    for (int i = 0; i < 3; ++i) {
      vec2 r = arcAngleRange(normalize(p[i]), normalize(p[(i + 1) % 3]), axis);
      alphaLo = min(alphaLo, r.x);
      alphaHi = max(alphaHi, r.y);
    }
    // Does the axis line pierce the triangle (origin inside the projected triangle)?
    float tol = 1e-6 * scale;
    float s0 = q[0].x * q[1].y - q[0].y * q[1].x;
    float s1 = q[1].x * q[2].y - q[1].y * q[2].x;
    float s2 = q[2].x * q[0].y - q[2].y * q[0].x;
    bool inside = (s0 >= -tol && s1 >= -tol && s2 >= -tol) || (s0 <= tol && s1 <= tol && s2 <= tol);
    if (inside) {
      allTheta = true;
      vec3 n = cross(p[1] - p[0], p[2] - p[0]);
      float along = dot(n, axis);
      if (abs(along) > 1e-6 * length(n)) {
        bool ahead = dot(n, p[0]) / along >= 0.0;
        alphaLo = ahead ? 0.0 : alphaLo;
        alphaHi = ahead ? alphaHi : PI;
      } else {
        alphaLo = 0.0;
        alphaHi = PI;
      }
    }
  } else {
    alphaLo = 0.0;
    alphaHi = PI;
  }
  const float eps = 1e-5;
  if (alphaLo - eps >= aMax) return;
  int colLo = clamp(int(floor((alphaLo - eps) / aMax * float(nAlpha()))), 0, nAlpha() - 1);
  int colHi = clamp(int(floor((alphaHi + eps) / aMax * float(nAlpha()))), 0, nAlpha() - 1);
  if (allTheta) {
    emitBox(colLo, colHi, 0, nTheta() - 1);
    return;
  }
  // θ span below π: unwrap the vertices around the first one.
  float t0 = thetaOf(p[0]);
  float thetaLo = t0, thetaHi = t0;
  for (int i = 1; i < 3; ++i) {
    float d = thetaOf(p[i]) - t0;
    d -= TWO_PI * floor((d + PI) / TWO_PI);
    thetaLo = min(thetaLo, t0 + d);
    thetaHi = max(thetaHi, t0 + d);
  }
  int rowLo = int(floor((thetaLo - eps) / TWO_PI * float(nTheta())));
  int rowHi = int(floor((thetaHi + eps) / TWO_PI * float(nTheta())));
  if (rowHi - rowLo >= nTheta() - 1) {
    emitBox(colLo, colHi, 0, nTheta() - 1);
  } else if (rowLo < 0) {  // wraps the θ = 0 seam: split
    emitBox(colLo, colHi, rowLo + nTheta(), nTheta() - 1);
    emitBox(colLo, colHi, 0, rowHi);
  } else if (rowHi >= nTheta()) {
    emitBox(colLo, colHi, rowLo, nTheta() - 1);
    emitBox(colLo, colHi, 0, rowHi - nTheta());
  } else {
    emitBox(colLo, colHi, rowLo, rowHi);
  }
}
