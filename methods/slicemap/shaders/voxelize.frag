#version 450 core
// "Slicemap" (Eisemann & Decoret §2): each fragment of a colour class sets the bit of its slice in
// its light texel's column; the framebuffer ORs the one-hot words in (glLogicOp(GL_OR)), 128 slices
// per RGBA32UI target. With NEAR_FAR_PASS: "Near/Far Maps" for local slicing, each column's
// nearest and farthest fragment (MIN blending of d and -d).
#include "common.glsl"
#include "slicemap.glsl"
in vec3 vPosition;
in vec3 vColor;
in vec2 vUv;
in vec3 vAlpha;
layout(location = 4) uniform int voxelClass;  // the class this draw voxelizes
layout(location = 6) uniform int opaqueDraw;  // 1 while the class's opaque meshes draw
#ifdef NEAR_FAR_PASS
layout(location = 0) out vec2 outNearFar;
#else
layout(location = 0) out uvec4 outBits[SLICEMAP_TARGETS];
#endif

void main() {
  if (opaqueDraw == 0) {
    // Semi-transparent meshes all draw; each fragment keeps to the class of its transmittance.
    float o = surfaceOpacity(vAlpha, vUv);
    if (o <= 0.0) discard;
    vec4 bin = slicemap.classBin[voxelClass];
    bool perTexel = vAlpha.x > -0.5 && vAlpha.y < -0.5;  // alpha-textured BLEND: opacity bins
    if (perTexel) {
      // The bin of this opacity (none below the minimum), and the class's tint.
      float span = max(1.0 - bin.z, 1e-6);
      int b = o < bin.z ? -1 : clamp(int((o - bin.z) / span * bin.y), 0, int(bin.y) - 1);
      if (bin.x < 0.0 || b != int(bin.x) || any(greaterThanEqual(abs(vColor - slicemap.classTint[voxelClass].rgb), vec3(1e-3))))
        discard;
    } else {
      vec3 crossing = vec3(1.0) - o * (vec3(1.0) - vColor);
      vec3 t = slicemap.classTransmittance[voxelClass].rgb;
      if (bin.x >= 0.0 || any(greaterThanEqual(abs(crossing - t), vec3(1e-3)))) discard;
    }
  }
  float depth = slicemapDepth(vPosition);
#ifdef NEAR_FAR_PASS
  outNearFar = vec2(depth, -depth);
#else
  // The column of this fragment (local slicing reads its near/far map there).
  float coord = sliceCoordinate(slicemapColumn(vPosition), voxelClass, depth);
  int slice = clamp(int(clamp(coord, 0.0, slicemap.params.z - 1.0)), 0, int(slicemap.params.z) - 1);
  // Packed classes: class c owns words c * SLICEMAP_CLASS_WORDS onwards of the shared targets.
  int word = (SLICEMAP_PACKED != 0 ? voxelClass * SLICEMAP_CLASS_WORDS : 0) + (slice >> 5);
  int target = word >> 2;
  uvec4 oneHot = uvec4(0u);
  oneHot[word & 3] = 1u << uint(slice & 31);
  for (int k = 0; k < SLICEMAP_TARGETS; ++k) outBits[k] = k == target ? oneHot : uvec4(0u);
#endif
}
