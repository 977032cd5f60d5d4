#version 450 core
// Shadow Map Rectification (Chen et al. 2011, §3.2): texel (j, k) of the rectified map is the light
// ray gamma_j of slice k; it stores the beta of the camera ray through the point where that light ray
// is blocked (kUnoccluded when it never is). A camera ray with parameter beta is lit over texel j
// iff beta < S[j, k].
// The rectified rows are written straight into the leaves of the min-max tree (tree.glsl): an
// invocation rectifies a block of kBlock texels of one slice, so the slice's frame and the light
// rays' clip coordinates are set up once per block, and reduces the block to the three levels above
// it in registers, which Mipmap Construction continues from.
#include "common.glsl"
#include "epipolar.glsl"
#include "tree.glsl"
layout(local_size_x = 64) in;
layout(rgba32f, binding = 3) uniform writeonly image2D tree;
#if VS_LIGHT_TYPE == 0
layout(binding = VS_UNIT_SHADOW_DEPTH_CUBE) uniform samplerCube shadowDepthCube;
#else
layout(binding = VS_UNIT_SHADOW_DEPTH_2D) uniform sampler2D shadowDepth2D;
#endif
const int kBlock = 16;  // kRectifyBlock in minmax.cpp
// VS_LIGHT_TYPE (harness/frame.cpp): 0 point (cube map), 1 spot, 2 directional (LIGHT_* in common.glsl).

#if VS_LIGHT_TYPE != 0
// The shadow map's depth at clip-space position `clip` (a nearest texel), unprojected to the world
// point it stores; false where the map has no occluder or the position is outside it.
bool occluder2D(vec4 clip, out vec3 hit) {
  if (clip.w <= 1e-20) return false;
  vec2 st = clip.xy / clip.w * 0.5 + 0.5;
  if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0)))) return false;
  ivec2 size = textureSize(shadowDepth2D, 0);
  ivec2 texel = clamp(ivec2(floor(st * vec2(size))), ivec2(0), size - 1);  // GL_NEAREST, clamp to edge
  float depth = texelFetch(shadowDepth2D, texel, 0).r;
  if (depth >= 1.0) return false;
  vec4 world = ep.invLightViewProj * vec4(st * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
  if (abs(world.w) <= 1e-20) return false;
  hit = world.xyz / world.w;
  return true;
}
#endif

// The block's state: which texel comes next and, for point and spot lights, (cos, sin) of its gamma.
struct Block {
  int slice, i;
  vec3 a, n;
  float gamma0, step;
  vec2 cs, rotation;
#if VS_LIGHT_TYPE == 2
  vec4 clipEye, clipN;
#elif VS_LIGHT_TYPE == 1
  vec4 clipLight, clipA, clipN;
#endif
};

// S of the block's next texel: the beta at which its light ray is blocked (kUnoccluded if never).
float nextTexel(inout Block b) {
  float result = kUnoccluded;
#if VS_LIGHT_TYPE == 2
  // Directional: the light ray through eye + gamma n, blocked at height h along the axis: lit iff
  // beta < atan(gamma, h). Its clip position is linear in gamma.
  float gamma = b.gamma0 + float(b.i) * b.step;
  vec3 hit;
  if (occluder2D(b.clipEye + gamma * b.clipN, hit)) result = atan(gamma, dot(hit - u.eye.xyz, b.a));
#else
  // Point and spot: the light ray w(gamma) = -cos(gamma) a + sin(gamma) n from the light.
  float rOcc = -1.0;
#if VS_LIGHT_TYPE == 0
  vec3 w = -b.cs.x * b.a + b.cs.y * b.n;
  float depth = textureLod(shadowDepthCube, w, 0.0).r;
  if (depth < 1.0) {
    float nearZ = u.shadowParams.x, farZ = u.shadowParams.y;
    float zNdc = depth * 2.0 - 1.0;
    float major = 2.0 * farZ * nearZ / max((farZ + nearZ) - zNdc * (farZ - nearZ), 1e-20);
    rOcc = major / max(max(abs(w.x), abs(w.y)), max(abs(w.z), 1e-6));
  }
#else
  vec3 hit;
  if (occluder2D(b.clipLight - b.cs.x * b.clipA + b.cs.y * b.clipN, hit)) rOcc = length(hit - u.lightPos.xyz);
#endif
  // Seen from the eye, the point at distance rOcc along the light ray has beta = atan(r sin g, D - r cos g).
  if (rOcc >= 0.0) result = atan(rOcc * b.cs.y, ep.axis.w - rOcc * b.cs.x);
  // (cos, sin) of the next gamma by rotation (16 steps from an exact start: a few ulps).
  b.cs = vec2(b.cs.x * b.rotation.x - b.cs.y * b.rotation.y, b.cs.y * b.rotation.x + b.cs.x * b.rotation.y);
#endif
  ++b.i;
  return result == result ? result : kUnoccluded;  // never store NaN
}

