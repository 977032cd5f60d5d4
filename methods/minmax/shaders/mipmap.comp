#version 450 core
// Mipmap Construction (Chen et al. 2011, §3.3): one pass per level of the 1D min-max mipmaps of all
// rectified rows. The first pass reads the rectified map and also stores the leaves; later passes
// read the previous level from one ping-pong image and write the next into the other. Every level
// is coalesced into one row per slice in Ahnentafel order: node k of the row at x = k (root 1,
// children 2k and 2k+1, leaves d..2d-1).
layout(local_size_x = 64, local_size_y = 1) in;
layout(binding = 10) uniform sampler2D rectified;            // first pass only
layout(rg32f, binding = 1) uniform readonly image2D previous;  // later passes
layout(rg32f, binding = 2) uniform writeonly image2D next;
layout(rg32f, binding = 3) uniform writeonly image2D tree;
layout(location = 0) uniform int levelWidth;  // nodes on the level written by this pass
layout(location = 1) uniform int firstPass;
layout(location = 2) uniform int slices;
void main() {
  ivec2 id = ivec2(gl_GlobalInvocationID.xy);
  if (id.x >= levelWidth || id.y >= slices) return;
  vec2 left, right;
  if (firstPass != 0) {
    float a = texelFetch(rectified, ivec2(2 * id.x, id.y), 0).r;
    float b = texelFetch(rectified, ivec2(2 * id.x + 1, id.y), 0).r;
    left = vec2(a);
    right = vec2(b);
    int d = 2 * levelWidth;
    imageStore(tree, ivec2(d + 2 * id.x, id.y), vec4(left, 0.0, 0.0));
    imageStore(tree, ivec2(d + 2 * id.x + 1, id.y), vec4(right, 0.0, 0.0));
  } else {
    left = imageLoad(previous, ivec2(2 * id.x, id.y)).xy;
    right = imageLoad(previous, ivec2(2 * id.x + 1, id.y)).xy;
  }
  vec2 node = vec2(min(left.x, right.x), max(left.y, right.y));
  imageStore(next, id, vec4(node, 0.0, 0.0));
  imageStore(tree, ivec2(levelWidth + id.x, id.y), vec4(node, 0.0, 0.0));
}
