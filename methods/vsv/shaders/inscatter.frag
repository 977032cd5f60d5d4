#version 450 core
// "Compute L_s" (Eq. 5): a Riemann sum over φ along the pixel's eye ray, visibility from one
// 128-bit texel per layer of the scanned VSV. A point at light angle φ on the ray at eye angle α
// lies at s = D sin φ / sin(α + φ), and ds/dφ = D sin α / sin²(α + φ), which cancels the light's
// 1/r² (r = D sin α / sin(α + φ)), so uniform steps in φ suit the integrand. Each step's
// visibility is the lit fraction of the φ bins it covers; with a light texture a step spans
// `coarse` bins (coarse stepping), otherwise one. Directional lights: see parallelInscatter.
#include "common.glsl"
#include "epipolar.glsl"
layout(binding = 10) uniform usampler2DArray voxels;
layout(location = 0) uniform int binsPerStep;
layout(location = 0) out vec4 outInscatter;

const int MIN_STEPS = 8;

bool bitSet(uvec4 bits, int b) { return ((bits[(b >> 5) & 3] >> uint(b & 31)) & 1u) != 0u; }

// Directional light: along the ray φ is the distance from the axis, y = s sin α, linear in s,
// so the ray is stepped uniformly in s with steps no longer than `binsPerStep` φ bins. Parallel
// and anti-parallel rays (sin α = 0) stay in one bin: finite, nothing divides by sin α.
// L_in has no extinction along light rays, so each step's exp(-σt s) is integrated exactly.
vec3 parallelInscatter(vec3 dir, float dist, float alpha, int col, int row, float binWidth) {
  float sinAlpha = max(sin(alpha), 0.0);
  float yEnd = dist * sinAlpha;
  int steps = clamp(int(ceil(yEnd / (binWidth * float(max(binsPerStep, 1))))), MIN_STEPS, 4 * nPhi());
  float h = dist / float(steps);
  float stepAttenuation = exp(-sigmaT() * h);
  float stepWeight = sigmaT() * h > 1e-4 ? (1.0 - stepAttenuation) / sigmaT() : h;  // ∫ e^{-σt t} dt over a step
  int cachedLayer = -1;
  uvec4 bits = uvec4(0u);
  vec3 sum = vec3(0.0);
  float attenuation = 1.0;  // e^{-σt s} at the step's start
  for (int j = 0; j < steps; ++j, attenuation *= stepAttenuation) {
    float yLo = float(j) * h * sinAlpha, yHi = yLo + h * sinAlpha;
    float lit = 0.0;
    if (yHi - yLo <= 1e-6 * binWidth) {  // along the axis: a single bin
      int b = int(yLo / binWidth);
      lit = b >= nPhi() ? 1.0 : (bitSet(texelFetch(voxels, ivec3(col, row, b >> 7), 0), b) ? 0.0 : 1.0);
    } else {
      for (int b = int(yLo / binWidth); b <= int(yHi / binWidth); ++b) {
        float overlap = max(min(yHi, float(b + 1) * binWidth) - max(yLo, float(b) * binWidth), 0.0);
        if (b >= nPhi()) {  // beyond φ_max: nothing occludes
          lit += overlap;
          continue;
        }
        int layer = b >> 7;
        if (layer != cachedLayer) {
          bits = texelFetch(voxels, ivec3(col, row, layer), 0);
          cachedLayer = layer;
        }
        if (!bitSet(bits, b)) lit += overlap;
      }
      lit /= (yHi - yLo);
    }
    if (lit <= 0.0) continue;
    vec3 x = vsv.eyeAndDistance.xyz + dir * ((float(j) + 0.5) * h);
    sum += lit * attenuation * stepWeight * lightIncident(x);
  }
  return sum * sigmaS() * phase(dot(u.lightDir.xyz, -dir));
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = vsv.eyeAndDistance.xyz;
  float D = gridDistance();
  float aMax = alphaMax(), pMax = phiMax();
  float alpha = alphaOfPlane(planeCoords(dir));
  float phiEnd = phiOfPlane(planeCoords(dir * dist));
  int row = thetaRow(thetaOf(dir));
  int col = alphaColumn(alpha, aMax);
  if (col < 0) col = nAlpha() - 1;  // only by rounding at the very edge of the range
  if (parallelLight()) {
    vec3 result = parallelInscatter(dir, dist, alpha, col, row, pMax / float(nPhi()));
    outInscatter = vec4(all(lessThan(abs(result), vec3(3.0e38))) ? result : vec3(0.0), 1.0);
    return;
  }
  float binWidth = pMax / float(nPhi());
  int steps = clamp(int(ceil(phiEnd / (binWidth * float(max(binsPerStep, 1))))), MIN_STEPS, 4 * nPhi());
  float h = phiEnd / float(steps);
  float sinAlpha = sin(alpha);

  int cachedLayer = -1;
  uvec4 bits = uvec4(0u);
  vec3 sum = vec3(0.0);
  for (int j = 0; j < steps; ++j) {
    // Lit fraction of [j h, (j + 1) h] from the φ bins it overlaps.
    float lo = float(j) * h, hi = lo + h;
    int binLo = min(int(lo / binWidth), nPhi() - 1), binHi = min(int(hi / binWidth), nPhi() - 1);
    float lit = 0.0;
    for (int b = binLo; b <= binHi; ++b) {
      int layer = b >> 7;
      if (layer != cachedLayer) {
        bits = texelFetch(voxels, ivec3(col, row, layer), 0);
        cachedLayer = layer;
      }
      uint word = bits[(b >> 5) & 3];
      if (((word >> uint(b & 31)) & 1u) != 0u) continue;
      float overlap = min(hi, float(b + 1) * binWidth) - max(lo, float(b) * binWidth);
      lit += max(overlap, 0.0);
    }
    if (lit <= 0.0) continue;
    float phi = lo + 0.5 * h;
    float sinSum = max(sin(alpha + phi), 1e-12);
    float s = min(D * sin(phi) / sinSum, dist);
    float jacobian = D * sinAlpha / (sinSum * sinSum);
    vec3 x = eye + dir * s;
    float cosTheta = dot(lightTravelDir(x), -dir);
    sum += (lit / h) * exp(-sigmaT() * s) * phase(cosTheta) * lightIncident(x) * jacobian;
  }
  vec3 result = sum * sigmaS() * h;
  outInscatter = vec4(all(lessThan(abs(result), vec3(3.0e38))) ? result : vec3(0.0), 1.0);
}
