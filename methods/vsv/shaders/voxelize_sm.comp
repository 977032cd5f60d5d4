#version 450 core
// "Voxelize: From SM" fused with the scan (beyond the paper; `fused=1`): this voxelizer sets one
// bit per light ray, at the α column of its first occluder, and the scan ORs it into every larger
// α. So the scanned bit (α, θ, φ) is set exactly when the first occluder's column of light ray
// (θ, φ) is at most α, and one workgroup per θ row writes the scanned words directly: no points,
// logic op, clear or separate Scan VSV.
#include "common.glsl"
#include "epipolar.glsl"
#include "shadow_rays.glsl"
layout(local_size_x = 128) in;
layout(binding = 0, rgba32ui) uniform writeonly uimage2DArray voxels;

// The rows' unscanned bits, one uvec4 per (row, column, 128-bit layer), VSV_ROWS x N_α x N_φ / 32
// words in all (VSV_ROW_WORDS per row; the method picks VSV_ROWS, up to 8 rows, to fit the
// shared-memory limit): each light ray ORs its one bit in at its first occluder's column. As uvec4s,
// a clear or a scan step is one access where four words were four (llvmpipe pays per access and
// per active lane): 2.25 -> 1.95 ms at 128/256/128 on room, 25.6 -> 20.7 ms at 512/1024/512.
// Splitting one row's α walk over 8 invocations was slower; several rows per workgroup, each walked
// by its own invocations side by side, share the walk's steps: 3.4 -> 2.15 ms at 128/256/128 (8 rows).
shared uvec4 rowQuads[VSV_ROWS * VSV_ROW_WORDS / 4];

void main() {
  int firstRow = int(gl_WorkGroupID.x) * VSV_ROWS;
  int lid = int(gl_LocalInvocationID.x);
  int quadsPerRow = nAlpha() * VSV_LAYERS;  // one uvec4 per (column, layer)
  for (int i = lid; i < VSV_ROWS * quadsPerRow; i += 128) rowQuads[i] = uvec4(0u);
  barrier();
  // Light ray (row, bin) of this workgroup's rows; neighbouring invocations take neighbouring bins.
  const int kPhi = 128 * VSV_LAYERS;  // N_φ, a compile-time power of two
  for (int ray = lid; ray < VSV_ROWS * kPhi; ray += 128) {
    int r = ray / kPhi, bin = ray % kPhi;
    int col = firstRow + r < nTheta() ? occluderColumn(firstRow + r, bin) : -1;
    if (col >= 0) atomicOr(rowQuads[r * quadsPerRow + col * VSV_LAYERS + (bin >> 7)][(bin >> 5) & 3], 1u << uint(bin & 31));
  }
  barrier();
  // The scan: one invocation per (row, layer) walks α, ORing each column's bits into the running words.
  int r = lid / VSV_LAYERS, layer = lid - r * VSV_LAYERS;
  if (r < VSV_ROWS && firstRow + r < nTheta()) {
    uvec4 acc = uvec4(0u);
    for (int col = 0; col < nAlpha(); ++col) {
      acc |= rowQuads[r * quadsPerRow + col * VSV_LAYERS + layer];
      imageStore(voxels, ivec3(col, firstRow + r, layer), acc);
    }
  }
}
