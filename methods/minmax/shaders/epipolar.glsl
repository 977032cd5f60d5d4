// Epipolar frame of the min-max method (mirrors vs::minmax::EpipolarUniforms in minmax.cpp and the
// coordinates documented in epipolar.hpp). Include after common.glsl.
layout(std140, binding = 3) uniform EpipolarBlock {
  mat4 invLightViewProj;
  vec4 axis;         // xyz: eye -> light (directional: against the light's travel); w: D (1 directional)
  vec4 basis0;       // xyz: n0; w: alpha of the first slice's lower edge
  vec4 basis1;       // xyz: n1; w: alpha range covered by the slices
  vec4 gammaInfo;    // x: gammaMap (rectified rows), y: gammaAll (prefix tables), z: row length d
  vec4 betaInfo;     // x, y: beta range of the SVD grid; z, w: epipole in window pixels
  vec4 epipoleInfo;  // x: near-epipole radius in pixels (< 0: no epipole), y: ray-march steps, z: 1 = light at the eye
  ivec4 counts;      // slices, rank, prefix resolution, light-texture prefix resolution
  ivec4 flags;       // up_one_level, delay_gamma, textured (light texture or spot cone), unused
} ep;

const float kUnoccluded = 4.0;  // beta beyond pi: the light ray is never blocked
const int kGridSize = 64;
const int kMaxRank = 16;

bool isDirectional() { return lightType() == LIGHT_DIRECTIONAL; }

// n(alpha): the in-slice direction perpendicular to the axis.
vec3 sliceNormal(float alpha) { return cos(alpha) * ep.basis0.xyz + sin(alpha) * ep.basis1.xyz; }
float sliceAlpha(int slice) {
  return ep.basis0.w + (float(slice) + 0.5) * ep.basis1.w / float(ep.counts.x);
}

bool nearEpipole(vec2 fragCoord) {
  if (ep.epipoleInfo.z > 0.5) return true;
  if (ep.epipoleInfo.x < 0.0) return false;
  return distance(fragCoord, ep.betaInfo.zw) < ep.epipoleInfo.x;
}

// The slice nearest to camera ray v, its beta, sin(beta) (accurate near 0 and pi).
void rayCoords(vec3 v, out int slice, out float beta, out float sinBeta) {
  vec3 a = ep.axis.xyz;
  float cosBeta = clamp(dot(v, a), -1.0, 1.0);
  vec3 perp = v - a * cosBeta;
  sinBeta = length(perp);
  beta = atan(sinBeta, cosBeta);
  float alpha = atan(dot(perp, ep.basis1.xyz), dot(perp, ep.basis0.xyz));
  float range = ep.basis1.w;
  float rel = mod(alpha - ep.basis0.w, 2.0 * PI);  // in [0, 2 pi)
  if (rel > range) rel = rel - range < 2.0 * PI - rel ? range : 0.0;  // outside: nearest end
  slice = clamp(int(floor(rel / max(range, 1e-20) * float(ep.counts.x))), 0, ep.counts.x - 1);
}

// gamma of the point at distance dist along a camera ray with this beta.
float gammaAlongRay(float dist, float beta, float sinBeta) {
  if (isDirectional()) return dist * sinBeta;
  return atan(dist * sinBeta, ep.axis.w - dist * cos(beta));
}

// Texture coordinate (0..1) of the SVD grids: Chebyshev in beta, quadratic in gamma.
float betaGridCoord(float beta) {
  float u = (beta - ep.betaInfo.x) / max(ep.betaInfo.y - ep.betaInfo.x, 1e-12);
  float t = acos(clamp(1.0 - 2.0 * u, -1.0, 1.0)) / PI;
  return (t * float(kGridSize - 1) + 0.5) / float(kGridSize);
}
float gammaGridCoord(float gamma) {
  float t = sqrt(clamp(gamma / max(ep.gammaInfo.y, 1e-20), 0.0, 1.0));
  return t;  // 0..1 over the kGridSize nodes
}
