// Shared by every shader: frame uniforms, the light, the medium, shadow-map visibility.
// Mirrors vs::FrameUniforms and the bind:: units in harness/pipeline/frame.hpp.
layout(std140, binding = VS_BLOCK_FRAME) uniform FrameUniformBlock {
  mat4 viewProj;
  mat4 invViewProj;
  mat4 view;
  mat4 proj;
  mat4 lightViewProj;
  mat4 lightView;
  vec4 eye;
  vec4 cameraForward;  // w = tan(fovY / 2)
  vec4 lightPos;       // w = type: 0 point, 1 spot, 2 directional
  vec4 lightDir;       // direction the light travels; w = cos(outer cone)
  vec4 lightColor;     // rgb * intensity; w = cos(inner cone)
  vec4 shadowParams;   // near, far, shadow-map size, has light texture
  vec4 medium;         // sigma_s, sigma_a, sigma_t, g
  vec4 cameraClip;     // near, far, phase (0 isotropic, 1 HG), directional ortho half-extent
  ivec4 viewport;      // width, height, frame index, seed
  vec4 lightEmission;  // x: 1 cosine lobe about lightDir (area lights, virtual point lights); y: two-sided
} u;

layout(binding = VS_UNIT_SHADOW_MAP_2D) uniform sampler2DShadow shadowMap2D;
layout(binding = VS_UNIT_SHADOW_MAP_CUBE) uniform samplerCubeShadow shadowMapCube;
layout(binding = VS_UNIT_LIGHT_TEXTURE) uniform sampler2D lightTexture;
layout(binding = VS_UNIT_G_POSITION) uniform sampler2D gPosition;
layout(binding = VS_UNIT_G_NORMAL) uniform sampler2D gNormal;
layout(binding = VS_UNIT_G_ALBEDO) uniform sampler2D gAlbedo;

layout(binding = VS_UNIT_ALPHA_TEXTURE) uniform sampler2D alphaTexture;  // of the mesh being drawn (frame.hpp, SceneGpu)

const float PI = 3.14159265358979323846;

// Opacity of a surface point from the vertex attribute `alpha` (x texture or -1, y MASK cutoff or
// -1, z opacity) and its texture coordinate: scenes/scene.hpp, Mesh::opacityAt.
float surfaceOpacity(vec3 alpha, vec2 uv) {
  // x and y are -1 or >= 0, the same at every vertex of a mesh but interpolated: compared with -0.5.
  float a = alpha.z * (alpha.x > -0.5 ? textureLod(alphaTexture, uv, 0.0).r : 1.0);
  return alpha.y > -0.5 ? (a < alpha.y ? 0.0 : 1.0) : a;
}
const int LIGHT_POINT = 0;
const int LIGHT_SPOT = 1;
const int LIGHT_DIRECTIONAL = 2;
const int LIGHT_RECT = 3;  // area lights: the shared passes treat them as a cosine-lobed point light
const int LIGHT_DISK = 4;  // at their centre (cube shadow map); methods sample the surface

// Programs built with sceneDefines() (harness/pipeline/frame.hpp) know the light type, light texture and
// phase function at compile time, so the branches below fold away.
#ifdef VS_LIGHT_TYPE
int lightType() { return VS_LIGHT_TYPE; }
#else
int lightType() { return int(u.lightPos.w + 0.5); }
#endif
#ifdef VS_LIGHT_TEXTURE
bool hasLightTexture() { return VS_LIGHT_TEXTURE != 0; }
#else
bool hasLightTexture() { return u.shadowParams.w > 0.5; }
#endif
#ifdef VS_HG_PHASE
bool hgPhase() { return VS_HG_PHASE != 0; }
#else
bool hgPhase() { return u.cameraClip.z > 0.5; }
#endif
float sigmaS() { return u.medium.x; }
// Point lights and area lights use the cube shadow map around u.lightPos.
bool omniLight() { return lightType() == LIGHT_POINT || lightType() >= LIGHT_RECT; }
// Cosine emission of an area light (or one of its virtual point lights) towards direction d (unit,
// from the light): one-sided unless u.lightEmission.y (two-sided) is set.
float areaEmission(vec3 d) {
  float c = dot(d, u.lightDir.xyz);
  return u.lightEmission.y > 0.5 ? abs(c) : max(c, 0.0);
}
#ifdef VS_COSINE_LOBE
bool cosineLobe() { return VS_COSINE_LOBE != 0; }
#else
bool cosineLobe() { return u.lightEmission.x > 0.5; }
#endif
float sigmaT() { return u.medium.z; }

