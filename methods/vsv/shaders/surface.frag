#version 450 core
// "Surface Shadows" (Fig. 7): a visible surface point is in shadow when the scanned VSV has the
// bit of its (θ, α, φ) voxel set. The surface voxelizes itself, so the lookup point is moved
// `bias` voxels towards the light (smaller α along the same light ray) and along the normal
// (out of the dilated φ and θ extent of its own voxels), as normal-offset shadow maps do.
#include "common.glsl"
#include "epipolar.glsl"
layout(binding = 10) uniform usampler2DArray voxels;
layout(location = 0) uniform vec2 bias;  // voxels towards the light, along the normal
layout(location = 0) out vec4 outRadiance;

bool inShadowVolume(vec3 world) {
  vec2 p = planeCoords(world - vsv.eyeAndDistance.xyz);
  int bin = phiBin(phiOfPlane(p), phiMax());
  if (bin < 0) return false;  // beyond φ_max: no occluder there
  int col = alphaColumn(alphaOfPlane(p), alphaMax());
  if (col < 0) col = nAlpha() - 1;  // beyond α_max the scanned last column holds every occluder
  uvec4 bits = texelFetch(voxels, ivec3(col, thetaRow(thetaOf(world - vsv.eyeAndDistance.xyz)), bin >> 7), 0);
  return ((bits[(bin >> 5) & 3] >> uint(bin & 31)) & 1u) != 0u;
}

// World size of the voxel around x: the largest of its α, φ and θ extents.
float voxelWorldSize(vec3 x) {
  vec3 offset = x - vsv.eyeAndDistance.xyz;
  vec2 p = planeCoords(offset);
  float alphaSize = length(offset) * alphaMax() / float(nAlpha());
  float phiStep = phiMax() / float(nPhi());
  float phiSize = parallelLight() ? phiStep : length(x - vsv.gridLight.xyz) * phiStep;
  float thetaSize = p.y * TWO_PI / float(nTheta());
  return max(alphaSize, max(phiSize, thetaSize));
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 n = texelFetch(gNormal, pixel, 0);
  vec3 x = texelFetch(gPosition, pixel, 0).xyz;
  float visibility = 0.0;
  if (n.w >= 0.5) {
    vec3 toLight = -lightTravelDir(x);
    if (dot(n.xyz, toLight) > 0.0) {
      vec2 offset = bias * voxelWorldSize(x);
      visibility = inShadowVolume(x + toLight * offset.x + n.xyz * offset.y) ? 0.0 : 1.0;
    }
  }
  vec3 L = surfaceRadiance(pixel, visibility);
  outRadiance = vec4(all(lessThan(abs(L), vec3(3.0e38))) ? L : vec3(0.0), 1.0);
}
