#version 450 core
// Final Gather: along the camera ray, per VPL, L_in times the visibility read from that VPL's
// scanned grid, at steps spaced equiangularly around the VPL (harness/shaders/equiangular.glsl, as
// raymarch's march does around a point light), so rays passing close to a VPL converge as fast as
// the others. The ray lies in one epipolar half-plane of each VPL at one alpha, so its four
// (alpha, theta) columns and their bilinear weights are fixed along the ray; each step only reads
// the phi bit. One pass covers VPLs [first, first + count), added into L_s (loop budget).
#include "common.glsl"
#include "ivsv.glsl"
#include "equiangular.glsl"
layout(binding = 11) uniform usampler2DArray grids;
layout(location = 0) out vec4 outInscatter;

float bitAt(uvec4 w, int bin) { return float((w[bin >> 5] >> uint(bin & 31)) & 1u); }

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 hit = texelFetch(gPosition, pixel, 0);
  vec3 eye = u.eye.xyz;
  vec3 toHit = hit.xyz - eye;
  float dist = length(toHit);
  vec3 dir = dist > 1e-20 ? toHit / dist : u.cameraForward.xyz;
  const int G = IVSV_GRID;
  const float goldenRatio = 0.61803398875;
  bool jitter = iv.weight.w > 0.5;
  float pixelOffset = jitter ? random01(uvec4(uint(pixel.x), uint(pixel.y), uint(u.viewport.w), 0u)) : 0.5;
  int n = max(iv.counts.y, 1);
  vec3 sum = vec3(0.0);
  for (int kk = 0; kk < iv.counts.w; ++kk) {
    int k = iv.counts.z + kk;
    EpipolarFrame f = vplFrame(k);
    vec2 plane = framePlane(f, dir);  // of the unit direction; a point at s has s * plane
    float a = alphaOfPlane(plane) / PI * float(G), t = frameTheta(f, dir) / TWO_PI * float(G);
    uvec4 w00, w10, w01, w11;
    float wa = 0.0, wt = 0.0;
#if IVSV_INTERPOLATE
    a -= 0.5;
    t -= 0.5;
    int a0 = int(floor(a)), t0 = int(floor(t));
    wa = a - float(a0);
    wt = t - float(t0);
    int a1 = clamp(a0 + 1, 0, G - 1), t1 = (t0 + 1 + G) % G;  // theta wraps around the axis
    a0 = clamp(a0, 0, G - 1);
    t0 = (t0 + G) % G;
    w00 = texelFetch(grids, ivec3(a0, t0, k), 0);
    w10 = texelFetch(grids, ivec3(a1, t0, k), 0);
    w01 = texelFetch(grids, ivec3(a0, t1, k), 0);
    w11 = texelFetch(grids, ivec3(a1, t1, k), 0);
#else
    w00 = texelFetch(grids, ivec3(clamp(int(a), 0, G - 1), clamp(int(t), 0, G - 1), k), 0);
    w10 = w01 = w11 = w00;
#endif
    vec3 light = vpls[k].position.xyz;
    EquiangularSpan span = equiangularSpan(light, eye, dir, dist);
    for (int i = 0; i < n; ++i) {
      float s = equiangularDistance(span, stratumPosition(i, n, pixelOffset, jitter, goldenRatio), dist);
      float weight = equiangularWeight(span, s, n);  // cancels the 1/r^2 below
      vec3 x = eye + dir * s;
      vec3 d = x - light;
      float r2 = max(dot(d, d), 1e-12);
      float r = sqrt(r2);
      vec3 l = d / r;
      float emission = max(dot(l, iv.normal.xyz), 0.0);
      float phi = safeAtan(plane.y * s, f.distance - plane.x * s);
      int bin = clamp(int(phi / PI * float(kPhiBits)), 0, kPhiBits - 1);
      float shadow = mix(mix(bitAt(w00, bin), bitAt(w10, bin), wa), mix(bitAt(w01, bin), bitAt(w11, bin), wa), wt);
      sum += (1.0 - shadow) * emission * weight * exp(-sigmaT() * (s + r)) / r2 * phase(dot(l, -dir));
    }
  }
  vec3 result = sum * iv.weight.rgb * sigmaS();
  if (any(isnan(result)) || any(isinf(result))) result = vec3(0.0);
  outInscatter = vec4(result, 1.0);
}
