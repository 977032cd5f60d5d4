// Epipolar space of the VSV grid (Wyman 2011, §2.1) and the voxel-buffer layout (§2.2).
// Mirrors vs::epipolar::GridUniforms and the CPU functions in methods/epipolar/epipolar_grid.cpp.
#include "methods/epipolar/shaders/epipolar_frame.glsl"
// Directional light: the axis points towards the light at infinity, light rays are the lines
// parallel to it, and the third coordinate ("φ") is the distance from the axis instead of an angle.
layout(std140, binding = 3) uniform VsvBlock {
  vec4 eyeAndDistance;  // xyz eye; w = distance to the grid light (> 0)
  vec4 gridLight;       // xyz light on the axis at that distance
  vec4 axis;            // unit, eye towards light
  vec4 e1;              // axis, e1, e2 orthonormal; θ = 0 along e1
  vec4 e2;
  ivec4 grid;           // N_α, N_θ, N_φ, layers of 128 φ bits
  vec4 fixedRanges;     // α_max, φ_max without dynamic ranges (π, or the scene's largest
                        // distance from the axis for a directional light); z = 1 when dynamic
                        // (§4.3); w = 1 for a directional light
} vsv;

// Dynamic angular ranges (§4.3), reduced over the G-buffer as float bits by ranges.comp into a
// storage buffer, which the passes after it read through a uniform-block copy: the same value for
// every invocation, loaded once rather than per lane (Compute L_s 7.6 -> 6.9 ms on room).
#ifdef VSV_RANGES_WRITABLE
layout(std430, binding = 0) buffer VsvRanges {
  uint alphaMaxBits;
  uint phiMaxBits;
} vsvRanges;
#else
layout(std140, binding = 5) uniform VsvRangesBlock {
  uint alphaMaxBits;
  uint phiMaxBits;
} vsvRanges;
#endif

int nAlpha() { return vsv.grid.x; }
int nTheta() { return vsv.grid.y; }
int nPhi() { return vsv.grid.z; }
float gridDistance() { return vsv.eyeAndDistance.w; }

float alphaMax() {
  if (vsv.fixedRanges.z < 0.5) return vsv.fixedRanges.x;
  return clamp(uintBitsToFloat(vsvRanges.alphaMaxBits), 1e-4, PI);
}
// From lightType(): a constant in programs built with sceneDefines, so that llvmpipe, which runs
// both sides of a branch on a uniform, does not pay for the other kind of light's integral.
bool parallelLight() { return lightType() == LIGHT_DIRECTIONAL; }
// Directional light: φ is a distance, so the dynamic range is bounded by the scene's largest
// distance from the axis (the fixed range: beyond it nothing is shadowed), not by π.
float phiMax() {
  if (vsv.fixedRanges.z < 0.5) return vsv.fixedRanges.y;
  float dynamicMax = uintBitsToFloat(vsvRanges.phiMaxBits);
  if (parallelLight()) return min(dynamicMax, vsv.fixedRanges.y);
  return clamp(dynamicMax, 1e-4, PI);
}

EpipolarFrame vsvFrame() {
  return EpipolarFrame(vsv.eyeAndDistance.xyz, vsv.eyeAndDistance.w, vsv.axis.xyz, vsv.e1.xyz, vsv.e2.xyz,
                       parallelLight());
}
float thetaOf(vec3 offsetFromEye) { return frameTheta(vsvFrame(), offsetFromEye); }
vec2 planeCoords(vec3 offsetFromEye) { return framePlane(vsvFrame(), offsetFromEye); }
float phiOfPlane(vec2 p) { return framePhi(vsvFrame(), p); }
vec3 epipolarCoords(vec3 world) {  // (θ, α, φ)
  vec3 offset = world - vsv.eyeAndDistance.xyz;
  vec2 p = planeCoords(offset);
  return vec3(thetaOf(offset), alphaOfPlane(p), phiOfPlane(p));
}

int thetaRow(float theta) { return clamp(int(theta / TWO_PI * float(nTheta())), 0, nTheta() - 1); }
// -1 at or beyond the range: nothing there is seen.
int alphaColumn(float alpha, float aMax) {
  if (!(alpha < aMax)) return -1;
  return clamp(int(alpha / aMax * float(nAlpha())), 0, nAlpha() - 1);
}
int phiBin(float phi, float pMax) {
  if (!(phi < pMax)) return -1;
  return clamp(int(phi / pMax * float(nPhi())), 0, nPhi() - 1);
}

// Unit vector from the eye towards θ in its half-plane, perpendicular to the axis.
vec3 halfPlaneDir(float theta) { return frameHalfPlaneDir(vsvFrame(), theta); }

// Bits lo..hi (inclusive, bin numbers) that fall into 32-bit word `word` of the whole φ range.
uint wordMask(int lo, int hi, int word) {
  int a = max(lo - 32 * word, 0), b = min(hi - 32 * word, 31);
  if (a > b) return 0u;
  uint upper = b == 31 ? 0xffffffffu : ((1u << uint(b + 1)) - 1u);
  return upper & ~((1u << uint(a)) - 1u);
}
uvec4 layerMask(int lo, int hi, int layer) {
  int w = 4 * layer;
  return uvec4(wordMask(lo, hi, w), wordMask(lo, hi, w + 1), wordMask(lo, hi, w + 2), wordMask(lo, hi, w + 3));
}
