#version 450 core
// "Compute L_s" (Eq. 5): a Riemann sum over φ along the pixel's eye ray, visibility from one
// 128-bit texel per layer of the scanned VSV. A point at light angle φ on the ray at eye angle α
// lies at s = D sin φ / sin(α + φ), and ds/dφ = D sin α / sin²(α + φ), which cancels the light's
// 1/r² (r = D sin α / sin(α + φ)), so the integrand is smooth in φ. Without a light texture it is
// taken as linear over groups of VSV_GROUP bins, evaluated at two Gauss points per group, and the
// lit bins of a group are counted with bitCount (their number and their first moment): two light
// evaluations per group instead of one per bin, and only for the groups the ray reaches. With a
// light texture each step spans `coarse` bins (coarse stepping) and reads its bins one by one.
// Directional lights: see parallelInscatter.
#include "common.glsl"
#include "epipolar.glsl"
#include "work_counters.glsl"
layout(binding = 10) uniform usampler2DArray voxels;
layout(location = 0) uniform int binsPerStep;
layout(location = 0) out vec4 outInscatter;

const int MIN_STEPS = 8;
// Work counters: φ bins the pixel's integral visits, light evaluations, voxel-texel fetches.
uint workBins = 0u, workEvals = 0u, workFetches = 0u;

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
      ++workBins;
      ++workFetches;
      lit = b >= nPhi() ? 1.0 : (bitSet(texelFetch(voxels, ivec3(col, row, b >> 7), 0), b) ? 0.0 : 1.0);
    } else {
      for (int b = int(yLo / binWidth); b <= int(yHi / binWidth); ++b) {
        ++workBins;
        float overlap = max(min(yHi, float(b + 1) * binWidth) - max(yLo, float(b) * binWidth), 0.0);
        if (b >= nPhi()) {  // beyond φ_max: nothing occludes
          lit += overlap;
          continue;
        }
        int layer = b >> 7;
        if (layer != cachedLayer) {
          bits = texelFetch(voxels, ivec3(col, row, layer), 0);
          cachedLayer = layer;
          ++workFetches;
        }
        if (!bitSet(bits, b)) lit += overlap;
      }
      lit /= (yHi - yLo);
    }
    if (lit <= 0.0) continue;
    ++workEvals;
    vec3 x = vsv.eyeAndDistance.xyz + dir * ((float(j) + 0.5) * h);
    sum += lit * attenuation * stepWeight * lightIncident(x);
  }
  return sum * sigmaS() * phase(dot(u.lightDir.xyz, -dir));
}

// ---- Untextured lights: groups of VSV_GROUP bins (8, 16, 32, 64 or 128; the method's `group`).
#ifndef VSV_GROUP
#define VSV_GROUP 16
#endif
// Bit k of a bin's index within its 32-bit word, as masks over the word's bits: the first moment of
// the lit bins of a word is sum_k 2^k bitCount(lit & kIndexBit[k]).
const uint kIndexBit[5] = uint[5](0xAAAAAAAAu, 0xCCCCCCCCu, 0xF0F0F0F0u, 0xFF00FF00u, 0xFFFF0000u);
#define kGroupLog2 (VSV_GROUP >= 32 ? 5 : (VSV_GROUP == 16 ? 4 : 3))
#define kWordsPerGroup (VSV_GROUP >= 32 ? VSV_GROUP / 32 : 1)

// Point and spot lights: the integrand per unit φ (σs left out). ds/dφ = r² / (D sin α) with r
// the distance from the grid's light, taken from the point itself so that it stays consistent
// where s is clipped to the ray's end. sin(α + φ) by the angle sum from (cos α, sin α), and one
// exp for both extinctions, to the eye and from the light: 7.7 → 7.2 ms Compute L_s on room at
// 128/256/128.
vec3 pointIntegrand(float phi, vec3 eye, vec3 dir, float dist, vec2 alphaCosSin, float D, float DsinAlpha) {
  float sinPhi = sin(phi);
  float sinSum = max(alphaCosSin.y * cos(phi) + alphaCosSin.x * sinPhi, 1e-12);
  float s = min(D * sinPhi / sinSum, dist);
  vec3 x = eye + dir * s;
  vec3 toGrid = x - vsv.gridLight.xyz;
  vec3 fromLight = x - u.lightPos.xyz;
  float r2 = max(dot(fromLight, fromLight), 1e-24);
  float invR = inversesqrt(r2);
  vec3 l = fromLight * invR;  // lightTravelDir(x)
  float jacobianOverR2 = dot(toGrid, toGrid) / (max(DsinAlpha, 1e-30) * r2);
  return exp(-sigmaT() * (s + r2 * invR)) * phase(dot(l, -dir)) * lightEmitted(x, l) * jacobianOverR2;
}

