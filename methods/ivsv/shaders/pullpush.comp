#version 450 core
// ISM hole filling by pull-push (Ritschel et al. 2008, after Grossman and Dally): pull averages the
// valid (non-zero) texels of 2x2 blocks into the next level; push fills the holes of a level from
// the level above. Tiles are powers of two, so no level mixes two VPLs.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, r32f) uniform image2D fine;
layout(binding = 1, r32f) uniform image2D coarse;
layout(location = 0) uniform int push;
void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  if (push == 0) {
    if (any(greaterThanEqual(c, imageSize(coarse)))) return;
    float sum = 0.0, n = 0.0;
    for (int i = 0; i < 4; ++i) {
      float v = imageLoad(fine, 2 * c + ivec2(i & 1, i >> 1)).r;
      if (v > 0.0) {
        sum += v;
        n += 1.0;
      }
    }
    imageStore(coarse, c, vec4(n > 0.0 ? sum / n : 0.0));
  } else {
    if (any(greaterThanEqual(c, imageSize(fine)))) return;
    if (imageLoad(fine, c).r > 0.0) return;
    imageStore(fine, c, vec4(imageLoad(coarse, c / 2).r));
  }
}
