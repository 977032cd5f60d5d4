#version 450 core
// "Prefix Counts" (ours, beyond the paper): per column, the bits set in the words before each
// word, so that a lookup counts the bits in front with two fetches whatever the slice count.
layout(local_size_x = 8, local_size_y = 8) in;
// Layer-faces (class * targets + target) * faces + face, as the method allocates them.
#if SLICEMAP_CUBE
layout(binding = 0, rgba32ui) readonly uniform uimageCubeArray bits;
layout(binding = 1, rgba16ui) writeonly uniform uimageCubeArray counts;
#else
layout(binding = 0, rgba32ui) readonly uniform uimage2DArray bits;
layout(binding = 1, rgba16ui) writeonly uniform uimage2DArray counts;
#endif
layout(location = 0) uniform int faces;

void main() {
  ivec2 size = imageSize(bits).xy;
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, size))) return;
  int face = int(gl_GlobalInvocationID.z) % faces, cls = int(gl_GlobalInvocationID.z) / faces;
  uint running = 0u;
  for (int k = 0; k < SLICEMAP_TARGETS; ++k) {
    ivec3 at = ivec3(texel, (cls * SLICEMAP_TARGETS + k) * faces + face);
    uvec4 c = uvec4(bitCount(imageLoad(bits, at)));
    uvec4 before = uvec4(running, running + c.x, running + c.x + c.y, running + c.x + c.y + c.z);
    imageStore(counts, at, before);
    running = before.w + c.w;
  }
}