#define kGroupsPerLayer (128 / VSV_GROUP)
// The lit bins among word w of group g of a layer's texel (bin `first` of the whole range is the
// group's first), among the first `fullBins` bins; bit j is the group's bin 32 w + j.
uint litBits(uvec4 bits, int g, int w, int first, int fullBins) {
  const int kWordBits = min(VSV_GROUP, 32);
  int inWord = clamp(fullBins - first - 32 * w, 0, kWordBits);
  int bit = VSV_GROUP * g + 32 * w;
  return ~bitfieldExtract(bits[bit >> 5], bit & 31, kWordBits) & bitfieldExtract(0xFFFFFFFFu, 0, inWord);
}
// A group's lit bins: their count n0 and first moment n1 (sum of their indices in the group).
void litMoments(uvec4 bits, int g, int first, int fullBins, out float n0, out float n1) {
  n0 = 0.0;
  n1 = 0.0;
  for (int w = 0; w < kWordsPerGroup; ++w) {
    uint lit = litBits(bits, g, w, first, fullBins);
    float count = float(bitCount(lit));
    n0 += count;
    n1 += 32.0 * float(w) * count;
    for (int b = 0; b < kGroupLog2; ++b) n1 += float(bitCount(lit & kIndexBit[b]) << b);
  }
}

// Point and spot lights: ∫_0^rayEnd integrand × V dφ over the bins of column (col, row). Over each
// group the integrand is taken as linear through its values at the group's two Gauss points
// (never at φ = 0, where the light may sit at the eye, nor at the ray's clipped end); a group's
// lit bins enter through their count n0 and first moment n1. The rest of the ray after its full
// bins takes one evaluation: the part of the bin its end cuts, or, for a ray that ends past φ_max
// (pMax), the last bin and beyond, where the last bin's visibility holds as in the per-bin sum.
vec3 pointInscatter(vec3 eye, vec3 dir, float dist, vec2 alphaCosSin, int col, int row, float binWidth, float rayEnd,
                    float pMax) {
  const float kGauss = 0.28867513459;  // 1 / (2 sqrt 3)
  float D = gridDistance();
  float DsinAlpha = D * alphaCosSin.y;
  float phiEnd = min(rayEnd, pMax);
  float binsCovered = min(phiEnd / binWidth, float(nPhi()));
  int fullBins = int(binsCovered);
  vec3 sum = vec3(0.0);
  // Only the groups the ray reaches: a loop bound is the one place llvmpipe skips work (it runs
  // a loop while any pixel of the batch needs it), and on any GPU this is work the ray never uses.
  int groups = min((fullBins + VSV_GROUP - 1) / VSV_GROUP, nPhi() / VSV_GROUP);
  int layers = (groups * VSV_GROUP + 127) >> 7;
  workBins += uint(fullBins);
  workFetches += uint(layers);
  workEvals += uint(2 * groups);
  for (int layer = 0; layer < layers; ++layer) {
    uvec4 bits = texelFetch(voxels, ivec3(col, row, layer), 0);
    int groupsHere = min(groups - layer * kGroupsPerLayer, kGroupsPerLayer);
    for (int g = 0; g < groupsHere; ++g) {
      int first = 128 * layer + VSV_GROUP * g;
      float n0, n1;
      litMoments(bits, g, first, fullBins, n0, n1);
      float phiA = float(first) * binWidth;
      float phiB = min(float(first + VSV_GROUP) * binWidth, phiEnd);
      float mid = 0.5 * (phiA + phiB), offset = max(phiB - phiA, 0.0) * kGauss;
      vec3 g1 = pointIntegrand(mid - offset, eye, dir, dist, alphaCosSin, D, DsinAlpha);
      vec3 g2 = pointIntegrand(mid + offset, eye, dir, dist, alphaCosSin, D, DsinAlpha);
      vec3 slope = (g2 - g1) / max(2.0 * offset, 1e-30);
      // Sum over lit bins j of g(φ_A + (j + 1/2) w) w with g linear through the two points (the
      // line can dip below 0 at a group's end where g is steep; g itself cannot).
      sum += max(binWidth * (n0 * 0.5 * (g1 + g2) + slope * (binWidth * (n1 + 0.5 * n0) - n0 * (mid - phiA))), vec3(0.0));
    }
  }
  // One fetch and one evaluation for the rest: llvmpipe would pay for two blocks under a branch
  // each, though a ray never both ends inside a bin and runs past φ_max.
  float restStart = float(fullBins) * binWidth;
  float restLength = max(rayEnd - restStart, 0.0);
  if (restLength > 0.0) {
    int bin = min(fullBins, nPhi() - 1);
    uvec4 bits = texelFetch(voxels, ivec3(col, row, bin >> 7), 0);
    bool shadowed = ((bits[(bin >> 5) & 3] >> uint(bin & 31)) & 1u) != 0u;
    ++workBins;
    ++workFetches;
    ++workEvals;
    if (!shadowed) sum += restLength * pointIntegrand(restStart + 0.5 * restLength, eye, dir, dist, alphaCosSin, D, DsinAlpha);
  }
  return sum;
}