// Phase function of the angle between the light's travel direction and the direction to the eye.
float phase(float cosTheta) {
  if (!hgPhase()) return 1.0 / (4.0 * PI);
  float g = u.medium.w;
  float denom = max(1.0 + g * g - 2.0 * g * clamp(cosTheta, -1.0, 1.0), 1e-12);
  return (1.0 - g * g) / (4.0 * PI * denom * sqrt(denom));
}

// Direction in which light travels at x (unit).
vec3 lightTravelDir(vec3 x) {
  if (lightType() == LIGHT_DIRECTIONAL) return u.lightDir.xyz;
  vec3 d = x - u.lightPos.xyz;
  float len = length(d);
  return len > 1e-20 ? d / len : u.lightDir.xyz;
}

vec3 lightTextureAt(vec3 x) {
  if (!hasLightTexture()) return vec3(1.0);
  vec2 st;
  if (lightType() == LIGHT_POINT) {  // latitude-longitude around the light; v = 0 at +Y
    vec3 d = lightTravelDir(x);
    st = vec2(atan(d.z, d.x) / (2.0 * PI) + 0.5, acos(clamp(d.y, -1.0, 1.0)) / PI);
  } else {
    vec4 p = u.lightViewProj * vec4(x, 1.0);
    if (p.w <= 1e-20) return vec3(0.0);
    st = p.xy / p.w * 0.5 + 0.5;
    if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0)))) return vec3(0.0);
    st.y = 1.0 - st.y;  // texture row 0 is the top
  }
  return textureLod(lightTexture, st, 0.0).rgb;
}

// What a point or spot light sends towards x, before distance falloff and extinction: its colour,
// cosine lobe, spot cone and light texture. l: unit direction from the light to x.
vec3 lightEmitted(vec3 x, vec3 l) {
  vec3 L = u.lightColor.rgb;
  if (cosineLobe()) L *= areaEmission(l);
  if (lightType() == LIGHT_SPOT) {
    float c = dot(l, u.lightDir.xyz);
    float cosOuter = u.lightDir.w, cosInner = u.lightColor.w;
    L *= clamp((c - cosOuter) / max(cosInner - cosOuter, 1e-6), 0.0, 1.0);
  }
  return L * lightTextureAt(x);
}

// L_in(x) without visibility: point/spot I * T * exp(-sigma_t r) / r^2 (spot cone falloff);
// directional E * T, no extinction along light rays.
vec3 lightIncident(vec3 x) {
  if (lightType() == LIGHT_DIRECTIONAL) return u.lightColor.rgb * lightTextureAt(x);
  vec3 d = x - u.lightPos.xyz;
  float r2 = max(dot(d, d), 1e-12);
  float r = sqrt(r2);
  return lightEmitted(x, d / r) * (exp(-sigmaT() * r) / r2);
}

// Depth that the cube face looking along the major axis of d stores for a point at offset d.
float cubeFaceDepth(vec3 d) {
  float m = max(abs(d.x), max(abs(d.y), abs(d.z)));
  float n = u.shadowParams.x, f = u.shadowParams.y;
  float zNdc = (f + n) / max(f - n, 1e-20) - 2.0 * f * n / max((f - n) * m, 1e-20);
  return clamp(zNdc * 0.5 + 0.5, 0.0, 1.0);
}

