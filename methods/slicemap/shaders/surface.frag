#version 450 core
// "Shading" (Eisemann & Decoret §3.1): L_surf re-shaded with the slicemaps' visibility at each
// visible surface point (the shared shadow map first unless opaque occluders are voxelized),
// looked up one slice and 1e-4 of the depth nearer the light and, on surfaces slanted to the
// light, up to 1.5 slicemap texels along the normal (slope-scaled), off the surface's own cell.
#include "common.glsl"
#include "slicemap.glsl"
layout(location = 0) out vec4 outRadiance;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 n = texelFetch(gNormal, pixel, 0);
  vec3 x = texelFetch(gPosition, pixel, 0).xyz;
  vec3 visibility = vec3(0.0);
  float cosine = dot(n.xyz, -lightTravelDir(x));
  if (n.w > 0.5 && cosine > 0.0) {
    float texel = shadowTexelWorldSize(x) * max(u.shadowParams.z, 1.0) / max(slicemap.params.x, 1.0);
    vec3 offset = x + n.xyz * (1.5 * texel * sqrt(max(1.0 - cosine * cosine, 0.0)));
#if SLICEMAP_OPAQUE_IN_SLICES
    visibility = slicemapTransmittance(offset, 1.0, 1e-4 * abs(slicemapDepth(x)));
#else
    float v = surfaceShadowVisibility(pixel);
    visibility = v > 0.0 ? v * slicemapTransmittance(offset, 1.0, 1e-4 * abs(slicemapDepth(x))) : vec3(0.0);
#endif
  }
  vec3 L = surfaceRadiance(pixel, visibility);
  outRadiance = vec4(all(lessThan(abs(L), vec3(3.0e38))) ? L : vec3(0.0), 1.0);
}