// Directional light without a texture: L_in is constant and φ = s sin α, so each lit bin adds
// ∫ e^{-σt s} ds over its span of the ray exactly, and so does each run of lit bins. Returns
// ∫_0^dist e^{-σt s} V ds; beyond φ_max the ray is lit.
float parallelTransmittanceIntegral(float dist, float sinAlpha, int col, int row, float binWidth, float pMax) {
  float yEnd = dist * sinAlpha;
  float sigma = sigmaT();
  // Of the ray, per bin. A ray along the axis (sin α -> 0) stays within the first bin, whose
  // length then exceeds the ray: no division by 0, and no block of its own for llvmpipe to pay.
  float binLength = min(binWidth / max(sinAlpha, 1e-30), 1e30);
  int fullBins = min(int(min(yEnd, pMax) / binWidth), nPhi());
  float sum = 0.0;
  int layers = min((fullBins + 127) >> 7, vsv.grid.w);
  workBins += uint(fullBins);
  workFetches += uint(layers);
  // Each run of lit bins [a, b) adds ∫ e^{-σt s} ds = F(b binLength) - F(a binLength) with
  // F(s) = ∫_0^s e^{-σt t} dt, so only the edges of the runs cost anything: one F per edge, found
  // with findLSB across the words (a ray lit all along costs one at its start and one at its end,
  // where a walk over every bit cost 32 per word: terrain, 128/256/128, 1.8 of 5.9 ms).
  #define RUN_INTEGRAL(s) (sigma * (s) > 1e-2 ? (1.0 - exp(-sigma * (s))) / sigma : (s) * (1.0 - sigma * (s) * (0.5 - sigma * (s) * (1.0 / 6.0 - sigma * (s) / 24.0))))
  uint carry = 0u;  // the bin before the word's first is lit
  for (int layer = 0; layer < layers; ++layer) {
    uvec4 bits = texelFetch(voxels, ivec3(col, row, layer), 0);
    for (int w = 0; w < 4; ++w) {
      int first = 128 * layer + 32 * w;
      uint lit = ~bits[w] & bitfieldExtract(0xFFFFFFFFu, 0, clamp(fullBins - first, 0, 32));
      uint edges = lit ^ ((lit << 1u) | carry);  // bins where a run starts or ends
      carry = lit >> 31u;
      while (edges != 0u) {
        int k = findLSB(edges);
        edges &= edges - 1u;
        float f = RUN_INTEGRAL(float(first + k) * binLength);
        sum += ((lit >> uint(k)) & 1u) != 0u ? -f : f;
      }
    }
  }
  // The rest of the ray after its full bins, one fetch: up to φ_max with the visibility of the bin
  // it reaches (the bin its end cuts, or the one φ_max cuts when the range is not a whole number of
  // bins), then lit beyond φ_max. Lit, it continues an open run; so a run ends at the ray's end.
  float sCut = float(fullBins) * binLength;
  float sMax = pMax / max(sinAlpha, 1e-30);
  int bin = min(fullBins, nPhi() - 1);
  uvec4 bits = texelFetch(voxels, ivec3(col, row, bin >> 7), 0);
  ++workFetches;
  bool shadowed = fullBins < nPhi() && ((bits[(bin >> 5) & 3] >> uint(bin & 31)) & 1u) != 0u;
  float tailStart = shadowed ? min(dist, sMax) : sCut;
  float runOpenUpTo = carry != 0u ? sCut : 0.0;  // F(0) = 0
  sum += RUN_INTEGRAL(runOpenUpTo) + RUN_INTEGRAL(dist) - RUN_INTEGRAL(tailStart);
  #undef RUN_INTEGRAL
  return max(sum, 0.0);
}