// Shadow-map visibility of x from the light (hardware 2x2 PCF), 1 outside the map.
float shadowVisibility(vec3 x) {
  if (omniLight()) {
    vec3 d = x - u.lightPos.xyz;
    if (dot(d, d) < 1e-24) return 1.0;
    return texture(shadowMapCube, vec4(d, cubeFaceDepth(d)));
  }
  vec4 p = u.lightViewProj * vec4(x, 1.0);
  if (p.w <= 1e-20) return 1.0;  // behind a spot light: its cone gives zero anyway
  vec3 ndc = p.xyz / p.w;
  vec2 st = ndc.xy * 0.5 + 0.5;
  if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0)))) return 1.0;
  return texture(shadowMap2D, vec3(st, clamp(ndc.z * 0.5 + 0.5, 0.0, 1.0)));
}

// ---- semi-transparent occluders (VS_TRANSLUCENT, from sceneDefines)
#ifndef VS_TRANSLUCENT
#define VS_TRANSLUCENT 0
#endif
#if VS_TRANSLUCENT
layout(std140, binding = VS_BLOCK_TRANSMITTANCE) uniform TransmittanceBlock {
  mat4 faceViewProj[6];
  vec4 params;  // size, faces, light type, longest list
} tm;
layout(binding = VS_IMAGE_TRANSMITTANCE_HEADS, r32ui) readonly uniform uimage2DArray transmittanceHeads;
struct TransmittanceNode {
  vec4 data;   // rgb transmittance of the crossing, w distance from the light
  uvec4 link;  // x next node
};
layout(std430, binding = VS_STORAGE_TRANSMITTANCE_NODES) readonly buffer TransmittanceNodes { TransmittanceNode transmittanceNodes[]; };

// Transmittance of every semi-transparent crossing between the light and x (1 without any), read
// from x's light texel: the product over the crossings nearer the light than x by more than `bias`.
vec3 translucentTransmittance(vec3 x, float bias) {
  // One exit and no break: this runs inside the methods' sample loops (see raymarch.frag).
  int face = 0;
  if (tm.params.y > 1.5) {  // cube faces +x, -x, +y, -y, +z, -z
    vec3 d = x - u.lightPos.xyz;
    vec3 a = abs(d);
    int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    face = 2 * axis + (d[axis] < 0.0 ? 1 : 0);
  }
  vec4 p = tm.faceViewProj[face] * vec4(x, 1.0);
  vec2 st = p.xy / max(p.w, 1e-20) * 0.5 + 0.5;
  bool inside = p.w > 1e-20 && all(greaterThanEqual(st, vec2(0.0))) && all(lessThan(st, vec2(1.0)));
  ivec2 texel = clamp(ivec2(st * tm.params.x), ivec2(0), ivec2(int(tm.params.x) - 1));
  float dist = lightType() == LIGHT_DIRECTIONAL ? dot(x, u.lightDir.xyz) : length(x - u.lightPos.xyz);
  vec3 T = vec3(1.0);
  uint node = inside ? imageLoad(transmittanceHeads, ivec3(texel, face)).r : 0xFFFFFFFFu;
  // A trip count the same for every invocation (the longest list): a loop whose exit depends on
  // per-invocation data, nested in the callers' sample loops, ended those loops early for some
  // invocations on llvmpipe (Mesa 22.3).
  int longest = int(tm.params.w);
  for (int k = 0; k < longest; ++k) {
    if (node != 0xFFFFFFFFu) {
      vec4 crossing = transmittanceNodes[node].data;
      node = transmittanceNodes[node].link.x;
      T *= crossing.w < dist - bias ? crossing.rgb : vec3(1.0);
    }
  }
  return T;
}
#endif

// World size of one shadow-map texel at x (for normal-offset surface lookups).
float shadowTexelWorldSize(vec3 x) {
  float size = max(u.shadowParams.z, 1.0);
  if (lightType() == LIGHT_DIRECTIONAL) return 2.0 * u.cameraClip.w / size;
  float dist = length(x - u.lightPos.xyz);
  float halfTan = omniLight() ? 1.0 : tan(acos(clamp(u.lightDir.w, -1.0, 1.0)));
  return 2.0 * halfTan * dist / size;
}

