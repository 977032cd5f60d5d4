#version 450 core
// Voxelize: one workgroup per (theta row, VPL). Each invocation is one phi bin: the light ray of
// (theta, phi) leaves the VPL, meets its nearest occluder in the ISM, and the occluder's alpha
// column gets the bin's bit; Scan then ORs along alpha, so everything behind it is in shadow.
#include "common.glsl"
#include "ivsv.glsl"
layout(local_size_x = 128) in;
layout(binding = 10) uniform sampler2D ism;
layout(binding = 2, rgba32ui) uniform writeonly uimage2DArray grids;
shared uint row[IVSV_GRID * 4];

void main() {
  int theta = int(gl_WorkGroupID.x), k = int(gl_WorkGroupID.y);
  const int G = IVSV_GRID;
  int bin = int(gl_LocalInvocationID.x);
  for (int i = bin; i < G * 4; i += 128) row[i] = 0u;
  barrier();
  EpipolarFrame f = vplFrame(k);
  vec3 h = frameHalfPlaneDir(f, (float(theta) + 0.5) / float(G) * TWO_PI);
  float phi = (float(bin) + 0.5) / float(kPhiBits) * PI;
  vec3 d = -cos(phi) * f.axis + sin(phi) * h;
  if (dot(d, iv.normal.xyz) > 0.0) {
    float stored = texelFetch(ism, ismTexel(k, paraboloid(d)), 0).r;
    if (stored > 0.0) {
      vec3 occluder = vpls[k].position.xyz + stored * iv.normal.w * d;
      float alpha = alphaOfPlane(framePlane(f, occluder - f.eye));
      int col = clamp(int(alpha / PI * float(G)), 0, G - 1);
      atomicOr(row[col * 4 + bin / 32], 1u << uint(bin % 32));
    }
  }
  barrier();
  for (int col = bin; col < G; col += 128)
    imageStore(grids, ivec3(col, theta, k), uvec4(row[col * 4], row[col * 4 + 1], row[col * 4 + 2], row[col * 4 + 3]));
}
