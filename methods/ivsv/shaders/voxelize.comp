#version 450 core
// Voxelize: one workgroup per (IVSV_ROWS theta rows, VPL). Each invocation is one phi bin: the light
// ray of (theta, phi) leaves the VPL, meets its nearest occluder in the ISM, and the occluder's alpha
// column gets the bin's bit; Scan then ORs along alpha, so everything behind it is in shadow.
// Several rows per workgroup: llvmpipe pays for every workgroup and barrier.
#include "common.glsl"
#include "ivsv.glsl"
layout(local_size_x = 128) in;
layout(binding = 10) uniform sampler2D ism;
layout(binding = 2, rgba32ui) uniform writeonly uimage2DArray grids;
shared uint rows[IVSV_ROWS * IVSV_GRID * 4];

void main() {
  const int G = IVSV_GRID;
  int firstRow = int(gl_WorkGroupID.x) * IVSV_ROWS, k = int(gl_WorkGroupID.y);
  int bin = int(gl_LocalInvocationID.x);
  for (int i = bin; i < IVSV_ROWS * G * 4; i += 128) rows[i] = 0u;
  barrier();
  EpipolarFrame f = vplFrame(k);
  float phi = (float(bin) + 0.5) / float(kPhiBits) * PI;
  float cosPhi = cos(phi), sinPhi = sin(phi);
  for (int r = 0; r < IVSV_ROWS; ++r) {
    int theta = firstRow + r;
    if (theta >= G) break;
    vec3 d = -cosPhi * f.axis + sinPhi * frameHalfPlaneDir(f, (float(theta) + 0.5) / float(G) * TWO_PI);
    if (dot(d, iv.normal.xyz) <= 0.0) continue;
    float stored = texelFetch(ism, ismTexel(k, paraboloid(d)), 0).r;
    if (stored <= 0.0) continue;
    // A texel keeps the nearest point of its footprint, nearer than the surface along the bin's ray
    // where the surface is seen at a grazing angle: push the occluder back by IVSV_BIAS texel angles.
    float texelAngle = 2.0 / float(iv.dims.w);
    vec3 occluder = vpls[k].position.xyz + stored * iv.normal.w * (1.0 + IVSV_BIAS * texelAngle) * d;
    float alpha = alphaOfPlane(framePlane(f, occluder - f.eye));
    int col = clamp(int(alpha / PI * float(G)), 0, G - 1);
    atomicOr(rows[(r * G + col) * 4 + bin / 32], 1u << uint(bin % 32));
  }
  barrier();
  for (int i = bin; i < IVSV_ROWS * G; i += 128) {
    int r = i / G, col = i % G;
    if (firstRow + r >= G) break;
    int at = i * 4;
    imageStore(grids, ivec3(col, firstRow + r, k), uvec4(rows[at], rows[at + 1], rows[at + 2], rows[at + 3]));
  }
}