// Visibility of the light from x in the medium, per channel: the shadow map times the
// transmittance of semi-transparent occluders (volume data is marched by the methods).
vec3 lightVisibility(vec3 x) {
  vec3 v = vec3(shadowVisibility(x));
#if VS_TRANSLUCENT
  float scale = lightType() == LIGHT_DIRECTIONAL ? length(x) : length(x - u.lightPos.xyz);
  v *= translucentTransmittance(x, 1e-4 * scale + 1e-5);
#endif
  return v;
}

// Lambert surface radiance at a G-buffer pixel for a given light visibility (0 on sky pixels).
// Direct Lighting uses shadow-map visibility; a method with surface shadows of its own re-shades
// with its visibility through the same function.
vec3 surfaceRadiance(ivec2 pixel, vec3 visibility) {
  vec4 n = texelFetch(gNormal, pixel, 0);
  if (n.w < 0.5) return vec3(0.0);
  vec3 x = texelFetch(gPosition, pixel, 0).xyz;
  vec3 albedo = texelFetch(gAlbedo, pixel, 0).rgb;
  float cosine = max(dot(n.xyz, -lightTravelDir(x)), 0.0);
  return albedo / PI * lightIncident(x) * cosine * visibility;
}

vec3 surfaceRadiance(ivec2 pixel, float visibility) { return surfaceRadiance(pixel, vec3(visibility)); }

// Shadow-map visibility of the surface at a G-buffer pixel, with a normal offset against acne.
float surfaceShadowVisibility(ivec2 pixel) {
  vec4 n = texelFetch(gNormal, pixel, 0);
  vec3 x = texelFetch(gPosition, pixel, 0).xyz;
  if (n.w < 0.5 || dot(n.xyz, -lightTravelDir(x)) <= 0.0) return 0.0;
  return shadowVisibility(x + n.xyz * 1.5 * shadowTexelWorldSize(x));
}

// The same, times the transmittance of semi-transparent occluders in front of the surface (its
// own crossing excluded by a bias of two light texels).
vec3 surfaceLightVisibility(ivec2 pixel) {
  float v = surfaceShadowVisibility(pixel);
#if VS_TRANSLUCENT
  if (v > 0.0) {
    vec3 x = texelFetch(gPosition, pixel, 0).xyz;
    float scale = lightType() == LIGHT_DIRECTIONAL ? length(x) : length(x - u.lightPos.xyz);
    return v * translucentTransmittance(x, 2.0 * shadowTexelWorldSize(x) + 1e-4 * scale);
  }
#endif
  return vec3(v);
}

// Camera ray through a pixel of the G-buffer: unit direction and distance to the first hit
// (or to the far plane when nothing is hit).
void cameraRay(ivec2 pixel, out vec3 dir, out float dist) {
  vec4 p = texelFetch(gPosition, pixel, 0);
  vec3 d = p.xyz - u.eye.xyz;
  float len = length(d);
  dir = len > 1e-20 ? d / len : u.cameraForward.xyz;
  dist = max(p.w, 0.0);
}

// ---- volume data (VS_VOLUMES = number of volumes, from sceneDefines)
#ifndef VS_VOLUMES
#define VS_VOLUMES 0
#endif
#if VS_VOLUMES > 0
layout(std140, binding = VS_BLOCK_VOLUMES) uniform VolumeBlock {
  ivec4 count;
  vec4 boxLo[4];
  vec4 boxHi[4];
  vec4 coeff[4];       // mean sigma_s, mean sigma_t per unit density (times density_scale), max density, smallest voxel side
  vec4 scattering[4];  // rgb sigma_s per unit density (times density_scale)
  vec4 extinction[4];  // rgb sigma_t per unit density (times density_scale)
} vol;
layout(binding = VS_UNIT_VOLUME_DENSITY0) uniform sampler3D volumeDensity[4];

// Density of volume i at x: trilinear between voxel centres, 0 outside its box.
float volumeDensityAt(int i, vec3 x) {
  vec3 f = (x - vol.boxLo[i].xyz) / max(vol.boxHi[i].xyz - vol.boxLo[i].xyz, vec3(1e-30));
  if (any(lessThan(f, vec3(0.0))) || any(greaterThan(f, vec3(1.0)))) return 0.0;
  return textureLod(volumeDensity[i], f, 0.0).r;
}

