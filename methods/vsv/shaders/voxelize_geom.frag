#version 450 core
// Conservative coverage (§4.1.2): clip the triangle to this texel's wedge (θ0..θ1, α0..α1) and set
// every φ bit the clipped piece spans. The α cones are replaced by planes through the wedge's
// middle half-plane (second order in Δθ).
#include "common.glsl"
#include "epipolar.glsl"
flat in vec3 gP0, gP1, gP2;
layout(location = 0) out uvec4 outBits[VSV_LAYERS];
const int MAX_VERTICES = 8;

// Keeps the part of the polygon with dot(p, n) >= 0 (a half-space through the eye).
void clipPolygon(inout vec3 poly[MAX_VERTICES], inout int count, vec3 n) {
  vec3 kept[MAX_VERTICES];
  int keptCount = 0;
  for (int i = 0; i < count; ++i) {
    vec3 a = poly[i], b = poly[(i + 1) % count];
    float da = dot(a, n), db = dot(b, n);
    if (da >= 0.0 && keptCount < MAX_VERTICES) kept[keptCount++] = a;
    if ((da >= 0.0) != (db >= 0.0) && keptCount < MAX_VERTICES) kept[keptCount++] = mix(a, b, da / (da - db));
  }
  poly = kept;
  count = keptCount;
}

void main() {
  int col = int(gl_FragCoord.x), row = int(gl_FragCoord.y);
  float aMax = alphaMax(), pMax = phiMax();
  float theta0 = float(row) / float(nTheta()) * TWO_PI, theta1 = float(row + 1) / float(nTheta()) * TWO_PI;
  float alpha0 = float(col) / float(nAlpha()) * aMax, alpha1 = float(col + 1) / float(nAlpha()) * aMax;
  vec3 axis = vsv.axis.xyz, e1 = vsv.e1.xyz, e2 = vsv.e2.xyz;
  vec3 mid = halfPlaneDir(0.5 * (theta0 + theta1));
  vec3 poly[MAX_VERTICES];
  poly[0] = gP0;
  poly[1] = gP1;
  poly[2] = gP2;
  int count = 3;
  clipPolygon(poly, count, -sin(theta0) * e1 + cos(theta0) * e2);   // θ >= θ0
  clipPolygon(poly, count, sin(theta1) * e1 - cos(theta1) * e2);    // θ <= θ1
  clipPolygon(poly, count, cos(alpha0) * mid - sin(alpha0) * axis);  // α >= α0
  clipPolygon(poly, count, sin(alpha1) * axis - cos(alpha1) * mid);  // α <= α1
  if (count == 0) discard;
  float phiLo = 3.0e38, phiHi = 0.0;  // φ is a distance, not an angle, under a directional light
  for (int i = 0; i < count; ++i) {
    float phi = phiOfPlane(planeCoords(poly[i]));
    phiLo = min(phiLo, phi);
    phiHi = max(phiHi, phi);
  }
  if (phiLo >= pMax) discard;
  int binLo = phiBin(phiLo, pMax);
  int binHi = phiHi >= pMax ? nPhi() - 1 : phiBin(phiHi, pMax);
  for (int layer = 0; layer < VSV_LAYERS; ++layer) outBits[layer] = layerMask(binLo, binHi, layer);
}
