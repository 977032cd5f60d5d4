#version 450 core
// "Scan VSV": prefix OR along α of every (row, layer), in place. One invocation walks one row, so
// it is exact for any N_α (no power-of-two passes).
layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform coherent uimage2DArray voxels;
layout(location = 0) uniform ivec3 dims;  // N_α, N_θ, layers
void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= dims.y * dims.z) return;
  int row = id % dims.y, layer = id / dims.y;
  uvec4 acc = uvec4(0u);
  for (int col = 0; col < dims.x; ++col) {
    ivec3 at = ivec3(col, row, layer);
    uvec4 bits = imageLoad(voxels, at);
    uvec4 merged = acc | bits;
    if (merged != bits) imageStore(voxels, at, merged);
    acc = merged;
  }
}