// rgb sigma_s and sigma_t of all volumes at x.
void volumeCoefficients(vec3 x, out vec3 scattering, out vec3 extinction) {
  scattering = extinction = vec3(0.0);
  for (int i = 0; i < VS_VOLUMES; ++i) {
    float d = volumeDensityAt(i, x);
    scattering += d * vol.scattering[i].rgb;
    extinction += d * vol.extinction[i].rgb;
  }
}
vec3 volumeExtinction(vec3 x) {
  vec3 scattering, extinction;
  volumeCoefficients(x, scattering, extinction);
  return extinction;
}
// sigma_t averaged over the colour channels (each volume's mean) at x.
float volumeMeanExtinction(vec3 x) {
  float extinction = 0.0;
  for (int i = 0; i < VS_VOLUMES; ++i) extinction += volumeDensityAt(i, x) * vol.coeff[i].y;
  return extinction;
}

// Ray parameters [t0, t1] of the segment of a + t (b - a), t in [0, 1], inside volume i's box
// (t0 >= t1 when it misses).
vec2 volumeSegment(int i, vec3 a, vec3 b) {
  vec3 d = b - a;
  vec3 inv = 1.0 / mix(d, vec3(1e-30), lessThan(abs(d), vec3(1e-30)));
  vec3 tLo = (vol.boxLo[i].xyz - a) * inv, tHi = (vol.boxHi[i].xyz - a) * inv;
  vec3 tMin = min(tLo, tHi), tMax = max(tLo, tHi);
  return vec2(max(max(tMin.x, tMin.y), max(tMin.z, 0.0)), min(min(tMax.x, tMax.y), min(tMax.z, 1.0)));
}

// Optical depth of the volumes between a and b: midpoint rule over each box's segment with
// `stepsPerVoxel` steps per smallest voxel side (at most maxSteps per volume). `offset` in [0, 1)
// shifts the midpoints (jitter).
vec3 volumeOpticalDepth(vec3 a, vec3 b, float stepsPerVoxel, int maxSteps, float offset) {
  vec3 depth = vec3(0.0);
  float len = length(b - a);
  for (int i = 0; i < VS_VOLUMES; ++i) {
    vec2 seg = volumeSegment(i, a, b);
    float inside = max(seg.y - seg.x, 0.0) * len;
    // maxSteps 0 skips the march (callers use it so that lanes with nothing to do add no iterations).
    int n = inside > 0.0 && vol.coeff[i].z > 0.0
                ? min(max(int(ceil(min(inside * stepsPerVoxel / max(vol.coeff[i].w, 1e-30), 1e6))), 1), maxSteps)
                : 0;
    float dt = (seg.y - seg.x) / float(max(n, 1));
    float sum = 0.0;
    for (int k = 0; k < n; ++k) sum += volumeDensityAt(i, mix(a, b, seg.x + (float(k) + offset) * dt));
    depth += sum * dt * len * vol.extinction[i].rgb;
  }
  return depth;
}

// Transmittance of the volumes from x towards the light (to the light's position, or out of every
// box along the light's direction for directional lights).
vec3 volumeLightTransmittance(vec3 x, float stepsPerVoxel, int maxSteps, float offset) {
  vec3 target;
  if (lightType() == LIGHT_DIRECTIONAL) {
    float reach = 0.0;
    for (int i = 0; i < VS_VOLUMES; ++i)
      reach = max(reach, length(max(abs(x - vol.boxLo[i].xyz), abs(x - vol.boxHi[i].xyz))));
    target = x - u.lightDir.xyz * (reach * 1.001 + 1e-3);
  } else {
    target = u.lightPos.xyz;
  }
  return exp(-volumeOpticalDepth(x, target, stepsPerVoxel, maxSteps, offset));
}
#endif

// Deterministic hash -> [0, 1) (PCG).
uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
float random01(uvec4 key) {
  uint h = pcgHash(key.x ^ pcgHash(key.y ^ pcgHash(key.z ^ pcgHash(key.w))));
  return float(h >> 8) * (1.0 / 16777216.0);
}
