#version 450 core
// Shadow Map Rectification (Chen et al. 2011, §3.2): texel (j, k) of the rectified map is the light
// ray gamma_j of slice k; it stores the beta of the camera ray through the point where that light ray
// is blocked (kUnoccluded when it never is). A camera ray with parameter beta is lit over texel j
// iff beta < S[j, k].
#include "common.glsl"
#include "epipolar.glsl"
layout(local_size_x = 64, local_size_y = 1) in;
layout(r32f, binding = 0) uniform writeonly image2D rectified;
#if VS_LIGHT_TYPE == 0
layout(binding = 9) uniform samplerCube shadowDepthCube;
#else
layout(binding = 8) uniform sampler2D shadowDepth2D;
#endif

// Occluder on the light ray through `origin` along `dir` from a 2D shadow map; false if none.
bool occluder2D(vec3 origin, out vec3 hit) {
#if VS_LIGHT_TYPE != 0
  vec4 clip = u.lightViewProj * vec4(origin, 1.0);
  if (clip.w <= 1e-20) return false;
  vec2 st = clip.xy / clip.w * 0.5 + 0.5;
  if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0)))) return false;
  float depth = textureLod(shadowDepth2D, st, 0.0).r;
  if (depth >= 1.0) return false;
  vec4 world = ep.invLightViewProj * vec4(st * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
  if (abs(world.w) <= 1e-20) return false;
  hit = world.xyz / world.w;
  return true;
#else
  hit = origin;
  return false;
#endif
}

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  int d = int(ep.gammaInfo.z);
  if (texel.x >= d || texel.y >= ep.counts.x) return;
  vec3 a = ep.axis.xyz;
  vec3 n = sliceNormal(sliceAlpha(texel.y));
  float gamma = (float(texel.x) + 0.5) / float(d) * ep.gammaInfo.x;
  float result = kUnoccluded;
  if (isDirectional()) {
    // Light ray through eye + gamma n; blocked at height h along the axis: lit iff beta < atan(gamma, h).
    vec3 hit;
    if (occluder2D(u.eye.xyz + gamma * n, hit)) result = atan(gamma, dot(hit - u.eye.xyz, a));
  } else {
    vec3 w = -cos(gamma) * a + sin(gamma) * n;  // light ray direction from the light
    float rOcc = -1.0;
#if VS_LIGHT_TYPE == 0
    float depth = textureLod(shadowDepthCube, w, 0.0).r;
    if (depth < 1.0) {
      float nearZ = u.shadowParams.x, farZ = u.shadowParams.y;
      float zNdc = depth * 2.0 - 1.0;
      float major = 2.0 * farZ * nearZ / max((farZ + nearZ) - zNdc * (farZ - nearZ), 1e-20);
      rOcc = major / max(max(abs(w.x), abs(w.y)), max(abs(w.z), 1e-6));
    }
#else
    vec3 hit;
    if (occluder2D(u.lightPos.xyz + w, hit)) rOcc = length(hit - u.lightPos.xyz);
#endif
    // Seen from the eye, the point at distance rOcc along the light ray has beta = atan(r sin g, D - r cos g).
    if (rOcc >= 0.0) result = atan(rOcc * sin(gamma), ep.axis.w - rOcc * cos(gamma));
  }
  if (!(result == result)) result = kUnoccluded;  // never store NaN
  imageStore(rectified, texel, vec4(result));
}