vec4 nextFour(inout Block b) {
  vec4 s;
  s.x = nextTexel(b);
  s.y = nextTexel(b);
  s.z = nextTexel(b);
  s.w = nextTexel(b);
  return s;
}

// The parents of two sibling pairs (min, max, min, max), themselves a sibling pair.
vec4 parents(vec4 left, vec4 right) {
  return vec4(min(left.x, left.z), max(left.y, left.w), min(right.x, right.z), max(right.y, right.w));
}

void main() {
  int d = int(ep.gammaInfo.z);
  int perSlice = d / kBlock;
  int id = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x);
  Block b;
  b.slice = id / perSlice;
  if (b.slice >= ep.counts.x) return;
  int first = (id - b.slice * perSlice) * kBlock;
  b.i = 0;
  b.a = ep.axis.xyz;
  b.n = sliceNormal(sliceAlpha(b.slice));
  b.step = ep.gammaInfo.x / float(d);
  b.gamma0 = (float(first) + 0.5) * b.step;
  b.cs = vec2(cos(b.gamma0), sin(b.gamma0));
  b.rotation = vec2(cos(b.step), sin(b.step));
#if VS_LIGHT_TYPE == 2
  b.clipEye = u.lightViewProj * vec4(u.eye.xyz, 1.0);
  b.clipN = u.lightViewProj * vec4(b.n, 0.0);
#elif VS_LIGHT_TYPE == 1
  b.clipLight = u.lightViewProj * vec4(u.lightPos.xyz, 1.0);
  b.clipA = u.lightViewProj * vec4(b.a, 0.0);
  b.clipN = u.lightViewProj * vec4(b.n, 0.0);
#endif
  // Written out, not looped: llvmpipe keeps an indexed local array in memory, per lane.
  vec4 q0 = nextFour(b), q1 = nextFour(b), q2 = nextFour(b), q3 = nextFour(b);
  ivec2 leaves = ivec2(leafTexel(d, uint(first)), b.slice);
  imageStore(tree, leaves, q0);
  imageStore(tree, leaves + ivec2(1, 0), q1);
  imageStore(tree, leaves + ivec2(2, 0), q2);
  imageStore(tree, leaves + ivec2(3, 0), q3);
  // The three levels above the leaves as sibling pairs: 4 + 2 + 1 texels. The block's own root has
  // its sibling in the next block (Mipmap Construction stores the pair) unless it is the row's root.
  vec4 p0 = parents(q0.xxyy, q0.zzww), p1 = parents(q1.xxyy, q1.zzww);
  vec4 p2 = parents(q2.xxyy, q2.zzww), p3 = parents(q3.xxyy, q3.zzww);
  ivec2 level = ivec2(innerTexel(uint(d / 2 + first / 2)), b.slice);
  imageStore(tree, level, p0);
  imageStore(tree, level + ivec2(1, 0), p1);
  imageStore(tree, level + ivec2(2, 0), p2);
  imageStore(tree, level + ivec2(3, 0), p3);
  vec4 r0 = parents(p0, p1), r1 = parents(p2, p3);
  level = ivec2(innerTexel(uint(d / 4 + first / 4)), b.slice);
  imageStore(tree, level, r0);
  imageStore(tree, level + ivec2(1, 0), r1);
  vec4 s = parents(r0, r1);
  imageStore(tree, ivec2(innerTexel(uint(d / 8 + first / 8)), b.slice), s);
  if (d == kBlock) imageStore(tree, ivec2(0, b.slice), parents(s, s));  // the row's root (zw)
}