// The pixel's L_s (non-finite values become 0) and its work counters.
void finish(ivec2 pixel, vec3 result) {
  outInscatter = vec4(all(lessThan(abs(result), vec3(3.0e38))) ? result : vec3(0.0), 1.0);
  countWork(pixel, 0, 1u);
  countWork(pixel, 1, workBins);
  countWork(pixel, 2, workEvals);
  countWork(pixel, 3, workFetches);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 dir;
  float dist;
  cameraRay(pixel, dir, dist);
  vec3 eye = vsv.eyeAndDistance.xyz;
  float D = gridDistance();
  float aMax = alphaMax(), pMax = phiMax();
  vec2 dirPlane = planeCoords(dir);  // (cos α, sin α >= 0): dir is a unit vector
  float alpha = alphaOfPlane(dirPlane);
  float phiEnd = phiOfPlane(planeCoords(dir * dist));
  int row = thetaRow(thetaOf(dir));
  int col = alphaColumn(alpha, aMax);
  if (col < 0) col = nAlpha() - 1;  // only by rounding at the very edge of the range
#if !VS_LIGHT_TEXTURE
  {
    float binWidth = pMax / float(nPhi());
    vec3 result;
    if (parallelLight()) {
      result = parallelTransmittanceIntegral(dist, dirPlane.y, col, row, binWidth, pMax) * lightIncident(eye) * sigmaS() *
               phase(dot(u.lightDir.xyz, -dir));
      ++workEvals;
    } else {
      result = pointInscatter(eye, dir, dist, dirPlane, col, row, binWidth, phiEnd, pMax) * sigmaS();
    }
    finish(pixel, result);
    return;
  }
#endif
  if (parallelLight()) {
    vec3 result = parallelInscatter(dir, dist, alpha, col, row, pMax / float(nPhi()));
    finish(pixel, result);
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
      ++workBins;
      int layer = b >> 7;
      if (layer != cachedLayer) {
        bits = texelFetch(voxels, ivec3(col, row, layer), 0);
        cachedLayer = layer;
        ++workFetches;
      }
      uint word = bits[(b >> 5) & 3];
      if (((word >> uint(b & 31)) & 1u) != 0u) continue;
      float overlap = min(hi, float(b + 1) * binWidth) - max(lo, float(b) * binWidth);
      lit += max(overlap, 0.0);
    }
    if (lit <= 0.0) continue;
    ++workEvals;
    float phi = lo + 0.5 * h;
    float sinSum = max(sin(alpha + phi), 1e-12);
    float s = min(D * sin(phi) / sinSum, dist);
    float jacobian = D * sinAlpha / (sinSum * sinSum);
    vec3 x = eye + dir * s;
    float cosTheta = dot(lightTravelDir(x), -dir);
    sum += (lit / h) * exp(-sigmaT() * s) * phase(cosTheta) * lightIncident(x) * jacobian;
  }
  finish(pixel, sum * sigmaS() * h);
}
