#version 450 core
// Mipmap Construction (Chen et al. 2011, §3.3): the 1D min-max mipmaps of all rectified rows, each
// row one row of `tree` (layout in tree.glsl). Rectification (rectify.comp) stores the leaves and
// the three levels above them; each pass here reads one level and builds up to three above it (four
// at the top), an invocation reducing a block of 16 nodes in registers and storing the 8 + 4 + 2
// nodes above them as sibling pairs, so a row of 1024 takes two passes here.
#include "tree.glsl"
layout(local_size_x = 64) in;
layout(rgba32f, binding = 3) uniform image2D tree;
layout(location = 0) uniform int inWidth;  // nodes on the level this pass reads (a power of two, >= 2)
layout(location = 2) uniform int slices;
const int kBlock = 16;

void main() {
  int block = min(inWidth, kBlock);
  int perSlice = inWidth / block;
  int id = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x);
  int slice = id / perSlice;
  if (slice >= slices) return;
  int base = (id - slice * perSlice) * block;
  vec2 node[kBlock];
  for (int i = 0; i < kBlock / 2; ++i) {
    if (2 * i >= block) break;
    vec4 pair = imageLoad(tree, ivec2(innerTexel(uint(inWidth + base + 2 * i)), slice));
    node[2 * i] = pair.xy;
    node[2 * i + 1] = pair.zw;
  }
  // Up the levels; the block's root is stored only when it is the row's (its sibling is another
  // invocation's: the next pass stores the pair).
  int width = inWidth;
  for (int count = block / 2; count >= 1; count /= 2) {
    width /= 2;
    base /= 2;
    for (int i = 0; i < kBlock / 2; ++i) {
      if (i >= count) break;
      node[i] = vec2(min(node[2 * i].x, node[2 * i + 1].x), max(node[2 * i].y, node[2 * i + 1].y));
    }
    if (count == 1 && width > 1) break;
    for (int i = 0; i < kBlock / 2; i += 2) {
      if (i >= count) break;
      imageStore(tree, ivec2(innerTexel(uint(width + base + i)), slice), vec4(node[i], node[count > 1 ? i + 1 : i]));
    }
  }
}
