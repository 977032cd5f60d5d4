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

// The row's unscanned bits, N_α x N_φ / 32 words (VSV_ROW_WORDS, sized by the method to fit the
// shared-memory limit): each light ray ORs its one bit in at its first occluder's column.
shared uint rowBits[VSV_ROW_WORDS];

void main() {
  int row = int(gl_WorkGroupID.x);
  int lid = int(gl_LocalInvocationID.x);
  int words = nPhi() / 32;
  for (int i = lid; i < nAlpha() * words; i += 128) rowBits[i] = 0u;
  barrier();
  for (int bin = lid; bin < nPhi(); bin += 128) {
    int col = occluderColumn(row, bin);
    if (col >= 0) atomicOr(rowBits[col * words + (bin >> 5)], 1u << uint(bin & 31));
  }
  barrier();
  // The scan: one invocation per layer walks α, ORing each column's bits into the running words.
  if (lid < VSV_LAYERS) {
    uvec4 acc = uvec4(0u);
    for (int col = 0; col < nAlpha(); ++col) {
      int at = col * words + 4 * lid;
      acc |= uvec4(rowBits[at], rowBits[at + 1], rowBits[at + 2], rowBits[at + 3]);
      imageStore(voxels, ivec3(col, row, lid), acc);
    }
  }
}
