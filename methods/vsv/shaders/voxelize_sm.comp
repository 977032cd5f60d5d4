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

// The row's unscanned bits, one uvec4 per (column, 128-bit layer), N_α x N_φ / 32 words in all
// (VSV_ROW_WORDS, sized by the method to fit the shared-memory limit): each light ray ORs its one
// bit in at its first occluder's column. As uvec4s, a clear or a scan step is one access where four
// words were four (llvmpipe pays per access and per active lane): 2.25 -> 1.95 ms at 128/256/128
// on room, 25.6 -> 20.7 ms at 512/1024/512. Splitting the α walk over 8 invocations was slower.
shared uvec4 rowQuads[VSV_ROW_WORDS / 4];

void main() {
  int row = int(gl_WorkGroupID.x);
  int lid = int(gl_LocalInvocationID.x);
  int quads = nAlpha() * VSV_LAYERS;  // one uvec4 per (column, layer)
  for (int i = lid; i < quads; i += 128) rowQuads[i] = uvec4(0u);
  barrier();
  for (int bin = lid; bin < nPhi(); bin += 128) {
    int col = occluderColumn(row, bin);
    if (col >= 0) atomicOr(rowQuads[col * VSV_LAYERS + (bin >> 7)][(bin >> 5) & 3], 1u << uint(bin & 31));
  }
  barrier();
  // The scan: one invocation per layer walks α, ORing each column's bits into the running words.
  if (lid < VSV_LAYERS) {
    uvec4 acc = uvec4(0u);
    for (int col = 0; col < nAlpha(); ++col) {
      acc |= rowQuads[col * VSV_LAYERS + lid];
      imageStore(voxels, ivec3(col, row, lid), acc);
    }
  }
}
