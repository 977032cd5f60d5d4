// Shared by every shader: frame uniforms, the light, the medium, shadow-map visibility.
// Mirrors vs::FrameUniforms and the bind:: units in harness/frame.hpp.
layout(std140, binding = 0) uniform FrameUniformBlock {
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
} u;

layout(binding = 0) uniform sampler2DShadow shadowMap2D;
layout(binding = 1) uniform samplerCubeShadow shadowMapCube;
layout(binding = 2) uniform sampler2D lightTexture;
layout(binding = 3) uniform sampler2D gPosition;
layout(binding = 4) uniform sampler2D gNormal;
layout(binding = 5) uniform sampler2D gAlbedo;

const float PI = 3.14159265358979323846;
const int LIGHT_POINT = 0;
const int LIGHT_SPOT = 1;
const int LIGHT_DIRECTIONAL = 2;

// Programs built with sceneDefines() (harness/frame.hpp) know the light type, light texture and
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

// L_in(x) without visibility: point/spot I * T * exp(-sigma_t r) / r^2 (spot cone falloff);
// directional E * T, no extinction along light rays.
vec3 lightIncident(vec3 x) {
  int type = lightType();
  if (type == LIGHT_DIRECTIONAL) return u.lightColor.rgb * lightTextureAt(x);
  vec3 d = x - u.lightPos.xyz;
  float r2 = max(dot(d, d), 1e-12);
  float r = sqrt(r2);
  vec3 L = u.lightColor.rgb * (exp(-sigmaT() * r) / r2);
  if (type == LIGHT_SPOT) {
    float c = dot(d / r, u.lightDir.xyz);
    float cosOuter = u.lightDir.w, cosInner = u.lightColor.w;
    L *= clamp((c - cosOuter) / max(cosInner - cosOuter, 1e-6), 0.0, 1.0);
  }
  return L * lightTextureAt(x);
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
  if (lightType() == LIGHT_POINT) {
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

// World size of one shadow-map texel at x (for normal-offset surface lookups).
float shadowTexelWorldSize(vec3 x) {
  float size = max(u.shadowParams.z, 1.0);
  if (lightType() == LIGHT_DIRECTIONAL) return 2.0 * u.cameraClip.w / size;
  float dist = length(x - u.lightPos.xyz);
  float halfTan = lightType() == LIGHT_POINT ? 1.0 : tan(acos(clamp(u.lightDir.w, -1.0, 1.0)));
  return 2.0 * halfTan * dist / size;
}

// Lambert surface radiance at a G-buffer pixel for a given light visibility (0 on sky pixels).
// Direct Lighting uses shadow-map visibility; a method with surface shadows of its own re-shades
// with its visibility through the same function.
vec3 surfaceRadiance(ivec2 pixel, float visibility) {
  vec4 n = texelFetch(gNormal, pixel, 0);
  if (n.w < 0.5) return vec3(0.0);
  vec3 x = texelFetch(gPosition, pixel, 0).xyz;
  vec3 albedo = texelFetch(gAlbedo, pixel, 0).rgb;
  float cosine = max(dot(n.xyz, -lightTravelDir(x)), 0.0);
  return albedo / PI * lightIncident(x) * cosine * visibility;
}

// Shadow-map visibility of the surface at a G-buffer pixel, with a normal offset against acne.
float surfaceShadowVisibility(ivec2 pixel) {
  vec4 n = texelFetch(gNormal, pixel, 0);
  vec3 x = texelFetch(gPosition, pixel, 0).xyz;
  if (n.w < 0.5 || dot(n.xyz, -lightTravelDir(x)) <= 0.0) return 0.0;
  return shadowVisibility(x + n.xyz * 1.5 * shadowTexelWorldSize(x));
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
