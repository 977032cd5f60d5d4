// The light rays of the VSV grid seen in the shared shadow map (§4.1.3), for both "Voxelize: From
// SM" variants: the ray of a (θ row, φ bin) cell and the α column of its first occluder.
// Include after common.glsl and epipolar.glsl.
layout(binding = VS_UNIT_SHADOW_DEPTH_2D) uniform sampler2D shadowDepth2D;
layout(binding = VS_UNIT_SHADOW_DEPTH_CUBE) uniform samplerCube shadowDepthCube;

// Distance along the light's perspective depth axis stored as window depth.
float linearDepth(float windowDepth) {
  float n = u.shadowParams.x, f = u.shadowParams.y;
  float zNdc = windowDepth * 2.0 - 1.0;
  return 2.0 * f * n / max((f + n) - zNdc * (f - n), 1e-20);
}

// Distance from the light to the first occluder along unit direction w; false when none.
bool occluderDistance(vec3 w, out float t) {
  t = 0.0;
  if (lightType() == LIGHT_POINT) {
    float depth = textureLod(shadowDepthCube, w, 0.0).r;
    if (depth >= 1.0) return false;
    float major = max(abs(w.x), max(abs(w.y), abs(w.z)));
    t = linearDepth(depth) / max(major, 1e-6);
    return true;
  }
  vec4 clip = u.lightViewProj * vec4(u.lightPos.xyz + w, 1.0);
  if (clip.w <= 1e-6) return false;
  vec2 st = clip.xy / clip.w * 0.5 + 0.5;
  if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0)))) return false;
  float depth = textureLod(shadowDepth2D, st, 0.0).r;
  if (depth >= 1.0) return false;
  t = linearDepth(depth) / max(dot(w, u.lightDir.xyz), 1e-6);
  return true;
}

// Directional light: the first occluder on the light ray through p (orthographic shadow map,
// window depth linear along the travel direction); false when none.
bool parallelOccluder(vec3 p, out vec3 hit) {
  hit = p;
  vec4 clip = u.lightViewProj * vec4(p, 1.0);
  vec2 st = clip.xy * 0.5 + 0.5;
  if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0)))) return false;
  float depth = textureLod(shadowDepth2D, st, 0.0).r;
  if (depth >= 1.0) return false;
  float zPerUnit = (u.lightViewProj * vec4(u.lightDir.xyz, 0.0)).z;  // NDC z per unit travelled
  if (abs(zPerUnit) < 1e-20) return false;
  hit = p + u.lightDir.xyz * ((depth * 2.0 - 1.0 - clip.z) / zPerUnit);
  return true;
}

// α column of the first occluder on the light ray of cell (row, bin), at the cell's centre; -1
// when nothing blocks it there or the occluder lies beyond the α range.
int occluderColumn(int row, int bin) {
  float theta = (float(row) + 0.5) / float(nTheta()) * TWO_PI;
  float phi = (float(bin) + 0.5) / float(nPhi()) * phiMax();
  if (parallelLight()) {
    // φ is the light ray's distance from the axis.
    vec3 hit;
    if (parallelOccluder(vsv.eyeAndDistance.xyz + phi * halfPlaneDir(theta), hit))
      return alphaColumn(epipolarCoords(hit).y, alphaMax());
    return -1;
  }
  vec3 w = cos(phi) * -vsv.axis.xyz + sin(phi) * halfPlaneDir(theta);
  float t;
  if (occluderDistance(w, t)) return alphaColumn(epipolarCoords(u.lightPos.xyz + t * w).y, alphaMax());
  return -1;
}
