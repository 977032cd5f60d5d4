#version 450 core
// The splatted bits into level 0 of the ISM: untouched texels (all bits set) become holes (0).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 3, r32ui) uniform readonly uimage2D splats;
layout(binding = 0, r32f) uniform writeonly image2D ism;
void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, imageSize(ism)))) return;
  uint bits = imageLoad(splats, c).r;
  imageStore(ism, c, vec4(bits == 0xffffffffu ? 0.0 : uintBitsToFloat(bits)));
}
