#version 450 core
// Mipmap Construction (Chen et al. 2011, §3.3): the 1D min-max mipmaps of all rectified rows, each
// row one row of `tree` in Ahnentafel order (node k at x = k: root 1, children 2k and 2k+1, leaves
// d..2d-1). One pass builds up to four levels: an invocation reduces a block of 16 nodes of the
// level it reads (the rectified map in the first pass, which also stores the leaves) in registers
// and stores the 8 + 4 + 2 + 1 nodes above them, so a row of 1024 takes three passes, not ten.
layout(local_size_x = 64) in;
layout(binding = 10) uniform sampler2D rectified;  // first pass only
layout(rg32f, binding = 3) uniform image2D tree;
layout(location = 0) uniform int inWidth;  // nodes on the level this pass reads (a power of two)
layout(location = 1) uniform int firstPass;
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
  for (int i = 0; i < kBlock; ++i) {
    if (i >= block) break;
    if (firstPass != 0) {
      float s = texelFetch(rectified, ivec2(base + i, slice), 0).r;
      node[i] = vec2(s);
      imageStore(tree, ivec2(inWidth + base + i, slice), vec4(s, s, 0.0, 0.0));
    } else {
      node[i] = imageLoad(tree, ivec2(inWidth + base + i, slice)).xy;
    }
  }
  int width = inWidth;
  for (int n = block / 2; n >= 1; n /= 2) {
    width /= 2;
    base /= 2;
    for (int i = 0; i < kBlock / 2; ++i) {
      if (i >= n) break;
      node[i] = vec2(min(node[2 * i].x, node[2 * i + 1].x), max(node[2 * i].y, node[2 * i + 1].y));
      imageStore(tree, ivec2(width + base + i, slice), vec4(node[i], 0.0, 0.0));
    }
  }
}
