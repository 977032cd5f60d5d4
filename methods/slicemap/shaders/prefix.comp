#version 450 core
// "Prefix Counts" (ours, beyond the paper): per column, the bits set in the words before each
// word, so that a lookup counts the bits in front with two fetches whatever the slice count.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 10) uniform usampler2DArray bits;
layout(binding = 0, rgba16ui) writeonly uniform uimage2DArray counts;

void main() {
  ivec3 size = textureSize(bits, 0);
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, size.xy))) return;
  int base = int(gl_GlobalInvocationID.z) * SLICEMAP_TARGETS;
  uint running = 0u;
  for (int k = 0; k < SLICEMAP_TARGETS; ++k) {
    uvec4 c = uvec4(bitCount(texelFetch(bits, ivec3(texel, base + k), 0)));
    uvec4 before = uvec4(running, running + c.x, running + c.x + c.y, running + c.x + c.y + c.z);
    imageStore(counts, ivec3(texel, base + k), before);
    running = before.w + c.w;
  }
}
